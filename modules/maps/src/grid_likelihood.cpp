#include "rove/maps/grid_likelihood.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/maps/grid_clearance.h"
#include "grid_internal.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

bool ray_valid(const RangeScan2D& s, std::size_t i) {
  const float r = s.ranges[i];
  return s.valid[i] && std::isfinite(r) && r >= 0.0f;
}

}  // namespace

void mrpt_scan_points(const RangeScan2D& scan, float min_dist, std::vector<float>& xs,
                      std::vector<float>& ys) {
  scan.check();
  xs.clear();
  ys.clear();
  const std::size_t n = scan.size();
  if (n == 0) return;
  ROVE_CHECK_MSG(n >= 2, "a scan with one ray has no ray angles");
  // Rotation and translation of T_robot_sensor, as floats (MRPT's m00..m23).
  const Eigen::Matrix3d& R = scan.T_robot_sensor.rotation();
  const float m00 = static_cast<float>(R(0, 0)), m01 = static_cast<float>(R(0, 1));
  const float m10 = static_cast<float>(R(1, 0)), m11 = static_cast<float>(R(1, 1));
  const float m20 = static_cast<float>(R(2, 0)), m21 = static_cast<float>(R(2, 1));
  const float m03 = static_cast<float>(scan.T_robot_sensor.x());
  const float m13 = static_cast<float>(scan.T_robot_sensor.y());
  const float m23 = static_cast<float>(scan.T_robot_sensor.z());
  // Ray directions: MRPT's CSinCosLookUpTableFor2DScans accumulates the
  // angle in double and rounds cos/sin to float.
  const double aperture = static_cast<float>(scan.aperture);
  double ang = (scan.right_to_left ? -0.5 : 0.5) * aperture;
  const double d_ang = (scan.right_to_left ? 1.0 : -1.0) * (aperture / static_cast<double>(n - 1));
  const bool use_min_dist = min_dist > 0.0f;
  const float min_d2 = min_dist * min_dist;
  float lx = 0, ly = 0, lz = 0;
  float lx1 = -100, ly1 = -100, lz1 = -100;
  bool last_valid = true, first = true, last_inserted = false;
  xs.reserve(n);
  ys.reserve(n);
  for (std::size_t i = 0; i < n; ++i, ang += d_ang) {
    const bool ok = ray_valid(scan, i);
    if (ok) {
      const float c = static_cast<float>(std::cos(ang)), s = static_cast<float>(std::sin(ang));
      const float r = scan.ranges[i];
      const float sx = r * c, sy = r * s;
      lx = m03 + (sx * m00 + sy * m01);
      ly = m13 + (sx * m10 + sy * m11);
      lz = m23 + (sx * m20 + sy * m21);
      last_inserted = false;
      bool pass = true;
      if (use_min_dist) {
        if (!last_valid) {
          pass = false;
        } else {
          const float d2 = (lx - lx1) * (lx - lx1) + (ly - ly1) * (ly - ly1) + (lz - lz1) * (lz - lz1);
          pass = d2 > min_d2;
        }
      }
      if (first || pass) {
        first = false;
        xs.push_back(lx);
        ys.push_back(ly);
        last_inserted = true;
        if (use_min_dist) {
          lx1 = lx;
          ly1 = ly;
          lz1 = lz;
        }
      }
    }
    last_valid = ok;
  }
  if (last_valid && !last_inserted) {
    xs.push_back(lx);
    ys.push_back(ly);
  }
}

GridLikelihoodOptions GridLikelihoodOptions::from_config(const ConfigSection& config) {
  GridLikelihoodOptions o;
  const IniFile& ini = config.ini();
  const std::string_view section = config.name();
  const std::string sec(section);
  if (ini.has(section, "likelihoodMethod")) {
    o.method = ini.get_enum<GridLikelihoodMethod>(
        section, "likelihoodMethod",
        {{"lmMeanInformation", GridLikelihoodMethod::MeanInformation},
         {"lmRayTracing", GridLikelihoodMethod::RayTracing},
         {"lmConsensus", GridLikelihoodMethod::Consensus},
         {"lmCellsDifference", GridLikelihoodMethod::CellsDifference},
         {"lmLikelihoodField_Thrun", GridLikelihoodMethod::LikelihoodFieldThrun},
         {"lmLikelihoodField_II", GridLikelihoodMethod::LikelihoodFieldII},
         {"lmConsensusOWA", GridLikelihoodMethod::ConsensusOWA}});
  }
  const auto rf = [&](const char* key, float& v) {
    if (ini.has(section, key)) v = ini.get<float>(section, key);
  };
  const auto rb = [&](const char* key, bool& v) {
    if (ini.has(section, key)) v = ini.get<bool>(section, key);
  };
  const auto ru = [&](const char* key, std::uint32_t& v) {
    if (ini.has(section, key)) v = ini.get<unsigned>(section, key);
  };
  const auto ri = [&](const char* key, std::int32_t& v) {
    if (ini.has(section, key)) v = ini.get<int>(section, key);
  };
  rb("enableLikelihoodCache", o.enable_likelihood_cache);
  rf("LF_stdHit", o.lf_std_hit);
  rf("LF_zHit", o.lf_z_hit);
  rf("LF_zRandom", o.lf_z_random);
  rf("LF_maxRange", o.lf_max_range);
  ru("LF_decimation", o.lf_decimation);
  rf("LF_maxCorrsDistance", o.lf_max_corrs_distance);
  rb("LF_useSquareDist", o.lf_use_square_dist);
  rb("LF_alternateAverageMethod", o.lf_alternate_average_method);
  rf("MI_exponent", o.mi_exponent);
  ru("MI_skip_rays", o.mi_skip_rays);
  rf("MI_ratio_max_distance", o.mi_ratio_max_distance);
  rb("rayTracing_useDistanceFilter", o.ray_tracing_use_distance_filter);
  ri("rayTracing_decimation", o.ray_tracing_decimation);
  rf("rayTracing_stdHit", o.ray_tracing_std_hit);
  ri("consensus_takeEachRange", o.consensus_take_each_range);
  rf("consensus_pow", o.consensus_pow);
  if (ini.has(section, "OWA_weights")) o.owa_weights = ini.get_vector<float>(section, "OWA_weights");
  if (ini.has(section, "arithmetic"))
    o.arithmetic = ini.get_enum<Arithmetic>(section, "arithmetic", kArithmeticNames);
  // Each value against its range, naming the key (check() below is the
  // precondition of the models and stays the last line of defence).
  const auto need = [&](bool ok, const char* key, double v, std::string_view range) {
    if (!ok) {
      throw ConfigError(ini.source(), sec, key,
                        fmt::format("line {}: {} is outside {}", ini.line(section, key).value_or(0),
                                    v, range));
    }
  };
  const auto positive = [](float v) { return std::isfinite(v) && v > 0.0f; };
  for (const auto& [key, v] :
       {std::pair{"LF_zHit", o.lf_z_hit}, std::pair{"LF_zRandom", o.lf_z_random},
        std::pair{"MI_exponent", o.mi_exponent}, std::pair{"consensus_pow", o.consensus_pow}}) {
    need(std::isfinite(v), key, v, "the finite numbers");
  }
  need(positive(o.lf_std_hit), "LF_stdHit", o.lf_std_hit, "(0, inf)");
  need(positive(o.lf_max_range), "LF_maxRange", o.lf_max_range, "(0, inf)");
  need(std::isfinite(o.lf_max_corrs_distance) && o.lf_max_corrs_distance >= 0.0f,
       "LF_maxCorrsDistance", o.lf_max_corrs_distance, "[0, inf)");
  need(o.lf_decimation >= 1, "LF_decimation", o.lf_decimation, "[1, inf)");
  need(o.mi_skip_rays >= 1, "MI_skip_rays", o.mi_skip_rays, "[1, inf)");
  need(positive(o.mi_ratio_max_distance), "MI_ratio_max_distance", o.mi_ratio_max_distance, "(0, inf)");
  need(o.ray_tracing_decimation >= 1, "rayTracing_decimation", o.ray_tracing_decimation, "[1, inf)");
  need(positive(o.ray_tracing_std_hit), "rayTracing_stdHit", o.ray_tracing_std_hit, "(0, inf)");
  need(o.consensus_take_each_range >= 1, "consensus_takeEachRange", o.consensus_take_each_range,
       "[1, inf)");
  for (const float w : o.owa_weights) need(std::isfinite(w), "OWA_weights", w, "the finite numbers");
  if (o.owa_weights.empty() && o.method == GridLikelihoodMethod::ConsensusOWA) {
    throw ConfigError(ini.source(), sec, "OWA_weights",
                      "likelihoodMethod lmConsensusOWA needs OWA_weights (none given)");
  }
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), sec, "", e.message());
  }
  return o;
}

void GridLikelihoodOptions::check() const {
  for (const float v : {lf_std_hit, lf_z_hit, lf_z_random, lf_max_range, lf_max_corrs_distance,
                        mi_exponent, mi_ratio_max_distance, ray_tracing_std_hit, consensus_pow}) {
    ROVE_CHECK_FINITE(v);
  }
  ROVE_CHECK_GT(lf_std_hit, 0.0f);
  ROVE_CHECK_GT(lf_max_range, 0.0f);
  ROVE_CHECK_GE(lf_max_corrs_distance, 0.0f);
  ROVE_CHECK_GE(lf_decimation, 1u);
  ROVE_CHECK_GE(mi_skip_rays, 1u);
  ROVE_CHECK_GT(mi_ratio_max_distance, 0.0f);
  ROVE_CHECK_GE(ray_tracing_decimation, 1);
  ROVE_CHECK_GT(ray_tracing_std_hit, 0.0f);
  ROVE_CHECK_GE(consensus_take_each_range, 1);
  ROVE_CHECK_MSG(!owa_weights.empty() || method != GridLikelihoodMethod::ConsensusOWA,
                 "OWA_weights is empty");
  for (const float w : owa_weights) ROVE_CHECK_FINITE(w);
}

template <GridCell Cell>
GridLikelihoodModel<Cell>::GridLikelihoodModel(const OccupancyGridT<Cell>& grid,
                                               GridLikelihoodOptions options,
                                               GridInsertionOptions insertion)
    : grid_(&grid), options_(std::move(options)), insertion_(insertion) {
  options_.check();
  insertion_.check();
  refresh();
}

template <GridCell Cell>
void GridLikelihoodModel<Cell>::refresh() {
  revision_ = grid_->revision();
  field_.clear();
  if (options_.method != GridLikelihoodMethod::LikelihoodFieldThrun) return;
  const auto& g = *grid_;
  const GridLikelihoodOptions& o = options_;
  // MRPT's per-cell value (COccupancyGridMap2D::computeLikelihoodField_Thrun),
  // with its float/double mix: d² in units of (cell/10)², capped at the
  // search radius, then zRandom/maxRange + zHit·exp(Q·d²) in float.
  const float z_random_term = o.lf_z_random / o.lf_max_range;
  const float q = -0.5f / (o.lf_std_hit * o.lf_std_hit);
  const double max_corr_sq = static_cast<double>(o.lf_max_corrs_distance) * o.lf_max_corrs_distance;
  const double res = g.resolution();
  const double units = 100.0 / (res * res);
  const double units_inv = 1.0 / units;
  const auto cap = static_cast<std::uint64_t>(std::lrint(max_corr_sq * units));
  const bool product = !o.lf_alternate_average_method;
  const double outside = z_random_term + o.lf_z_hit * std::exp(q * max_corr_sq);
  field_outside_ = product ? std::log(outside) : outside;
  const auto d2 = squared_distance_to_occupied(g, LogOddsLut<Cell>::instance().p2l(0.5f));
  field_.resize(d2.size());
  // Cache per distinct d² (few distinct values within the cap).
  std::vector<double> memo;
  const std::uint64_t cap_cells = cap / 100 + 1;
  memo.assign(static_cast<std::size_t>(std::min<std::uint64_t>(cap_cells + 1, 1u << 22)),
              std::numeric_limits<double>::quiet_NaN());
  const auto value_of = [&](std::uint64_t units_int) {
    float dist = static_cast<float>(static_cast<double>(units_int) * units_inv);
    if (o.lf_use_square_dist) dist *= dist;
    const float lik = z_random_term + o.lf_z_hit * std::exp(q * dist);
    return product ? std::log(static_cast<double>(lik)) : static_cast<double>(lik);
  };
  const double capped = value_of(cap);
  for (std::size_t i = 0; i < d2.size(); ++i) {
    const std::uint64_t dc = d2[i];  // squared distance in cells
    if (dc >= cap_cells || dc * 100 >= cap) {
      field_[i] = capped;
      continue;
    }
    double& m = memo[static_cast<std::size_t>(dc)];
    if (std::isnan(m)) m = value_of(dc * 100);
    field_[i] = m;
  }
}

template <GridCell Cell>
void GridLikelihoodModel<Cell>::check_fresh() const {
  ROVE_CHECK_MSG(revision_ == grid_->revision(),
                 "the grid changed since the likelihood model was built; call refresh()");
}

template <GridCell Cell>
PreparedGridScan GridLikelihoodModel<Cell>::prepare(const RangeScan2D& scan) const {
  scan.check();
  PreparedGridScan p;
  p.scan = std::make_shared<RangeScan2D>(scan);
  if (!is_horizontal(scan.T_robot_sensor, insertion_.horizontal_tolerance) ||
      (insertion_.use_map_altitude &&
       std::fabs(insertion_.map_altitude - scan.T_robot_sensor.z()) > 0.01)) {
    p.usable = false;
    p.fixed_value = -10.0;
    return p;
  }
  switch (options_.method) {
    case GridLikelihoodMethod::LikelihoodFieldThrun:
      mrpt_scan_points(scan, grid_->resolution() * 0.5f, p.xs, p.ys);
      break;
    case GridLikelihoodMethod::LikelihoodFieldII:
    case GridLikelihoodMethod::Consensus:
      mrpt_scan_points(scan, 0.02f, p.xs, p.ys);
      break;
    case GridLikelihoodMethod::ConsensusOWA:
      mrpt_scan_points(scan, -1.0f, p.xs, p.ys);
      break;
    default:
      break;
  }
  return p;
}

template <GridCell Cell>
double GridLikelihoodModel<Cell>::log_likelihood(const PreparedGridScan& scan,
                                                 const Pose2& T_map_robot) const {
  check_fresh();
  return eval_one(scan, T_map_robot);
}

template <GridCell Cell>
void GridLikelihoodModel<Cell>::log_likelihood(const PreparedGridScan& scan,
                                               std::span<const Pose2> poses,
                                               std::span<double> out) const {
  check_fresh();
  ROVE_CHECK_EQ(out.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) out[i] = eval_one(scan, poses[i]);
}

template <GridCell Cell>
double GridLikelihoodModel<Cell>::log_likelihood(const RangeScan2D& scan,
                                                 const Pose3& T_map_robot) const {
  check_fresh();
  return eval_one(prepare(scan), Pose2(T_map_robot));
}

namespace detail {

// MRPT's simulateScanRay: fixed-point (10 bits) march in steps of 0.8 cell
// until a cell with p(free) <= free_threshold, the grid's edge or max range.
template <GridCell Cell>
float simulate_ray(const OccupancyGridT<Cell>& g, double x, double y, double angle,
                   double max_range, Cell free_threshold) {
  constexpr double kStep = 0.8;
  constexpr int kBits = 10;
  const double res = g.resolution();
  const double qx = (x - g.x_min()) / res, qy = (y - g.y_min()) / res;
  // A start outside the grid sees nothing (and keeps the conversions below
  // in range).
  if (!(qx >= 0.0 && qy >= 0.0 && qx < g.size_x() && qy < g.size_y())) {
    return static_cast<float>(max_range);
  }
  const double ax = std::cos(angle), ay = std::sin(angle);
  const auto max_len = static_cast<unsigned>(std::lrint(max_range / res));
  auto rx = static_cast<std::int64_t>(qx * (1LL << kBits));
  auto ry = static_cast<std::int64_t>(qy * (1LL << kBits));
  const auto dx = static_cast<std::int64_t>(kStep * ax * (1LL << kBits));
  const auto dy = static_cast<std::int64_t>(kStep * ay * (1LL << kBits));
  int hit = 0;
  unsigned len = 0;
  std::int64_t cx = 0, cy = 0;
  const auto cells = g.cells();
  while (true) {
    cx = rx >> kBits;
    if (cx < 0) break;
    cy = ry >> kBits;
    if (cy < 0 || cx >= g.size_x() || cy >= g.size_y()) break;
    hit = cells[static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * g.size_x()];
    if (!(hit > free_threshold) || len >= max_len) break;
    rx += dx;
    ry += dy;
    ++len;
  }
  if (std::abs(hit) <= 1 || cx < 0 || cy < 0 || cx >= g.size_x() || cy >= g.size_y()) {
    return static_cast<float>(max_range);
  }
  return static_cast<float>(kStep * len * res);
}

}  // namespace detail

namespace {

/// What every likelihood method needs: the grid, the options, the prepared
/// scan and the pose (its rotation and translation).
template <GridCell Cell>
struct EvalContext {
  const OccupancyGridT<Cell>& g;
  const GridLikelihoodOptions& o;
  const GridInsertionOptions& insertion;
  const PreparedGridScan& s;
  Pose2 pose;
  double c, sn, x0, y0;
  /// The number of points of the prepared scan.
  std::size_t size() const { return s.xs.size(); }
  /// The scan as given.
  const RangeScan2D& scan() const { return *s.scan; }
  /// Point j of the prepared scan in the map frame.
  Eigen::Vector2d world(std::size_t j) const {
    const double lx = s.xs[j], ly = s.ys[j];
    return {x0 + lx * c - ly * sn, y0 + lx * sn + ly * c};
  }
};

/// Thrun's likelihood field over the precomputed per-cell values.
template <GridCell Cell>
double field_thrun(const EvalContext<Cell>& ctx, const std::vector<double>& field, double field_outside) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const std::size_t n = ctx.size();
  if (n == 0) return -100.0;
  const std::size_t step = n < 10 ? 1 : o.lf_decimation;
  const int lim_x = static_cast<int>(g.size_x()) - 1, lim_y = static_cast<int>(g.size_y()) - 1;
  double sum = 0.0;
  std::size_t m = 0;
  for (std::size_t j = 0; j < n; j += step, ++m) {
    const Eigen::Vector2d w = ctx.world(j);
    const double gx = w.x(), gy = w.y();
    const int cx = g.x_to_idx_clamped(gx), cy = g.y_to_idx_clamped(gy);
    // MRPT treats the last row and column as outside.
    if (static_cast<unsigned>(cx) >= static_cast<unsigned>(lim_x) ||
        static_cast<unsigned>(cy) >= static_cast<unsigned>(lim_y)) {
      sum += field_outside;
    } else {
      sum += field[g.index(cx, cy)];
    }
  }
  return o.lf_alternate_average_method ? std::log(sum / static_cast<double>(m)) : sum;
}

/// The likelihood field II: per point, the mean over a window of cells.
template <GridCell Cell>
double field_ii(const EvalContext<Cell>& ctx) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const std::size_t n = ctx.size();
  if (n == 0) return 1e-100;
  const float z_random_term = 1.0f / o.lf_max_range;
  const float q = -0.5f / (o.lf_std_hit * o.lf_std_hit);
  const int k = static_cast<int>(std::ceil(o.lf_max_corrs_distance / g.resolution()));
  const int sx = static_cast<int>(g.size_x()), sy = static_cast<int>(g.size_y());
  double ret = 0.0;
  std::size_t n_used = 0;
  for (std::size_t j = 0; j < n; j += o.lf_decimation) {
    const Eigen::Vector2d w = ctx.world(j);
    const double gx = w.x(), gy = w.y();
    const int cx0 = g.x_to_idx_clamped(gx), cy0 = g.y_to_idx_clamped(gy);
    int cx_min = std::max(cx0 - k, 0), cx_max = std::min(cx0 + k, sx);
    int cy_min = std::max(cy0 - k, 0), cy_max = std::min(cy0 + k, sy);
    if (cx_min > cx_max || cy_min > cy_max) {
      // Far outside: a window of unknown cells around the point.
      cx_min = cx0 - k;
      cx_max = cx0 + k;
      cy_min = cy0 - k;
      cy_max = cy0 + k;
    }
    double lik = 0.0;
    for (int cx = cx_min; cx <= cx_max; ++cx) {
      for (int cy = cy_min; cy <= cy_max; ++cy) {
        const float p_free = g.free_probability(cx, cy);
        const double ddx = static_cast<double>(g.idx_to_x(static_cast<std::size_t>(cx))) - gx;
        const double ddy = static_cast<double>(g.idx_to_y(static_cast<std::size_t>(cy))) - gy;
        const float term = static_cast<float>(std::exp(q * (ddx * ddx + ddy * ddy)));
        lik += p_free * z_random_term + (1.0f - p_free) * term;
      }
    }
    if (o.lf_alternate_average_method) {
      ret += lik;
    } else {
      ret += std::log(lik / ((cy_max - cy_min + 1) * (cx_max - cx_min + 1)));
    }
    ++n_used;
  }
  if (o.lf_alternate_average_method && n_used > 0) return std::log(ret / n_used);
  return ret / static_cast<double>(n_used);
}

/// The consensus of the points' cells.
template <GridCell Cell>
double consensus(const EvalContext<Cell>& ctx) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const std::size_t n = ctx.size();
  double lik = 0.0;
  std::size_t denom = 0;
  for (std::size_t j = 0; j < n; j += static_cast<std::size_t>(o.consensus_take_each_range)) {
    const Eigen::Vector2d w = ctx.world(j);
    const double gx = w.x(), gy = w.y();
    lik += 1.0 - g.free_probability(g.x_to_idx_clamped(gx), g.y_to_idx_clamped(gy));
    ++denom;
  }
  if (denom) lik /= static_cast<double>(denom);
  return std::log(std::pow(lik, static_cast<double>(o.consensus_pow)));
}

/// The ordered weighted average of the points' 3×3-window occupancies.
template <GridCell Cell>
double consensus_owa(const EvalContext<Cell>& ctx) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const std::size_t n = ctx.size();
  std::vector<double> liks;
  liks.reserve(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Eigen::Vector2d w = ctx.world(j);
    const double gx = w.x(), gy = w.y();
    const int cx0 = g.x_to_idx_clamped(gx), cy0 = g.y_to_idx_clamped(gy);
    double lik = 0.0;
    int cells = 0;
    for (int cx = cx0 - 1; cx <= cx0 + 1; ++cx) {
      for (int cy = cy0 - 1; cy <= cy0 + 1; ++cy) {
        lik += 1.0 - g.free_probability(cx, cy);
        ++cells;
      }
    }
    liks.push_back(lik / cells);
  }
  std::sort(liks.begin(), liks.end(), std::greater<>());
  double r = 0.0;
  for (std::size_t k = 0; k < std::min(liks.size(), o.owa_weights.size()); ++k) {
    r += static_cast<double>(o.owa_weights[k]) * liks[k];
  }
  return std::log(r);
}

/// Simulated against measured ranges along one ray in rayTracing_decimation.
template <GridCell Cell>
double ray_tracing(const EvalContext<Cell>& ctx) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const RangeScan2D& scan = ctx.scan();
  const std::size_t n_rays = scan.size();
  double ret = 1.0;
  if (n_rays < 2) return ret;
  const Pose3 T_map_sensor = Pose3(ctx.pose) + scan.T_robot_sensor;
  const double yaw = T_map_sensor.yaw();
  const double aperture = static_cast<float>(scan.aperture);
  const auto dec = static_cast<std::size_t>(o.ray_tracing_decimation);
  double a = yaw + (scan.right_to_left ? -0.5 : 0.5) * aperture;
  const double da = (scan.right_to_left ? 1.0 : -1.0) * (aperture / static_cast<double>(n_rays - 1));
  const Cell thr = LogOddsLut<Cell>::instance().p2l(1.0f - 0.45f);
  const double std_sqrt2 = static_cast<double>(std::sqrt(2.0f)) * o.ray_tracing_std_hit;
  const double max_range = scan.max_range;
  for (std::size_t j = 0; j < n_rays; j += dec, a += da * static_cast<double>(dec)) {
    if (!ray_valid(scan, j)) continue;
    const float r_sim =
        detail::simulate_ray(g, T_map_sensor.x(), T_map_sensor.y(), a, max_range, thr);
    const float diff = std::min(std::fabs(r_sim - scan.ranges[j]), 2.0f);
    const double z = diff / std_sqrt2;
    ret += std::log(0.1 / scan.max_range + 0.9 * std::exp(-(z * z)));
  }
  return ret;
}

/// The disagreement between the grid and a grid built from the scan alone.
template <GridCell Cell>
double cells_difference(const EvalContext<Cell>& ctx) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const RangeScan2D& scan = ctx.scan();
  const double x0 = ctx.x0, y0 = ctx.y0;
  // Far from the origin, float cannot hold a 20 m grid around the pose:
  // no cell of this grid can be compared there.
  if (!(static_cast<float>(x0 + 10) > static_cast<float>(x0 - 10)) ||
      !(static_cast<float>(y0 + 10) > static_cast<float>(y0 - 10)) ||
      std::fabs(x0) + std::fabs(y0) > 1e6) {
    return 0.0;
  }
  OccupancyGridT<Cell> cmp(static_cast<float>(x0 - 10), static_cast<float>(x0 + 10),
                           static_cast<float>(y0 - 10), static_cast<float>(y0 + 10),
                           g.resolution());
  // MRPT's comparison grid: p = 0.95, whose 3·L overflows int8 in
  // MRPT's arithmetic (reproduced only with Arithmetic::Mrpt).
  GridInsertionOptions io;
  io.max_distance_insertion = ctx.insertion.max_distance_insertion;
  io.max_occupancy_update_certainty = 0.95f;
  io.arithmetic = o.arithmetic;
  insert_scan(cmp, scan, Pose3(ctx.pose), io);
  const int ax = static_cast<int>(std::round((g.x_min() - cmp.x_min()) / g.resolution()));
  const int ay = static_cast<int>(std::round((g.y_min() - cmp.y_min()) / g.resolution()));
  const int xa = std::max(0, ax), ya = std::max(0, ay);
  const int xb = static_cast<int>(std::min<long long>(cmp.size_x(), static_cast<long long>(g.size_x()) + ax));
  const int yb = static_cast<int>(std::min<long long>(cmp.size_y(), static_cast<long long>(g.size_y()) + ay));
  int compared = 0;
  float differ = 0;
  for (int x = xa; x < xb; ++x) {
    for (int y = ya; y < yb; ++y) {
      const float xx = cmp.idx_to_x(static_cast<std::size_t>(x));
      const float yy = cmp.idx_to_y(static_cast<std::size_t>(y));
      const float c1 = g.free_probability(g.x_to_idx(xx), g.y_to_idx(yy));
      const float c2 = cmp.free_probability(x, y);
      if (c2 < 0.45f || c2 > 0.55f) {
        ++compared;
        if ((c1 > 0.5f && c2 < 0.5f) || (c1 < 0.5f && c2 > 0.5f)) differ += 1.0f;
      }
    }
  }
  // No observed cell to compare (MRPT divides 0 by 0): no evidence.
  if (compared == 0) return 0.0;
  return std::log(static_cast<double>(1.0f - differ / static_cast<float>(compared)));
}

/// The mean information of the cells the scan would update.
template <GridCell Cell>
double mean_information(const EvalContext<Cell>& ctx) {
  const auto& g = ctx.g;
  const GridLikelihoodOptions& o = ctx.o;
  const RangeScan2D& scan = ctx.scan();
  GridInsertionOptions io = ctx.insertion;
  io.max_distance_insertion *= o.mi_ratio_max_distance;
  io.arithmetic = o.arithmetic;
  const auto stats =
      detail::scan_information(g, scan, Pose3(ctx.pose), io, static_cast<int>(o.mi_skip_rays));
  const double mean_i = stats.cells ? stats.information / static_cast<double>(stats.cells) : 0.0;
  return std::log(std::pow(mean_i, static_cast<double>(o.mi_exponent)));
}

}  // namespace

template <GridCell Cell>
double GridLikelihoodModel<Cell>::log_likelihood(const PreparedGridScan& scan,
                                                 const SE2d& T_map_robot) const {
  check_fresh();
  const Eigen::Vector2d& t = T_map_robot.translation();
  const Pose2 pose(t.x(), t.y(), T_map_robot.angle());
  if (scan.usable && options_.method == GridLikelihoodMethod::LikelihoodFieldThrun) {
    // The rotation's cosine and sine as they are, not recomputed from the angle.
    const Eigen::Vector2d cs = T_map_robot.rotation().unit_complex();
    const EvalContext<Cell> ctx{*grid_, options_, insertion_, scan, pose, cs.x(), cs.y(), t.x(), t.y()};
    return field_thrun(ctx, field_, field_outside_);
  }
  return eval_one(scan, pose);
}

template <GridCell Cell>
double GridLikelihoodModel<Cell>::eval_one(const PreparedGridScan& s, const Pose2& pose) const {
  if (!s.usable) return s.fixed_value;
  const EvalContext<Cell> ctx{*grid_, options_, insertion_, s, pose, std::cos(pose.phi()),
                              std::sin(pose.phi()), pose.x(), pose.y()};
  switch (options_.method) {
    case GridLikelihoodMethod::LikelihoodFieldThrun: return field_thrun(ctx, field_, field_outside_);
    case GridLikelihoodMethod::LikelihoodFieldII: return field_ii(ctx);
    case GridLikelihoodMethod::Consensus: return consensus(ctx);
    case GridLikelihoodMethod::ConsensusOWA: return consensus_owa(ctx);
    case GridLikelihoodMethod::RayTracing: return ray_tracing(ctx);
    case GridLikelihoodMethod::CellsDifference: return cells_difference(ctx);
    case GridLikelihoodMethod::MeanInformation: return mean_information(ctx);
  }
  return 0.0;
}

template <GridCell Cell>
double scan_log_likelihood(const OccupancyGridT<Cell>& grid, const RangeScan2D& scan,
                           const Pose3& T_map_robot, const GridLikelihoodOptions& options,
                           const GridInsertionOptions& insertion) {
  GridLikelihoodModel<Cell> model(grid, options, insertion);
  return model.log_likelihood(scan, T_map_robot);
}

template class GridLikelihoodModel<std::int8_t>;
template class GridLikelihoodModel<std::int16_t>;
template double scan_log_likelihood(const OccupancyGridT<std::int8_t>&, const RangeScan2D&,
                                    const Pose3&, const GridLikelihoodOptions&,
                                    const GridInsertionOptions&);
template double scan_log_likelihood(const OccupancyGridT<std::int16_t>&, const RangeScan2D&,
                                    const Pose3&, const GridLikelihoodOptions&,
                                    const GridInsertionOptions&);

}  // namespace rove
