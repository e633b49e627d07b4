#pragma once
/// \file
/// Runs the RGB-D SLAM pipeline (rove/slam/rgbd_slam.h) over a sequence
/// folder or rawlog (rove/slam/rgbd_sequence.h): reads each frame's images
/// (a rawlog's scans in one pass, registered by
/// rove/vision/range_image_frame.h), processes
/// them, finishes the pose graph, and evaluates the trajectory against the
/// folder's reference (ATE, Sturm et al. IROS 2012) when it has one.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rove/slam/rgbd_sequence.h"
#include "rove/slam/rgbd_slam.h"
#include "rove/slam/trajectory_eval.h"

namespace rove {

/// Options of run_rgbd_slam.
struct RgbdSlamRunOptions {
  /// Process at most this many frames (from the first).
  std::optional<std::size_t> max_frames;
  /// Called after each frame (progress reports).
  std::function<void(const RgbdFrameUpdate&)> on_frame;
  /// Pairing of the estimate with the reference for the ATE: default
  /// largest time difference 0.02 s (TUM's evaluate_ate.py); SE(3)
  /// alignment.
  AteOptions ate{{0.02, 0.0}, TrajectoryAlignment::SE3};
};

/// Something the user must know about a run whose outputs are still written.
struct RgbdSlamRunIssue {
  std::string code;     ///< "lost-tracking", "no-features", "not-converged", ...
  std::string message;  ///< one line
};

/// What run_rgbd_slam did.
struct RgbdSlamRunResult {
  std::size_t frames = 0;          ///< frames processed
  double read_seconds = 0.0;       ///< reading and decoding the images
  double processing_seconds = 0.0; ///< RgbdSlam::process and finish
  double first_time = 0.0, last_time = 0.0;  ///< the frames' times, seconds
  /// The final optimization (after the last frame), if the graph has loops.
  std::optional<GraphOptimizerResult> final_optimization;
  /// Against the sequence's reference, when it has one and poses associate.
  std::optional<AteResult> ate;
  /// Why there is no ATE although a reference exists (no pose associated).
  std::string ate_problem;
  std::vector<RgbdSlamRunIssue> issues;
};

/// Processes the frames of `sequence` with `slam` (whose camera should be
/// the sequence's). Image files that cannot be read are errors naming the
/// file (rove/vision/rgbd_frame.h), and so are rawlog entries (naming the
/// file and the entry). Issues: frames lost or without features,
/// a final optimization that did not converge, color images left without
/// depth by the association. Throws rove::Interrupted on Ctrl-C (the
/// command line's handler).
RgbdSlamRunResult run_rgbd_slam(RgbdSlam& slam, const RgbdSequence& sequence,
                                const RgbdSlamRunOptions& options = {});

/// `options` with what it leaves to the sequence filled from it: the
/// rolling shutter's readout, when unset, from the sequence's camera.
RgbdSlamOptions for_sequence(RgbdSlamOptions options, const RgbdSequence& sequence);

/// The trajectory of every processed frame (T_world_camera at its time).
std::vector<StampedPose3> rgbd_trajectory(const RgbdSlam& slam);

}  // namespace rove
