#include "rove/maps/point_map.h"

#include <algorithm>
#include <cmath>

#include "rove/core/check.h"
#include "point_map_internal.h"

namespace rove {

struct PointMap::Trees {
  std::mutex mutex;
  std::unique_ptr<KdTree3f> tree3;
  std::unique_ptr<KdTree2f> tree2;
};

PointMap::PointMap(PointChannels channels) : trees_(std::make_unique<Trees>()) { cloud_.set_channels(channels); }
PointMap::PointMap(PointCloud cloud) : cloud_(std::move(cloud)), trees_(std::make_unique<Trees>()) {}
PointMap::PointMap(const PointMap& o)
    : insertion_options(o.insertion_options),
      likelihood_options(o.likelihood_options),
      default_color(o.default_color),
      cloud_(o.cloud_),
      trees_(std::make_unique<Trees>()) {}
PointMap& PointMap::operator=(const PointMap& o) {
  if (this != &o) {
    insertion_options = o.insertion_options;
    likelihood_options = o.likelihood_options;
    default_color = o.default_color;
    cloud_ = o.cloud_;
    touch();
  }
  return *this;
}
PointMap::PointMap(PointMap&&) noexcept = default;
PointMap& PointMap::operator=(PointMap&&) noexcept = default;
PointMap::~PointMap() = default;

void PointMap::touch() {
  if (!trees_) trees_ = std::make_unique<Trees>();
  trees_->tree3.reset();
  trees_->tree2.reset();
}

void PointMap::set_cloud(PointCloud cloud) {
  cloud_ = std::move(cloud);
  touch();
}

void PointMap::clear() {
  cloud_.clear();
  touch();
}

void PointMap::insert_point(const Eigen::Vector3f& p) {
  const std::size_t i = cloud_.push_back(p);
  if (cloud_.has_colors()) cloud_.colors_mut()[i] = default_color;
  touch();
}

const KdTree3f& PointMap::kdtree3() const {
  std::lock_guard<std::mutex> lock(trees_->mutex);
  if (!trees_->tree3) trees_->tree3 = std::make_unique<KdTree3f>(cloud_);
  return *trees_->tree3;
}

const KdTree2f& PointMap::kdtree2() const {
  std::lock_guard<std::mutex> lock(trees_->mutex);
  if (!trees_->tree2) trees_->tree2 = std::make_unique<KdTree2f>(cloud_);
  return *trees_->tree2;
}

namespace detail {

namespace {
/// MRPT's sequential filter over candidate points in scan order. `valid[k]`
/// tells whether candidate k comes from a valid measurement; invalid ones
/// only break the "previous ray valid" chain. Interpolation applies to 2D
/// scans only.
template <typename Emit>
void mrpt_filter(const std::vector<Eigen::Vector3f>& cand, const std::vector<bool>& valid,
                 const PointMapInsertionOptions& o, bool interpolate, Emit emit) {
  const bool use_min = o.min_dist_between_points > 0;
  const float min_d2 = o.min_dist_between_points * o.min_dist_between_points;
  bool first = true, last_valid = true, last_inserted = false;
  Eigen::Vector3f last(-100, -100, -100), prev_last(-100, -100, -100), cur = Eigen::Vector3f::Zero();
  int inserted = 0;
  std::size_t cur_k = 0;
  for (std::size_t k = 0; k < cand.size(); ++k) {
    if (valid[k]) {
      cur = cand[k];
      cur_k = k;
      last_inserted = false;
      bool pass = true;
      float d2 = 0;
      if (use_min || interpolate) {
        if (!last_valid) {
          pass = false;
        } else {
          d2 = (cur - last).squaredNorm();
          pass = d2 > min_d2;
        }
      }
      if (first || pass) {
        if (interpolate && inserted >= 2) {
          const float d = std::sqrt(d2);
          float turn = 0;
          if ((cur.head<2>() != last.head<2>()) && (last.head<2>() != prev_last.head<2>()))
            turn = std::atan2(cur.y() - last.y(), cur.x() - last.x()) -
                   std::atan2(last.y() - prev_last.y(), last.x() - prev_last.x());
          if (d >= 2 * o.min_dist_between_points && d < o.max_dist_for_interpolate &&
              std::fabs(turn) < static_cast<float>(5.0 * 3.14159265358979323846 / 180.0) && use_min) {
            const int n = static_cast<int>(std::lround(d / (2 * o.min_dist_between_points)));
            for (int q = 1; q < n; ++q) emit(Eigen::Vector3f(last + (cur - last) * (static_cast<float>(q) / n)), -1);
          }
        }
        first = false;
        emit(cur, static_cast<int>(k));
        ++inserted;
        last_inserted = true;
        prev_last = last;
        last = cur;
      }
    }
    last_valid = valid[k];
  }
  if (last_valid && !last_inserted && !cand.empty() && !first) emit(cur, static_cast<int>(cur_k));
}
}  // namespace

std::vector<Eigen::Vector3f> scan_points(const RangeScan2D& scan, const Pose3& T_frame_robot,
                                         const PointMapInsertionOptions& o, std::vector<int>* ray_of) {
  scan.check();
  std::vector<Eigen::Vector3f> out;
  if (ray_of) ray_of->clear();
  const std::size_t n = scan.size();
  if (n == 0) return out;
  const bool any = std::any_of(scan.valid.begin(), scan.valid.end(), [](bool v) { return v; });
  if (!any) return out;
  const Pose3 T = T_frame_robot + scan.T_robot_sensor;
  std::vector<Eigen::Vector3f> cand(n, Eigen::Vector3f::Zero());
  std::vector<bool> valid(n, false);
  if (o.arithmetic == Arithmetic::Mrpt) {
    mrpt_scan_candidates(scan, T, cand, valid);
  } else {
    // In double, rounded once: the scan's own ray angles (a single ray
    // points at the aperture's first edge, as MRPT's).
    const Eigen::Matrix3d R = T.rotation();
    const Eigen::Vector3d t = T.translation();
    const double first = (scan.right_to_left ? -0.5 : 0.5) * scan.aperture;
    for (std::size_t i = 0; i < n; ++i) {
      if (!scan.ray_yields_point(i)) continue;
      const double angle = n >= 2 ? scan.ray_angle(i) : first;
      const double r = scan.ranges[i];
      cand[i] = (R.leftCols<2>() * Eigen::Vector2d(r * std::cos(angle), r * std::sin(angle)) + t)
                    .cast<float>();
      valid[i] = true;
    }
  }
  mrpt_filter(cand, valid, o, o.also_interpolate, [&](const Eigen::Vector3f& p, int k) {
    out.push_back(p);
    if (ray_of) ray_of->push_back(k);
  });
  return out;
}

}  // namespace detail

namespace {

bool is_planar(const Pose3& T_robot_sensor, float tolerance) {
  const auto ypr = T_robot_sensor.yaw_pitch_roll();
  return std::fabs(ypr.pitch) <= tolerance && std::fabs(ypr.roll) <= tolerance;
}

/// Points of a range image in the frame of T_frame_robot, MRPT's 3D rules;
/// `pixel_of` gets the row-major pixel index of each point.
std::vector<Eigen::Vector3f> image_points_mrpt(const RangeImage3D& scan, const Pose3& T_frame_robot,
                                               const PointMapInsertionOptions& o, std::vector<std::size_t>* pixel_of) {
  scan.check();
  RangeImageProjectionOptions po;
  po.frame = RangeImageFrame::Robot;
  po.T_target_robot = T_frame_robot;
  const RangeImageProjection proj = scan.project(po);
  const std::size_t w = scan.depth_camera.width, h = scan.depth_camera.height;
  const Eigen::Vector3f origin = (T_frame_robot + scan.T_robot_sensor).translation().cast<float>();
  std::vector<Eigen::Vector3f> cand;
  std::vector<bool> valid;
  std::vector<std::size_t> pix;
  std::size_t next = 0;
  for (std::size_t v = 0; v < h; ++v)
    for (std::size_t u = 0; u < w; ++u) {
      const bool has = next < proj.points.size() && proj.pixel_u[next] == u && proj.pixel_v[next] == v;
      if (has) {
        cand.push_back(proj.points[next++].cast<float>());
        valid.push_back(true);
        pix.push_back(v * w + u);
      } else if (o.insert_invalid_points) {
        cand.push_back(origin);
        valid.push_back(true);
        pix.push_back(v * w + u);
      } else {
        cand.push_back(Eigen::Vector3f::Zero());
        valid.push_back(false);
        pix.push_back(v * w + u);
      }
    }
  std::vector<Eigen::Vector3f> out;
  if (pixel_of) pixel_of->clear();
  std::vector<bool> any_valid = valid;
  if (std::none_of(any_valid.begin(), any_valid.end(), [](bool b) { return b; })) return out;
  detail::mrpt_filter(cand, valid, o, false, [&](const Eigen::Vector3f& p, int k) {
    out.push_back(p);
    if (pixel_of) pixel_of->push_back(pix[static_cast<std::size_t>(k)]);
  });
  return out;
}

/// Crossing-number point-in-polygon test in XY.
bool inside_polygon(const std::vector<Eigen::Vector3f>& poly, float x, float y) {
  bool in = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const float xi = poly[i].x(), yi = poly[i].y(), xj = poly[j].x(), yj = poly[j].y();
    if (((yi > y) != (yj > y)) && (x < (xj - xi) * (y - yi) / (yj - yi) + xi)) in = !in;
  }
  return in;
}

}  // namespace


void PointMap::append_scan_points(const std::vector<Eigen::Vector3f>& pts, const std::vector<Rgb8>* colors,
                                  const std::vector<float>* intensity) {
  cloud_.reserve(cloud_.size() + pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const std::size_t i = cloud_.push_back(pts[k]);
    if (cloud_.has_colors()) cloud_.colors_mut()[i] = colors ? (*colors)[k] : default_color;
    if (cloud_.has_intensity() && intensity) cloud_.intensities_mut()[i] = (*intensity)[k];
  }
  touch();
}

void PointMap::fuse_points(const std::vector<Eigen::Vector3f>& pts, bool allow_deletion) {
  const std::size_t n_old = cloud_.size();
  std::vector<bool> deletable(n_old, true);
  {
    const KdTree2f& tree = kdtree2();  // the map before fusion, as MRPT matches once
    std::vector<std::optional<Neighbor<float>>> match(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      auto nn = tree.nearest(pts[k].head<2>());
      if (nn && std::sqrt(nn->sq_distance) < insertion_options.min_dist_between_points) match[k] = nn;
    }
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (match[k]) {
        auto pm = cloud_.points_mut();
        pm[match[k]->index] = 0.5f * (pm[match[k]->index] + pts[k]);
        deletable[match[k]->index] = false;
      } else {
        const std::size_t i = cloud_.push_back(pts[k]);
        if (cloud_.has_colors()) cloud_.colors_mut()[i] = default_color;
      }
    }
  }
  if (allow_deletion && !insertion_options.disable_deletion && pts.size() >= 3) {
    std::vector<bool> keep(cloud_.size(), true);
    for (std::size_t i = 0; i < n_old; ++i)
      if (deletable[i] && inside_polygon(pts, cloud_[i].x(), cloud_[i].y())) keep[i] = false;
    cloud_.filter(keep);
  }
  touch();
}

bool PointMap::insert(const RangeScan2D& scan, const Pose3& T_map_robot) {
  if (insertion_options.is_planar_map && !is_planar(scan.T_robot_sensor, insertion_options.horizontal_tolerance))
    return false;
  std::vector<int> rays;
  const auto pts = detail::scan_points(scan, T_map_robot, insertion_options, &rays);
  if (insertion_options.fuse_with_existing) {
    fuse_points(pts, true);
  } else {
    std::vector<float> inten;
    if (cloud_.has_intensity() && !scan.intensity.empty())
      for (int r : rays) inten.push_back(r >= 0 ? static_cast<float>(scan.intensity[static_cast<std::size_t>(r)]) : 0.0f);
    append_scan_points(pts, nullptr, inten.empty() ? nullptr : &inten);
  }
  return true;
}

namespace {
Rgb8 sample_color(const Image& img, double u, double v) {
  const long ui = std::lround(u), vi = std::lround(v);
  if (ui < 0 || vi < 0 || ui >= static_cast<long>(img.width) || vi >= static_cast<long>(img.height) ||
      img.pixel_type != PixelType::U8)
    return Rgb8{};
  const std::size_t base = (static_cast<std::size_t>(vi) * img.width + static_cast<std::size_t>(ui)) * img.channels;
  if (img.channels >= 3) return Rgb8{img.data[base], img.data[base + 1], img.data[base + 2]};
  return Rgb8{img.data[base], img.data[base], img.data[base]};
}
}  // namespace

std::vector<Rgb8> detail::range_image_colors(const RangeImage3D& scan, const Pose3& T_map_robot,
                                            const std::vector<Eigen::Vector3f>& p_map) {
  std::vector<Rgb8> colors(p_map.size(), Rgb8{});
  if (!scan.intensity || scan.intensity->empty()) return colors;
  // Color of each point: its projection into the intensity camera.
  const Pose3 T_map_intensity = T_map_robot + scan.T_robot_sensor + scan.T_sensor_intensity;
  const Pose3 T_intensity_map = T_map_intensity.inverse();
  for (std::size_t i = 0; i < p_map.size(); ++i) {
    const Eigen::Vector3d pc = T_intensity_map.rotation() * p_map[i].cast<double>() + T_intensity_map.translation();
    if (pc.z() > 0) {
      const Eigen::Vector2d uv = scan.intensity_camera.project(pc);
      colors[i] = sample_color(*scan.intensity, uv.x(), uv.y());
    }
  }
  return colors;
}

bool PointMap::insert(const RangeImage3D& scan, const Pose3& T_map_robot) {
  if (insertion_options.is_planar_map) return false;
  std::vector<std::size_t> pix;
  const auto pts = image_points_mrpt(scan, T_map_robot, insertion_options, &pix);
  if (insertion_options.fuse_with_existing) {
    fuse_points(pts, false);
    return true;
  }
  std::vector<Rgb8> colors;
  std::vector<float> inten;
  if ((cloud_.has_colors() || cloud_.has_intensity()) && scan.intensity && !scan.intensity->empty()) {
    colors = detail::range_image_colors(scan, T_map_robot, pts);
    for (const Rgb8& c : colors) inten.push_back((c.r + c.g + c.b) / (3.0f * 255.0f));
  }
  append_scan_points(pts, colors.empty() ? nullptr : &colors, inten.empty() ? nullptr : &inten);
  return true;
}

void PointMap::load_scan(const RangeScan2D& scan, const Pose3& T_map_robot) {
  if (!insertion_options.add_to_existing) clear();
  const bool fuse = insertion_options.fuse_with_existing;
  const bool planar = insertion_options.is_planar_map;
  insertion_options.fuse_with_existing = false;
  insertion_options.is_planar_map = false;
  insert(scan, T_map_robot);
  insertion_options.fuse_with_existing = fuse;
  insertion_options.is_planar_map = planar;
}

void PointMap::load_scan(const RangeImage3D& scan, const Pose3& T_map_robot) {
  if (!insertion_options.add_to_existing) clear();
  const bool fuse = insertion_options.fuse_with_existing;
  const bool planar = insertion_options.is_planar_map;
  insertion_options.fuse_with_existing = false;
  insertion_options.is_planar_map = false;
  insert(scan, T_map_robot);
  insertion_options.fuse_with_existing = fuse;
  insertion_options.is_planar_map = planar;
}

double PointMap::likelihood_of(const std::vector<Eigen::Vector3f>& p_robot, const Pose3& T, bool planar) const {
  const auto& lo = likelihood_options;
  ROVE_CHECK_GT(lo.sigma_dist, 0.0);
  ROVE_CHECK_GT(lo.max_corr_distance, 0.0);
  ROVE_CHECK_GE(lo.decimation, 1u);
  if (p_robot.empty() || cloud_.count_finite() == 0) return -100.0;
  const float max_d2 = static_cast<float>(lo.max_corr_distance * lo.max_corr_distance);
  const Eigen::Matrix3f R = T.rotation().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  double sum = 0;
  std::size_t n = 0;
  const KdTree2f* t2 = planar ? &kdtree2() : nullptr;
  const KdTree3f* t3 = planar ? nullptr : &kdtree3();
  for (std::size_t i = 0; i < p_robot.size(); i += lo.decimation, ++n) {
    const Eigen::Vector3f g = R * p_robot[i] + t;
    float d2 = max_d2;
    if (t2) {
      if (auto nn = t2->nearest(g.head<2>())) d2 = nn->sq_distance;
    } else if (auto nn = t3->nearest(g)) {
      d2 = nn->sq_distance;
    }
    sum += std::min(d2, max_d2);
  }
  return -(sum / static_cast<double>(n)) / lo.sigma_dist;
}

double PointMap::log_likelihood(const RangeScan2D& scan, const Pose3& T_map_robot) const {
  const auto pts = detail::scan_points(scan, Pose3(), PointMapInsertionOptions{}, nullptr);
  const auto ypr = T_map_robot.yaw_pitch_roll();
  return likelihood_of(pts, T_map_robot, ypr.pitch == 0.0 && ypr.roll == 0.0);
}

double PointMap::log_likelihood(const RangeImage3D& scan, const Pose3& T_map_robot) const {
  const auto pts = image_points_mrpt(scan, Pose3(), PointMapInsertionOptions{}, nullptr);
  return likelihood_of(pts, T_map_robot, false);
}

void PointMap::clip(const BoundingBox3& box) {
  std::vector<bool> keep(cloud_.size());
  for (std::size_t i = 0; i < cloud_.size(); ++i) keep[i] = box.contains(cloud_[i]);
  cloud_.filter(keep);
  touch();
}

void PointMap::transform(const Pose3& T) {
  const Eigen::Matrix3d R = T.rotation();
  const Eigen::Vector3d t = T.translation();
  for (auto& p : cloud_.points_mut()) p = (R * p.cast<double>() + t).cast<float>();
  for (auto& n : cloud_.normals_mut()) n = (R * n.cast<double>()).cast<float>();
  touch();
}

}  // namespace rove
