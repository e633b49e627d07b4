// The output folder of rove rgbd-slam: the coloured map (map.ply), the
// occupancy octree (map.bt, its occupied voxels), the camera trajectory (trajectory.tum), the keyframes with their frames
// (keyframes.tum), the pose graph with its loop closures (graph.g2o) and
// the loop-closure attempts (loops.csv). Its world frame is the first
// keyframe's optical frame (x right, y down, z forward): the scene is
// shown with −y up.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <filesystem>
#include <map>
#include <string_view>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/tum_trajectory.h"
#include "scene_inputs.h"

namespace rove::detail {

namespace fs = std::filesystem;

namespace {

// Keyframes drawn with their coordinate frame, at most (evenly spread).
constexpr std::size_t kMaxKeyframeFrames = 400;

struct LoopChecks {
  std::size_t checked = 0;
  std::size_t accepted = 0;
  std::map<std::string, std::size_t> accepted_by_kind;  // appearance, nearby, proximity, random
};

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = line.find(',', at);
    out.push_back(line.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at));
    if (comma == std::string_view::npos) return out;
    at = comma + 1;
  }
}

// loops.csv: a header naming the columns (keyframe, candidate, kind and
// accepted among them), then one loop-closure attempt a line; keyframe and
// candidate index the keyframes of keyframes.tum.
LoopChecks read_loop_checks(const std::string& path, std::size_t keyframes) {
  const std::string text = read_input_file(path, std::uint64_t{1} << 30, "loops");
  constexpr std::array<std::string_view, 4> kColumns = {"keyframe", "candidate", "kind", "accepted"};
  std::array<std::size_t, 4> column{};
  std::size_t needed = 0, line = 0, at = 0;
  LoopChecks out;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    std::string_view l(text.data() + at, end - at);
    at = end + 1;
    ++line;
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    const std::vector<std::string_view> f = split_fields(l);
    if (line == 1) {
      for (std::size_t k = 0; k < kColumns.size(); ++k) {
        const auto it = std::find(f.begin(), f.end(), kColumns[k]);
        if (it == f.end()) {
          throw ParseError({printable(path), 1, std::nullopt, "header"},
                           fmt::format("not a loops.csv of rove rgbd-slam: the header has no column '{}' (it needs "
                                       "keyframe, candidate, kind and accepted)",
                                       kColumns[k]));
        }
        column[k] = static_cast<std::size_t>(it - f.begin());
      }
      needed = *std::max_element(column.begin(), column.end()) + 1;
      continue;
    }
    if (l.find_first_not_of(" \t") == std::string_view::npos) continue;
    if (f.size() < needed) {
      throw ParseError({printable(path), line, std::nullopt, "fields"},
                       fmt::format("{} fields, expected at least {}", f.size(), needed));
    }
    const auto index = [&](std::size_t k) {
      const std::string_view s = f[column[k]];
      std::size_t v = 0;
      const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
      if (r.ec != std::errc() || r.ptr != s.data() + s.size() || s.empty()) {
        throw ParseError({printable(path), line, std::nullopt, std::string(kColumns[k])},
                         fmt::format("'{}' is not a keyframe index", printable(s)));
      }
      if (v >= keyframes) {
        throw ParseError({printable(path), line, std::nullopt, std::string(kColumns[k])},
                         fmt::format("keyframe {} does not exist (keyframes.tum has {})", v, keyframes));
      }
      return v;
    };
    index(0);
    index(1);
    const std::string_view accepted = f[column[3]];
    if (accepted != "0" && accepted != "1") {
      throw ParseError({printable(path), line, std::nullopt, "accepted"},
                       fmt::format("'{}' is not 0 or 1", printable(accepted)));
    }
    ++out.checked;
    if (accepted == "1") {
      ++out.accepted;
      ++out.accepted_by_kind[printable(f[column[2]])];
    }
  }
  if (line == 0) throw ParseError({printable(path), std::nullopt, std::nullopt, "header"}, "the file is empty");
  return out;
}

}  // namespace

std::string add_rgbd_slam_folder(Scene& scene, const std::string& path, const SceneLoadOptions& o,
                                 SceneLoadReport& report) {
  const fs::path dir(path);
  std::error_code ec;
  const auto exists = [&](const char* name) { return fs::is_regular_file(dir / name, ec); };
  // The first input decides which way is up.
  if (scene.layers.empty()) scene.up = SceneUp::MinusY;
  std::vector<std::string> parts;
  if (exists("map.ply")) parts.push_back("map " + add_cloud_file(scene, (dir / "map.ply").string(), false, o, report));
  if (exists("map.bt")) {  // hidden at first: its voxels would cover the coloured cloud
    parts.push_back("octree " + add_octree_file(scene, (dir / "map.bt").string()) + " (hidden at first)");
    scene.layers.back().shown = false;
  }
  if (exists("graph.g2o")) parts.push_back("graph " + add_graph_file(scene, (dir / "graph.g2o").string()));

  TrajectoryLayerOptions to;
  to.frames = 0;  // the keyframes carry the frames
  parts.push_back(add_trajectory_file(scene, (dir / "trajectory.tum").string(), false, to) + " (trajectory.tum)");
  const Eigen::Vector3d start = scene.layers.back().positions.front().cast<double>();

  const std::string kf_path = (dir / "keyframes.tum").string();
  const std::vector<StampedPose3> keyframes = read_tum_trajectory(kf_path);
  if (keyframes.empty()) throw ParseError({printable(kf_path), std::nullopt, std::nullopt, "poses"}, "no keyframe");
  TrajectoryLayerOptions ko;
  ko.kind = LayerKind::Path;
  ko.color = {90, 200, 255, 255};
  ko.frames = kMaxKeyframeFrames;
  add_trajectory(scene, keyframes, "keyframes.tum", ko);
  parts.push_back(fmt::format("{} keyframes{}", keyframes.size(),
                              keyframes.size() > kMaxKeyframeFrames
                                  ? fmt::format(" ({} with their frame)", kMaxKeyframeFrames)
                                  : std::string()));

  if (exists("loops.csv")) {
    const LoopChecks loops = read_loop_checks((dir / "loops.csv").string(), keyframes.size());
    std::string kinds;
    for (const auto& [kind, n] : loops.accepted_by_kind) kinds += fmt::format("{}{} {}", kinds.empty() ? "" : ", ", kind, n);
    parts.push_back(fmt::format("loops.csv: {} of {} loop checks accepted{}", loops.accepted, loops.checked,
                                kinds.empty() ? std::string() : " (" + kinds + ")"));
  }
  add_label(scene, start, "start");
  std::string what;
  for (const auto& p : parts) what += (what.empty() ? "" : "; ") + p;
  return what;
}

}  // namespace rove::detail
