// Inputs made of several records: rawlogs (scans along the odometry path),
// the particle and step files of rove pf-localization, and the output
// folders of rove's commands.

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/io/any_rawlog.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/poses/lie_conversion.h"
#include "scene_inputs.h"

namespace rove::detail {

namespace fs = std::filesystem;

namespace {

SE3d planar(const SE2d& T) {
  return SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(T.angle(), Eigen::Vector3d::UnitZ())),
              Eigen::Vector3d(T.translation().x(), T.translation().y(), 0.0));
}

// The numbers of each line of a text file (blank and comment lines left
// out), with the line number.
struct Row {
  std::size_t line = 0;
  std::vector<double> values;
};

std::vector<Row> read_rows(const std::string& path, std::size_t min_fields, const char* what) {
  const std::string text = read_input_file(path, std::uint64_t{1} << 30, what);
  std::vector<Row> rows;
  std::size_t line = 0, at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view l(text.data() + at, end - at);
    at = end + 1;
    ++line;
    const std::size_t first = l.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || l[first] == '#' || l[first] == '%') continue;
    Row r;
    r.line = line;
    std::size_t p = first;
    while (p < l.size()) {
      const std::size_t q = std::min(l.find_first_of(" \t\r", p), l.size());
      double v = 0.0;
      const auto res = std::from_chars(l.data() + p, l.data() + q, v);
      if (res.ec != std::errc() || res.ptr != l.data() + q || !std::isfinite(v)) {
        throw ParseError({printable(path), line, std::nullopt, what}, fmt::format("'{}' is not a finite number",
                                                                                  printable(l.substr(p, q - p))));
      }
      r.values.push_back(v);
      p = l.find_first_not_of(" \t\r", q);
      if (p == std::string_view::npos) break;
    }
    if (r.values.size() < min_fields) {
      throw ParseError({printable(path), line, std::nullopt, what},
                       fmt::format("{} fields, expected at least {}", r.values.size(), min_fields));
    }
    rows.push_back(std::move(r));
  }
  return rows;
}

// Rows of steps.txt: step time x y phi ... cov_xx cov_xy cov_xphi cov_yy ...
struct Step {
  std::size_t index = 0;
  double time = 0.0;
  PositionCovariance2 position;
};

std::vector<Step> read_steps(const std::string& path) {
  std::vector<Step> steps;
  for (const Row& r : read_rows(path, 18, "steps")) {
    Step s;
    s.index = static_cast<std::size_t>(std::max(0.0, r.values[0]));
    s.time = r.values[1] >= 0.0 ? r.values[1] : static_cast<double>(steps.size());
    s.position.time = s.time;
    s.position.mean = {r.values[2], r.values[3]};
    s.position.covariance << r.values[12], r.values[13], r.values[13], r.values[15];
    steps.push_back(s);
  }
  if (steps.empty()) throw ParseError({printable(path), std::nullopt, std::nullopt, "steps"}, "no step");
  return steps;
}

// The step of a snapshot file name: particles_<step>_<reason>.txt; -1 for
// particles_initial.txt.
long step_of(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  const std::string digits = name.substr(std::min(name.size(), std::size_t{10}));
  long step = -1;
  std::from_chars(digits.data(), digits.data() + digits.size(), step);
  return step;
}

}  // namespace

std::string add_particle_files(Scene& scene, const std::vector<std::string>& paths,
                               const std::vector<double>& step_times) {
  std::vector<ParticleSnapshot> snaps;
  std::size_t particles = 0;
  for (const auto& path : paths) {
    ParticleSnapshot s;
    const long step = step_of(path);
    if (step < 0) {
      s.time = step_times.empty() ? -1.0 : step_times.front() - 1e-3;
    } else {
      s.time = static_cast<std::size_t>(step) < step_times.size() ? step_times[static_cast<std::size_t>(step)]
                                                                  : static_cast<double>(step);
    }
    for (const Row& r : read_rows(path, 3, "particles")) {
      s.states.emplace_back(r.values[0], r.values[1], r.values[2]);
      s.log_weights.push_back(r.values.size() >= 4 ? r.values[3] : 0.0);
    }
    if (s.states.empty()) throw ParseError({printable(path), std::nullopt, std::nullopt, "particles"}, "no particle");
    particles += s.states.size();
    snaps.push_back(std::move(s));
  }
  std::stable_sort(snaps.begin(), snaps.end(), [](const auto& a, const auto& b) { return a.time < b.time; });
  add_particles(scene, snaps, paths.size() == 1 ? display_name(paths.front()) : "particles");
  return fmt::format("{} particle sets, {} particles", snaps.size(), particles);
}

std::string add_steps_file(Scene& scene, const std::string& path, const SceneLoadOptions& o) {
  const std::vector<Step> steps = read_steps(path);
  std::vector<PositionCovariance2> items;
  const std::size_t n = steps.size(), keep = std::min(n, std::max<std::size_t>(1, o.max_ellipses));
  for (std::size_t k = 0; k < keep; ++k) items.push_back(steps[keep == 1 ? 0 : k * (n - 1) / (keep - 1)].position);
  add_covariance_ellipses(scene, items, display_name(path) + " 3-sigma");
  return fmt::format("{} steps, {} covariance ellipses", n, items.size());
}

std::string add_rawlog_file(Scene& scene, const std::string& path, const SceneLoadOptions& o) {
  AnyRawlogReader reader(path);
  std::vector<TimedPoints> scans;
  std::vector<StampedPose3> poses;
  SE2d pose;
  std::optional<SE2d> first_odometry;
  const auto add_scan = [&](const RangeScan2D& scan) {
    TimedPoints tp;
    tp.time = scan.timestamp.valid() ? scan.timestamp.to_seconds() : static_cast<double>(scans.size());
    const SE3d T_world_sensor = planar(pose) * to_se3(scan.T_robot_sensor);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!scan.ray_yields_point(i)) continue;
      const double a = scan.ray_angle(i), r = scan.ranges[i];
      tp.points.push_back((T_world_sensor * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0.0)).cast<float>());
    }
    poses.push_back({tp.time, planar(pose)});
    scans.push_back(std::move(tp));
  };
  std::uint64_t entries = 0;
  while (auto entry = reader.next()) {
    if (++entries % 1024 == 0) throw_if_interrupted();
    if (const auto* acts = std::get_if<std::shared_ptr<const ActionCollection>>(&*entry)) {
      if (const auto m = (*acts)->find<RobotMovement2D>()) pose = pose * to_se2(m->mean());
    } else if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&*entry)) {
      for (const auto& obs : (*sf)->observations) {
        if (const auto* scan = dynamic_cast<const RangeScan2D*>(obs.get())) add_scan(*scan);
      }
    } else {
      const auto& obs = std::get<std::shared_ptr<const Observation>>(*entry);
      if (const auto* odo = dynamic_cast<const OdometryObservation*>(obs.get())) {
        const SE2d T = to_se2(odo->odometry);
        if (!first_odometry) first_odometry = T;
        pose = first_odometry->inverse() * T;
      } else if (const auto* scan = dynamic_cast<const RangeScan2D*>(obs.get())) {
        add_scan(*scan);
      }
    }
  }
  if (scans.empty()) {
    throw ParseError({printable(path), std::nullopt, std::nullopt, "observations"}, "no 2D range scan to show");
  }
  const std::string name = display_name(path);
  const std::size_t first = scene.layers.size();
  add_scans(scene, scans, name + " scans", o.max_scan_points);
  TrajectoryLayerOptions to;
  to.color = {200, 200, 200, 255};
  add_trajectory(scene, poses, name + " odometry", to);
  return fmt::format("{} scans along the odometry, {} points shown", scans.size(),
                     scene.layers[first].positions.size());
}

namespace {

// The files of `dir` whose name starts with `prefix` and ends with `suffix`, sorted.
std::vector<std::string> files_like(const fs::path& dir, std::string_view prefix, std::string_view suffix) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.rfind(prefix, 0) == 0 && ends_with_ci(name, suffix)) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::string add_paths(Scene& scene, const fs::path& dir, const std::string& main, const char* secondary,
                      Rgba8 secondary_color) {
  std::string what = add_trajectory_file(scene, (dir / main).string(), false, {}) + " (" + main + ")";
  std::error_code ec;
  if (secondary != nullptr && fs::is_regular_file(dir / secondary, ec)) {
    TrajectoryLayerOptions o;
    o.kind = LayerKind::Path;
    o.color = secondary_color;
    o.frames = 0;
    add_trajectory_file(scene, (dir / secondary).string(), false, o);
    what += fmt::format(", {}", secondary);
  }
  const auto& start = scene.layers.back().positions.front();
  add_label(scene, start.cast<double>(), "start");
  return what;
}

std::string add_output_folder(Scene& scene, const std::string& path, SceneInputKind kind, const SceneLoadOptions& o,
                              SceneLoadReport& report) {
  const fs::path dir(path);
  std::vector<std::string> parts;
  std::error_code ec;
  const auto exists = [&](const char* name) { return fs::is_regular_file(dir / name, ec); };
  const Rgba8 gray{150, 150, 150, 255};
  switch (kind) {
    case SceneInputKind::LidarSlamFolder:
      if (exists("map.yaml")) parts.push_back("map " + add_map_file(scene, (dir / "map.yaml").string()));
      parts.push_back("graph " + add_graph_file(scene, (dir / "graph.g2o").string()));
      parts.push_back(add_paths(scene, dir, "path.tum", "odometry.tum", gray));
      break;
    case SceneInputKind::IcpSlamFolder:
      for (const auto& m : files_like(dir, "map", ".yaml")) parts.push_back("map " + add_map_file(scene, m));
      for (const auto& c : files_like(dir, "points", ".ply")) {
        parts.push_back("cloud " + add_cloud_file(scene, c, false, o, report));
      }
      parts.push_back(add_paths(scene, dir, "path.tum", "odometry.tum", gray));
      {
        TrajectoryLayerOptions kf;
        kf.kind = LayerKind::Path;
        kf.color = {90, 200, 255, 255};
        kf.frames = 60;
        parts.push_back("keyframes " + add_trajectory_file(scene, (dir / "keyframes.tum").string(), false, kf));
      }
      break;
    case SceneInputKind::PfLocalizationFolder: {
      const std::vector<Step> steps = read_steps((dir / "steps.txt").string());
      std::vector<double> times;
      for (const auto& s : steps) times.push_back(s.time);
      parts.push_back(add_paths(scene, dir, "path.tum", "odometry.tum", gray));
      parts.push_back(add_steps_file(scene, (dir / "steps.txt").string(), o));
      const std::vector<std::string> snaps = files_like(dir, "particles_", ".txt");
      if (!snaps.empty()) parts.push_back(add_particle_files(scene, snaps, times));
      break;
    }
    case SceneInputKind::KfSlamFolder:
    case SceneInputKind::RbpfSlamFolder:
      return add_filter_slam_folder(scene, path, kind);
    case SceneInputKind::RgbdSlamFolder:
      return add_rgbd_slam_folder(scene, path, o, report);
    case SceneInputKind::NavRunFolder: {
      TrajectoryLayerOptions planned;
      planned.kind = LayerKind::Path;
      planned.color = {255, 80, 200, 255};
      planned.frames = 0;
      planned.timed = false;
      parts.push_back("planned " + add_trajectory_file(scene, (dir / "planned.tum").string(), false, planned));
      parts.push_back(add_paths(scene, dir, "driven.tum", nullptr, gray));
      if (exists("run.rawlog")) parts.push_back(add_rawlog_file(scene, (dir / "run.rawlog").string(), o));
      break;
    }
    default:
      throw InvalidArgument(fmt::format("'{}' is not an output folder", printable(path)));
  }
  std::string what;
  for (const auto& p : parts) what += (what.empty() ? "" : "; ") + p;
  return what;
}

}  // namespace rove::detail
