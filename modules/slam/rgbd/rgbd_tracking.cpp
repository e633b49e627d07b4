#include "rgbd_tracking.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rove::detail {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

void build_grid(FrameFeatures& f, std::uint32_t width, std::uint32_t height) {
  f.grid_cols = std::max(1, static_cast<int>(std::ceil(width / f.cell_size)));
  f.grid_rows = std::max(1, static_cast<int>(std::ceil(height / f.cell_size)));
  const std::size_t cells = static_cast<std::size_t>(f.grid_cols) * static_cast<std::size_t>(f.grid_rows);
  std::vector<std::uint32_t> cell_of(f.keypoints.size());
  f.cell_start.assign(cells + 1, 0);
  for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
    const int cu = std::clamp(static_cast<int>(f.keypoints[i].u / f.cell_size), 0, f.grid_cols - 1);
    const int cv = std::clamp(static_cast<int>(f.keypoints[i].v / f.cell_size), 0, f.grid_rows - 1);
    cell_of[i] = static_cast<std::uint32_t>(cv * f.grid_cols + cu);
    ++f.cell_start[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) f.cell_start[c + 1] += f.cell_start[c];
  f.cell_items.resize(f.keypoints.size());
  std::vector<std::uint32_t> fill(f.cell_start.begin(), f.cell_start.end() - 1);
  for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
    f.cell_items[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  }
}

// True when every depth within `radius` pixels of (u, v) has a value within
// relative_step of z: a point on a depth edge (where color and depth may be
// misregistered by a few pixels) is not trusted.
bool smooth_depth(const DepthImage& depth, double u, double v, double z, int radius,
                  double relative_step) {
  const int cu = static_cast<int>(std::lround(u)), cv = static_cast<int>(std::lround(v));
  const int w = static_cast<int>(depth.width), h = static_cast<int>(depth.height);
  for (int y = std::max(0, cv - radius); y <= std::min(h - 1, cv + radius); ++y) {
    for (int x = std::max(0, cu - radius); x <= std::min(w - 1, cu + radius); ++x) {
      const double d = depth.meters(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
      if (!(std::abs(d - z) <= relative_step * z)) return false;
    }
  }
  return true;
}

// Depth at the sub-pixel position (u, v): bilinear between the four pixels
// around it when they all have values within 5 % of each other (a keypoint
// sits between pixel centres; the nearest pixel's depth is off by up to half
// a pixel of the surface's slope), else the nearest pixel's. NaN when that
// has no value in [min_depth, max_depth].
double interpolated_depth(const DepthImage& depth, double u, double v, double min_depth,
                          double max_depth) {
  const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
  const int w = static_cast<int>(depth.width), h = static_cast<int>(depth.height);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (u0 >= 0 && v0 >= 0 && u0 + 1 < w && v0 + 1 < h) {
    double d[4];
    for (int k = 0; k < 4; ++k) {
      d[k] = depth.meters(static_cast<std::uint32_t>(u0 + (k & 1)), static_cast<std::uint32_t>(v0 + (k >> 1)));
    }
    const double lo = std::min({d[0], d[1], d[2], d[3]}), hi = std::max({d[0], d[1], d[2], d[3]});
    if (lo >= min_depth && hi <= max_depth && hi - lo <= 0.05 * lo) {
      const double a = u - u0, b = v - v0;
      return (1 - b) * ((1 - a) * d[0] + a * d[1]) + b * ((1 - a) * d[2] + a * d[3]);
    }
  }
  const long un = std::lround(u), vn = std::lround(v);
  if (un < 0 || vn < 0 || un >= w || vn >= h) return nan;
  const double z = depth.meters(static_cast<std::uint32_t>(un), static_cast<std::uint32_t>(vn));
  return z >= min_depth && z <= max_depth ? z : nan;
}

}  // namespace

FrameFeatures describe_frame(const RgbdFrame& frame, const PinholeCamera& camera,
                             const RgbdSlamOptions& options, const Eigen::Vector3d& omega) {
  FrameFeatures f;
  Features orb = extract_orb(frame.color, options.orb);
  f.keypoints = std::move(orb.keypoints);
  f.descriptors = std::move(orb.descriptors);
  // OpenCV reports a keypoint found at pixel x of pyramid level l as x·s
  // (s = scale_factor^l), but its bilinear resize puts that pixel's centre
  // at (x + ½)·s − ½ of the full image: shift by (s − 1)/2.
  for (Keypoint& k : f.keypoints) {
    const double shift = 0.5 * (std::pow(options.orb.scale_factor, k.octave) - 1.0);
    k.u += shift;
    k.v += shift;
  }
  f.points.resize(f.keypoints.size());
  const Eigen::Vector3d nan = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
    const double z = interpolated_depth(frame.depth, f.keypoints[i].u, f.keypoints[i].v,
                                        options.min_depth, options.max_depth);
    const Eigen::Vector3d p = z * camera.unproject(f.keypoints[i].u, f.keypoints[i].v);
    if (std::isfinite(z) &&
        (options.depth_edge_step <= 0.0 ||
         smooth_depth(frame.depth, f.keypoints[i].u, f.keypoints[i].v, p.z(), options.depth_edge_radius,
                      options.depth_edge_step))) {
      f.points[i] = p;
      f.descriptors3d.push_back(f.descriptors[i]);
      f.index3d.push_back(static_cast<std::uint32_t>(i));
    } else {
      f.points[i] = nan;
    }
  }
  f.width = frame.color.width;
  f.height = frame.color.height;
  if (options.rolling_shutter_readout.value_or(0.0) > 0.0) {
    f.raw_keypoints = f.keypoints;
    f.raw_points = f.points;
    correct_rolling_shutter(f, camera, options, omega);
  } else {
    build_grid(f, f.width, f.height);
  }
  return f;
}

void correct_rolling_shutter(FrameFeatures& f, const PinholeCamera& camera, const RgbdSlamOptions& options,
                             const Eigen::Vector3d& omega) {
  if (f.raw_keypoints.size() != f.keypoints.size() || f.height == 0) return;
  f.omega = omega;
  // Row v was read (v/h − ½)·readout after the middle row: its ray, in the
  // middle row's camera frame, is exp(ω·δt)·ray (rotation only: over a few
  // milliseconds the camera's translation moves a pixel far less).
  const double h = static_cast<double>(f.height);
  for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
    const Keypoint& raw = f.raw_keypoints[i];
    f.keypoints[i] = raw;
    f.points[i] = f.raw_points[i];
    const double dt = (raw.v / h - 0.5) * options.rolling_shutter_readout.value_or(0.0);
    const SO3d R = SO3d::exp(omega * dt);
    const Eigen::Vector3d ray = R * camera.unproject(raw.u, raw.v);
    if (!(ray.z() > 1e-6)) continue;
    const Eigen::Vector2d px = camera.project(ray);
    f.keypoints[i].u = px.x();
    f.keypoints[i].v = px.y();
    if (std::isfinite(f.points[i].z())) f.points[i] = R * f.points[i];
  }
  build_grid(f, f.width, f.height);
}

std::vector<DescriptorMatch> match_guided(const FrameFeatures& ref, const FrameFeatures& cur,
                                          const SE3d& T_cur_ref, const PinholeCamera& camera,
                                          double radius_px, std::uint32_t max_distance, double ratio) {
  // Best match of each keypoint of cur so far: (distance, ref index).
  std::vector<std::uint32_t> best_dist(cur.keypoints.size(), kNone), best_ref(cur.keypoints.size(), kNone);
  const double r2 = radius_px * radius_px;
  const double w = cur.grid_cols * cur.cell_size, h = cur.grid_rows * cur.cell_size;
  for (const std::uint32_t i : ref.index3d) {
    const Eigen::Vector3d p = T_cur_ref * ref.points[i];
    // Beyond ±1.5 in normalized coordinates the distortion polynomial may
    // fold a point back into the image.
    if (!(p.z() > 1e-6) || std::abs(p.x()) > 1.5 * p.z() || std::abs(p.y()) > 1.5 * p.z()) continue;
    const Eigen::Vector2d px = camera.project(p);
    if (!(px.x() > -radius_px && px.x() < w + radius_px && px.y() > -radius_px && px.y() < h + radius_px)) {
      continue;
    }
    const int c0 = std::max(0, static_cast<int>((px.x() - radius_px) / cur.cell_size));
    const int c1 = std::min(cur.grid_cols - 1, static_cast<int>((px.x() + radius_px) / cur.cell_size));
    const int r0 = std::max(0, static_cast<int>((px.y() - radius_px) / cur.cell_size));
    const int r1 = std::min(cur.grid_rows - 1, static_cast<int>((px.y() + radius_px) / cur.cell_size));
    std::uint32_t d1 = kNone, d2 = kNone, j1 = kNone;
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const std::size_t cell = static_cast<std::size_t>(r * cur.grid_cols + c);
        for (std::uint32_t k = cur.cell_start[cell]; k < cur.cell_start[cell + 1]; ++k) {
          const std::uint32_t j = cur.cell_items[k];
          const double du = cur.keypoints[j].u - px.x(), dv = cur.keypoints[j].v - px.y();
          if (du * du + dv * dv > r2) continue;
          const std::uint32_t d = hamming_distance(ref.descriptors[i], cur.descriptors[j]);
          if (d < d1) {
            d2 = d1;
            d1 = d;
            j1 = j;
          } else if (d < d2) {
            d2 = d;
          }
        }
      }
    }
    if (j1 == kNone || d1 > max_distance) continue;
    if (ratio > 0.0 && d2 != kNone && !(d1 < ratio * d2)) continue;
    if (d1 < best_dist[j1]) {
      best_dist[j1] = d1;
      best_ref[j1] = i;
    }
  }
  std::vector<DescriptorMatch> out;
  for (std::size_t j = 0; j < cur.keypoints.size(); ++j) {
    if (best_ref[j] != kNone) out.push_back({best_ref[j], static_cast<std::uint32_t>(j), best_dist[j]});
  }
  return out;
}

std::vector<DescriptorMatch> match_brute_force(const FrameFeatures& ref, const FrameFeatures& cur,
                                               const BinaryMatchOptions& options) {
  std::vector<DescriptorMatch> m = match_binary(ref.descriptors3d, cur.descriptors, options);
  for (DescriptorMatch& x : m) x.query = ref.index3d[x.query];
  return m;
}

PnpResult solve_frame_pnp(const FrameFeatures& ref, const FrameFeatures& cur,
                          const std::vector<DescriptorMatch>& matches, const PinholeCamera& camera,
                          const PnpOptions& options) {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  points.reserve(matches.size());
  pixels.reserve(matches.size());
  for (const DescriptorMatch& m : matches) {
    const Eigen::Vector3d& p = ref.points[m.query];
    if (!std::isfinite(p.z())) continue;
    points.push_back(p);
    pixels.emplace_back(cur.keypoints[m.train].u, cur.keypoints[m.train].v);
  }
  return solve_pnp_ransac(points, pixels, camera, options);
}

std::vector<DescriptorMatch> pnp_inlier_matches(const FrameFeatures& ref,
                                                const std::vector<DescriptorMatch>& matches,
                                                const PnpResult& pnp) {
  std::vector<DescriptorMatch> used;
  used.reserve(matches.size());
  for (const DescriptorMatch& m : matches) {
    if (std::isfinite(ref.points[m.query].z())) used.push_back(m);
  }
  std::vector<DescriptorMatch> out;
  out.reserve(pnp.inliers.size());
  for (const std::size_t i : pnp.inliers) {
    if (i < used.size()) out.push_back(used[i]);
  }
  return out;
}

Eigen::Matrix<double, 6, 6> inverse_covariance(const SE3d& T,
                                               const Eigen::Matrix<double, 6, 6>& covariance) {
  const Eigen::Matrix<double, 6, 6> A = T.Adj();
  return A * covariance * A.transpose();
}

Eigen::Matrix<double, 6, 6> floored_covariance(const Eigen::Matrix<double, 6, 6>& covariance,
                                               double min_sigma_translation, double min_sigma_rotation) {
  Eigen::Matrix<double, 6, 6> c = 0.5 * (covariance + covariance.transpose());
  for (int k = 0; k < 3; ++k) {
    c(k, k) += min_sigma_translation * min_sigma_translation;
    c(k + 3, k + 3) += min_sigma_rotation * min_sigma_rotation;
  }
  return c;
}

Eigen::Matrix<double, 6, 6> edge_information(const Eigen::Matrix<double, 6, 6>& covariance,
                                             double min_sigma_translation,
                                             double min_sigma_rotation) {
  const Eigen::Matrix<double, 6, 6> c = floored_covariance(covariance, min_sigma_translation, min_sigma_rotation);
  // e = D·ξ with D = diag(1, 1, 1, ½, ½, ½): Cov(e) = D·C·D, Ω = Cov(e)⁻¹.
  Eigen::Matrix<double, 6, 1> d;
  d << 1.0, 1.0, 1.0, 0.5, 0.5, 0.5;
  const Eigen::Matrix<double, 6, 6> ce = d.asDiagonal() * c * d.asDiagonal();
  Eigen::Matrix<double, 6, 6> info = ce.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
  return 0.5 * (info + info.transpose());
}

}  // namespace rove::detail
