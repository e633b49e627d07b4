#include "rove/slam/rgbd_slam_run.h"

#include <fmt/format.h>

#include <algorithm>

#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/io/any_rawlog.h"
#include "rove/vision/range_image_frame.h"
#include "rove/vision/rgbd_frame.h"

namespace rove {
namespace {

void add_count_issues(const RgbdSlam& slam, const RgbdSequence& sequence, RgbdSlamRunResult& r) {
  const RgbdSlamStats& st = slam.stats();
  if (st.lost > 0) {
    r.issues.push_back({"lost-tracking",
                        fmt::format("{} of {} frames could not be tracked (kept at the predicted "
                                    "pose); {} keyframes joined by the prediction only",
                                    st.lost, st.frames, st.weak_edges)});
  }
  if (st.no_features > 0) {
    r.issues.push_back({"no-features", fmt::format("{} of {} frames had too few features with depth "
                                                   "(textureless, dark or blurred) and were skipped",
                                                   st.no_features, st.frames)});
  }
  if (sequence.unassociated_color > 0) {
    r.issues.push_back({"unassociated-images",
                        fmt::format("{} color images have no depth image within the association's "
                                    "time difference and were left out",
                                    sequence.unassociated_color)});
  }
  if (const auto& b = slam.bundle_adjustment(); b && !b->ok()) {
    r.issues.push_back({"not-converged", std::string("the bundle adjustment stopped") +
                                             (b->improved() ? "" : " and was not applied") + ": " + b->message});
  }
  if (r.final_optimization && !r.final_optimization->ok()) {
    r.issues.push_back({"not-converged", "the final pose-graph optimization stopped: " +
                                             r.final_optimization->message});
  }
}

// The frames of a rawlog sequence, read in order in one pass.
class RawlogFrames {
 public:
  explicit RawlogFrames(const RgbdSequence& s) : sequence_(s), reader_(s.folder) {}

  RgbdFrame frame(const RgbdSequenceFrame& f) {
    while (!current_ || entry_ < f.rawlog_entry) {
      if (current_) ++entry_;
      current_ = reader_.next();
      if (!current_) break;
    }
    std::vector<std::shared_ptr<const RangeImage3D>> scans;
    if (current_ && entry_ == f.rawlog_entry) scans = range_images_of(*current_);
    if (f.rawlog_scan >= scans.size()) {
      throw ParseError({sequence_.folder, std::nullopt, std::nullopt, "CObservation3DRangeScan"},
                       fmt::format("entry {}: the 3D range scan listed before is not there (the file changed "
                                   "while it was read)",
                                   f.rawlog_entry));
    }
    return rgbd_frame_from_range_image(*scans[f.rawlog_scan]);
  }

 private:
  const RgbdSequence& sequence_;
  AnyRawlogReader reader_;
  std::optional<RawlogEntry> current_;
  std::uint64_t entry_ = 0;
};

}  // namespace

RgbdSlamOptions for_sequence(RgbdSlamOptions options, const RgbdSequence& sequence) {
  if (!options.rolling_shutter_readout) options.rolling_shutter_readout = sequence.rolling_shutter_readout;
  return options;
}

std::vector<StampedPose3> rgbd_trajectory(const RgbdSlam& slam) {
  std::vector<StampedPose3> out;
  out.reserve(slam.num_frames());
  for (std::size_t i = 0; i < slam.num_frames(); ++i) out.push_back({slam.frame_time(i), slam.frame_pose(i)});
  return out;
}

RgbdSlamRunResult run_rgbd_slam(RgbdSlam& slam, const RgbdSequence& sequence,
                                const RgbdSlamRunOptions& options) {
  RgbdSlamRunResult r;
  const std::size_t n = std::min(sequence.frames.size(), options.max_frames.value_or(sequence.frames.size()));
  Stopwatch sw;
  std::optional<RawlogFrames> rawlog;
  if (sequence.format == RgbdSequenceFormat::Rawlog) rawlog.emplace(sequence);
  for (std::size_t i = 0; i < n; ++i) {
    throw_if_interrupted();
    const RgbdSequenceFrame& f = sequence.frames[i];
    sw.reset();
    const RgbdFrame frame =
        rawlog ? rawlog->frame(f) : read_rgbd_frame(f.color_path, f.depth_path, sequence.depth_scale);
    r.read_seconds += sw.lap();
    const RgbdFrameUpdate u = slam.process(frame, f.time);
    r.processing_seconds += sw.lap();
    ++r.frames;
    if (options.on_frame) options.on_frame(u);
  }
  if (n > 0) {
    r.first_time = sequence.frames.front().time;
    r.last_time = sequence.frames[n - 1].time;
  }
  sw.reset();
  r.final_optimization = slam.finish();
  r.processing_seconds += sw.elapsed();
  if (!sequence.reference.empty() && r.frames > 0) {
    try {
      r.ate = absolute_trajectory_error(sequence.reference, rgbd_trajectory(slam), options.ate);
    } catch (const InvalidArgument& e) {
      r.ate_problem = e.what();
      r.issues.push_back({"no-evaluation", "the reference " + sequence.reference_path +
                                               " has no pose at the frames' times"});
    }
  }
  add_count_issues(slam, sequence, r);
  return r;
}

}  // namespace rove
