// The outputs of rove's filter SLAM commands: the landmark map of
// rove kf-slam (landmarks.csv: means and covariances), the beacon map of its
// range-only rbpf-slam (beacons.csv) and the output folders of both.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string_view>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "scene_inputs.h"

namespace rove::detail {

namespace fs = std::filesystem;

namespace {

// landmarks.csv of rove kf-slam and beacons.csv of its range-only
// rbpf-slam: a header naming the columns (id, x, y, z and the covariance's
// upper triangle among them), then one landmark a line.
constexpr const char* kLandmarkColumns[] = {"x",      "y",      "z",      "cov_xx", "cov_xy",
                                            "cov_xz", "cov_yy", "cov_yz", "cov_zz"};

struct Landmark {
  std::string id;
  PositionCovariance3 position;
};

std::vector<std::string_view> split_commas(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = line.find(',', at);
    out.push_back(line.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at));
    if (comma == std::string_view::npos) return out;
    at = comma + 1;
  }
}

// Column of each of "id" and kLandmarkColumns in the header.
std::array<std::size_t, 10> landmark_columns(const std::string& path, std::string_view header) {
  const std::vector<std::string_view> names = split_commas(header);
  std::array<std::size_t, 10> at{};
  for (std::size_t k = 0; k < at.size(); ++k) {
    const std::string_view want = k == 0 ? "id" : kLandmarkColumns[k - 1];
    const auto it = std::find(names.begin(), names.end(), want);
    if (it == names.end()) {
      throw ParseError({printable(path), 1, std::nullopt, "header"},
                       fmt::format("not a landmark or beacon file of rove: the header has no column '{}' (it needs "
                                   "id, x, y, z, cov_xx, cov_xy, cov_xz, cov_yy, cov_yz, cov_zz)",
                                   want));
    }
    at[k] = static_cast<std::size_t>(it - names.begin());
  }
  return at;
}

std::vector<Landmark> read_landmarks(const std::string& path) {
  const std::string text = read_input_file(path, std::uint64_t{1} << 30, "landmarks");
  std::vector<Landmark> out;
  std::size_t line = 0, at = 0;
  std::array<std::size_t, 10> column{};
  std::size_t needed = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    std::string_view l(text.data() + at, end - at);
    at = end + 1;
    ++line;
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (line == 1) {
      column = landmark_columns(path, l);
      needed = *std::max_element(column.begin(), column.end()) + 1;
      continue;
    }
    if (l.find_first_not_of(" \t") == std::string_view::npos) continue;
    const std::vector<std::string_view> f = split_commas(l);
    if (f.size() < needed) {
      throw ParseError({printable(path), line, std::nullopt, "fields"},
                       fmt::format("{} fields, expected at least {}", f.size(), needed));
    }
    double v[9];
    for (std::size_t k = 0; k < 9; ++k) {
      const std::string_view s = f[column[k + 1]];
      const auto r = std::from_chars(s.data(), s.data() + s.size(), v[k]);
      if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v[k])) {
        throw ParseError({printable(path), line, std::nullopt, kLandmarkColumns[k]},
                         fmt::format("'{}' is not a finite number", printable(s)));
      }
    }
    Landmark lm;
    lm.id = printable(f[column[0]]);
    lm.position.time = static_cast<double>(out.size());
    lm.position.mean = {v[0], v[1], v[2]};
    lm.position.covariance << v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8];
    out.push_back(std::move(lm));
  }
  if (out.empty()) throw ParseError({printable(path), std::nullopt, std::nullopt, "landmarks"}, "no landmark");
  return out;
}

}  // namespace

std::string add_landmarks_file(Scene& scene, const std::string& path, std::string_view noun) {
  const std::vector<Landmark> landmarks = read_landmarks(path);
  const std::string name = display_name(path);
  PointCloud means;
  means.set_channels(PointChannels::Color);
  bool planar = true;
  std::vector<PositionCovariance3> ellipsoids;
  std::vector<PositionCovariance2> ellipses;
  for (const Landmark& l : landmarks) {
    means.push_back(l.position.mean.cast<float>(), Rgb8{230, 40, 40});
    planar = planar && l.position.mean.z() == 0.0 && l.position.covariance(2, 2) == 0.0;
    ellipsoids.push_back(l.position);
    ellipsoids.back().time = 0.0;
  }
  CloudLayerOptions co;
  co.point_size = 6.0f;
  add_point_cloud(scene, means, name, co);
  CovarianceLayerOptions eo;
  eo.timed = false;
  try {
    if (planar) {
      for (const auto& e : ellipsoids) {
        ellipses.push_back({0.0, e.mean.head<2>(), e.covariance.topLeftCorner<2, 2>()});
      }
      add_covariance_ellipses(scene, ellipses, name + " 3-sigma", eo);
    } else {
      add_covariance_ellipsoids(scene, ellipsoids, name + " 3-sigma", eo);
    }
  } catch (const InvalidArgument& e) {
    throw ParseError({printable(path), std::nullopt, std::nullopt, "covariance"}, e.message());
  }
  constexpr std::size_t kMaxLabels = 100;
  if (landmarks.size() <= kMaxLabels) {
    for (const Landmark& l : landmarks) add_label(scene, l.position.mean, l.id.empty() ? "?" : l.id);
  }
  return fmt::format("{} {} {} with their 3-sigma {}", landmarks.size(), planar ? "2D" : "3D", noun,
                     planar ? "ellipses" : "ellipsoids");
}

std::string add_filter_slam_folder(Scene& scene, const std::string& path, SceneInputKind kind) {
  const fs::path dir(path);
  std::error_code ec;
  const auto exists = [&](const char* name) { return fs::is_regular_file(dir / name, ec); };
  std::vector<std::string> parts;
  if (kind == SceneInputKind::RbpfSlamFolder && exists("map.yaml")) {
    parts.push_back("map " + add_map_file(scene, (dir / "map.yaml").string()));
  }
  parts.push_back(add_paths(scene, dir, "path.tum", "odometry.tum", {150, 150, 150, 255}));
  if (kind == SceneInputKind::KfSlamFolder) {
    parts.push_back(add_landmarks_file(scene, (dir / "landmarks.csv").string(), "landmarks"));
  }
  if (kind == SceneInputKind::RbpfSlamFolder && exists("beacons.csv")) {
    parts.push_back(add_landmarks_file(scene, (dir / "beacons.csv").string(), "beacons"));
  }
  std::string what;
  for (const auto& p : parts) what += (what.empty() ? "" : "; ") + p;
  return what;
}

}  // namespace rove::detail
