#include "rove/maps/metric_map_octree.h"

#include <cmath>

#include <fmt/format.h>

#include "rove/maps/point_map.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/velodyne_decode.h"
#include "rove/obs/velodyne_scan.h"

namespace rove {

OctreeMapInsertOptions OctreeMapInsertOptions::from_config(const ConfigSection& s) {
  OctreeMapInsertOptions o;
  o.max_range = s.get<double>("maxrange", o.max_range);
  if (!std::isfinite(o.max_range)) s.fail("maxrange", "must be finite (-1 for no limit)");
  o.pruning = s.get<bool>("pruning", o.pruning);
  o.sensor = OccupancyOctreeParams::from_config(s);
  return o;
}

OctreeMapLikelihoodOptions OctreeMapLikelihoodOptions::from_config(const ConfigSection& s) {
  OctreeMapLikelihoodOptions o;
  const auto d = s.get<std::int64_t>("decimation", o.decimation);
  if (d < 1 || d > 0xFFFFFFFF) s.fail("decimation", fmt::format("must be >= 1, got {}", d));
  o.decimation = static_cast<std::uint32_t>(d);
  return o;
}

namespace {

struct ScanPoints {
  std::vector<Eigen::Vector3f> p_map;
  std::vector<Rgb8> colors;  // only when asked and available
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};

// Maps points given in the sensor frame, skipping MRPT's invalid (0,0,0).
void add_sensor_points(const Pose3& T_map_sensor, const float* x, const float* y, const float* z, std::size_t n,
                       std::vector<Eigen::Vector3f>& out) {
  const Eigen::Matrix3d R = T_map_sensor.rotation();
  const Eigen::Vector3d t = T_map_sensor.translation();
  out.reserve(out.size() + n);
  for (std::size_t i = 0; i < n; ++i) {
    if (x[i] == 0.0f && y[i] == 0.0f && z[i] == 0.0f) continue;
    out.push_back((R * Eigen::Vector3d(x[i], y[i], z[i]) + t).cast<float>());
  }
}

// The points of an observation in the map frame and its sensor's origin;
// false for a kind without points, or a Velodyne scan whose packets cannot
// be decoded (then `undecoded` says why).
bool points_of(const Observation& o, const Pose3& T_map_robot, bool want_colors, ScanPoints& sp,
               std::string* undecoded = nullptr) {
  const Pose3 T_map_sensor = T_map_robot + o.T_robot_sensor;
  sp.origin = T_map_sensor.translation();
  if (const auto* scan = dynamic_cast<const RangeScan2D*>(&o)) {
    sp.p_map = detail::scan_points(*scan, T_map_robot, PointMapInsertionOptions{}, nullptr);
    return true;
  }
  if (const auto* img = dynamic_cast<const RangeImage3D*>(&o)) {
    if (img->points && !img->points->p_sensor.empty()) {
      const auto& pts = img->points->p_sensor;
      std::vector<float> x, y, z;
      for (const auto& p : pts) x.push_back(p.x()), y.push_back(p.y()), z.push_back(p.z());
      add_sensor_points(T_map_sensor, x.data(), y.data(), z.data(), pts.size(), sp.p_map);
    } else if (img->depth.pixel_count() > 0) {
      img->check();
      RangeImageProjectionOptions po;
      po.frame = RangeImageFrame::Robot;
      po.T_target_robot = T_map_robot;
      for (const auto& p : img->project(po).points) sp.p_map.push_back(p.cast<float>());
    } else {
      return false;
    }
    if (want_colors) sp.colors = detail::range_image_colors(*img, T_map_robot, sp.p_map);
    return true;
  }
  if (const auto* velo = dynamic_cast<const VelodyneScan*>(&o)) {
    const auto& c = velo->point_cloud;
    if (!c.x.empty()) {
      add_sensor_points(T_map_sensor, c.x.data(), c.y.data(), c.z.data(), c.x.size(), sp.p_map);
      return true;
    }
    if (velo->packets.empty()) return false;
    const VelodyneDecodeResult d = decode_velodyne_scan(*velo);
    if (!d.ok()) {
      if (undecoded != nullptr) *undecoded = d.message;
      return false;
    }
    add_sensor_points(T_map_sensor, d.cloud.x.data(), d.cloud.y.data(), d.cloud.z.data(), d.cloud.x.size(), sp.p_map);
    return true;
  }
  return false;
}

bool has_points_kind(const Observation& o) {
  return dynamic_cast<const RangeScan2D*>(&o) != nullptr || dynamic_cast<const RangeImage3D*>(&o) != nullptr ||
         dynamic_cast<const VelodyneScan*>(&o) != nullptr;
}

}  // namespace

OctreeMetricMap::OctreeMetricMap(double resolution, const OctreeMapInsertOptions& insert,
                                 const OctreeMapLikelihoodOptions& likelihood, bool colour)
    : insert_options(insert),
      likelihood_options(likelihood),
      tree_(resolution, insert.sensor, colour ? OctreeChannels::Color : OctreeChannels::None) {}

std::string_view OctreeMetricMap::kind() const noexcept {
  return has_channels(tree_.channels(), OctreeChannels::Color) ? "colourOctoMap" : "octoMap";
}

bool OctreeMetricMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  const bool colour = has_channels(tree_.channels(), OctreeChannels::Color);
  ScanPoints sp;
  std::string undecoded;
  if (!points_of(observation, T_map_robot, colour, sp, &undecoded)) {
    if (!undecoded.empty()) {
      ++undecoded_velodyne_;
      undecoded_reason_ = std::move(undecoded);
    }
    return false;
  }
  OctreeInsertOptions o;
  o.max_range = insert_options.max_range;
  o.lazy = !insert_options.pruning;
  o.skip_invalid_points = true;
  o.num_threads = insert_options.num_threads;
  if (colour && sp.colors.size() == sp.p_map.size()) {
    tree_.insert_point_cloud(sp.p_map, sp.colors, sp.origin, o, OctreeColorUpdate::Integrate);
  } else {
    tree_.insert_point_cloud(sp.p_map, sp.origin, o);
  }
  return true;
}

bool OctreeMetricMap::can_compute_likelihood(const Observation& observation) const {
  return has_points_kind(observation);
}

double OctreeMetricMap::log_likelihood(const Observation& observation, const Pose3& T_map_robot) const {
  ScanPoints sp;
  if (!points_of(observation, T_map_robot, false, sp)) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < sp.p_map.size(); i += likelihood_options.decimation) {
    const auto k = tree_.key_of(sp.p_map[i].cast<double>());
    if (!k) continue;
    const auto n = tree_.search(*k);
    if (n) sum += std::log(octree_probability(n->log_odds));
  }
  return sum;
}

void OctreeMetricMap::clear() {
  tree_ = OccupancyOctree(tree_.resolution(), insert_options.sensor, tree_.channels());
  undecoded_velodyne_ = 0;
  undecoded_reason_.clear();
}

MapBounds OctreeMetricMap::bounding_box() const {
  MapBounds b;
  Eigen::Vector3d lo, hi;
  tree_.metric_bounds(lo, hi);
  if ((lo.array() <= hi.array()).all()) {
    b.extend(lo);
    b.extend(hi);
  }
  return b;
}

MapStatistics OctreeMetricMap::statistics() const {
  MapStatistics s;
  s.unit = "occupied voxels";
  tree_.for_each_leaf([&](const OctreeLeaf& l) {
    ++s.total_cells;
    if (tree_.is_occupied(l.log_odds)) ++s.elements;
  });
  s.bounds = bounding_box();
  return s;
}

std::unique_ptr<MetricMap> make_octree_metric_map(const IniFile& ini, const std::string& p, bool colour,
                                                  std::vector<IgnoredConfigKey>* ign) {
  ConfigSection cs(ini, p + "_creationOpts", ign), is(ini, p + "_insertOpts", ign),
      ls(ini, p + "_likelihoodOpts", ign);
  const double resolution = cs.get_in_range("resolution", 0.10, 1e-6, 1e6);
  auto m = std::make_unique<OctreeMetricMap>(resolution, OctreeMapInsertOptions::from_config(is),
                                             OctreeMapLikelihoodOptions::from_config(ls), colour);
  is.check_all_read();
  ls.check_all_read();
  return m;
}

}  // namespace rove
