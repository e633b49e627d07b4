#include "rove/maps/beacon_map.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/math/statistics.h"
#include "rove/poses/angle.h"

namespace rove {

namespace {

constexpr double kDegToRad = kPi / 180.0;

bool is_2d(const BeaconMapInsertOptions& o) {
  return o.min_elevation_deg == o.max_elevation_deg;
}

Eigen::Vector3d robot_to_map(const Pose3& T_map_robot, const Eigen::Vector3d& p_robot) {
  return T_map_robot.rotation() * p_robot + T_map_robot.translation();
}

/// An orthonormal basis whose first column is along d (MRPT's
/// generateAxisBaseFromDirection): the second is horizontal, the third
/// their cross product.
Eigen::Matrix3d axis_base_from_direction(const Eigen::Vector3d& d) {
  Eigen::Matrix3d P;
  const double n = d.norm();
  P.col(0) = d / n;
  const double n_xy = std::hypot(d.x(), d.y());
  if (std::abs(d.x()) > 1e-4 || std::abs(d.y()) > 1e-4) {
    P.col(1) = Eigen::Vector3d(-d.y() / n_xy, d.x() / n_xy, 0.0);
  } else {
    P.col(1) = Eigen::Vector3d::UnitX();
  }
  P.col(2) = P.col(0).cross(P.col(1));
  return P;
}

/// Moment-matched Gaussian of weighted points or weighted Gaussians.
PointGaussian3 moments_of(const std::vector<Eigen::Vector3d>& means,
                          const std::vector<const Eigen::Matrix3d*>& covs,
                          std::vector<double> log_w) {
  ROVE_CHECK_MSG(!means.empty(), "a beacon density with no samples or modes has no moments");
  const std::vector<double> w = weights_from_log_weights(log_w);
  PointGaussian3 g;
  for (std::size_t i = 0; i < means.size(); ++i) g.mean += w[i] * means[i];
  for (std::size_t i = 0; i < means.size(); ++i) {
    const Eigen::Vector3d d = means[i] - g.mean;
    g.covariance += w[i] * (d * d.transpose());
    if (!covs.empty()) g.covariance += w[i] * *covs[i];
  }
  return g;
}

/// Predicted range from `sensor` to a Gaussian beacon, its Jacobian and the
/// innovation variance H·C·Hᵀ + σ². Returns false if the sensor sits on the
/// mean (no direction, no update).
bool range_model(const PointGaussian3& g, const Eigen::Vector3d& sensor, double var_r,
                 double& expected, Eigen::RowVector3d& H, double& var_z) {
  const Eigen::Vector3d d = g.mean - sensor;
  expected = d.norm();
  if (!(expected > 1e-9)) return false;
  H = d.transpose() / expected;
  var_z = (H * g.covariance * H.transpose())(0, 0) + var_r;
  return var_z > 0.0;
}

/// EKF update of a Gaussian with a range (Blanco et al., IROS 2008, Eq. 9).
void ekf_range_update(PointGaussian3& g, const Eigen::Vector3d& sensor, double range,
                      double var_r, double* innovation_log_lik) {
  double expected = 0.0, var_z = 0.0;
  Eigen::RowVector3d H;
  if (!range_model(g, sensor, var_r, expected, H, var_z)) {
    if (innovation_log_lik != nullptr) *innovation_log_lik = 0.0;
    return;
  }
  const double y = range - expected;
  const Eigen::Vector3d K = g.covariance * H.transpose() / var_z;
  g.mean += K * y;
  g.covariance = ((Eigen::Matrix3d::Identity() - K * H) * g.covariance).eval();
  g.covariance = (0.5 * (g.covariance + g.covariance.transpose())).eval();
  if (innovation_log_lik != nullptr) *innovation_log_lik = -0.5 * y * y / var_z;
}

double max_axis_std(const Eigen::Matrix3d& C) {
  return std::sqrt(std::max({C(0, 0), C(1, 1), C(2, 2), 0.0}));
}

}  // namespace

std::string_view to_string(BeaconPdfKind k) noexcept {
  switch (k) {
    case BeaconPdfKind::MonteCarlo: return "montecarlo";
    case BeaconPdfKind::Gaussian: return "gaussian";
    case BeaconPdfKind::SumOfGaussians: return "sog";
  }
  return "unknown";
}

PointGaussian3 Beacon::moments() const {
  switch (kind) {
    case BeaconPdfKind::Gaussian: return gaussian;
    case BeaconPdfKind::MonteCarlo: {
      std::vector<Eigen::Vector3d> m;
      std::vector<double> w;
      m.reserve(samples.size());
      w.reserve(samples.size());
      for (const auto& s : samples) {
        m.push_back(s.position);
        w.push_back(s.log_weight);
      }
      return moments_of(m, {}, std::move(w));
    }
    case BeaconPdfKind::SumOfGaussians: {
      std::vector<Eigen::Vector3d> m;
      std::vector<const Eigen::Matrix3d*> c;
      std::vector<double> w;
      for (const auto& mode : modes) {
        m.push_back(mode.gaussian.mean);
        c.push_back(&mode.gaussian.covariance);
        w.push_back(mode.log_weight);
      }
      return moments_of(m, c, std::move(w));
    }
  }
  throw InvalidArgument("Beacon::moments: invalid density kind");
}

BeaconMapInsertOptions BeaconMapInsertOptions::from_config(const ConfigSection& s) {
  BeaconMapInsertOptions o;
  o.insert_as_monte_carlo = s.get<bool>("insertAsMonteCarlo", o.insert_as_monte_carlo);
  o.max_elevation_deg = s.get_in_range("maxElevation_deg", o.max_elevation_deg, -90, 90);
  o.min_elevation_deg = s.get_in_range("minElevation_deg", o.min_elevation_deg, -90, 90);
  if (o.min_elevation_deg > o.max_elevation_deg) {
    s.fail("minElevation_deg", fmt::format("minElevation_deg ({}) > maxElevation_deg ({})",
                                           o.min_elevation_deg, o.max_elevation_deg));
  }
  o.mc_samples_per_meter = s.get<unsigned>("MC_numSamplesPerMeter", o.mc_samples_per_meter);
  o.mc_max_std_to_gauss = s.get_in_range("MC_maxStdToGauss", o.mc_max_std_to_gauss, 0, 1e9);
  o.mc_threshold_negligible =
      s.get_in_range("MC_thresholdNegligible", o.mc_threshold_negligible, 0, 1e300);
  o.mc_perform_resampling = s.get<bool>("MC_performResampling", o.mc_perform_resampling);
  o.mc_after_resampling_noise =
      s.get_in_range("MC_afterResamplingNoise", o.mc_after_resampling_noise, 0, 1e9);
  o.sog_threshold_negligible =
      s.get_in_range("SOG_thresholdNegligible", o.sog_threshold_negligible, 0, 1e300);
  o.sog_max_dist_between_gaussians = s.get_in_range(
      "SOG_maxDistBetweenGaussians", o.sog_max_dist_between_gaussians, 1e-6, 1e9);
  o.sog_separation_constant =
      s.get_in_range("SOG_separationConstant", o.sog_separation_constant, 1e-9, 1e9);
  o.random_seed = s.get<std::uint64_t>("random_seed", o.random_seed);
  return o;
}

BeaconMapLikelihoodOptions BeaconMapLikelihoodOptions::from_config(const ConfigSection& s) {
  BeaconMapLikelihoodOptions o;
  o.range_std = s.get_in_range("rangeStd", o.range_std, 1e-12, 1e9);
  return o;
}

std::vector<BeaconMode> beacon_ring_modes(double R, const Eigen::Vector3d& sensor,
                                          const BeaconMapInsertOptions& io,
                                          const BeaconMapLikelihoodOptions& lo) {
  ROVE_CHECK_MSG(std::isfinite(R) && R > 0, "ring radius must be positive, got {}", R);
  ROVE_CHECK_LE(io.min_elevation_deg, io.max_elevation_deg);
  const double min_el = io.min_elevation_deg * kDegToRad;
  const double max_el = io.max_elevation_deg * kDegToRad;
  // Number of modes along a great circle: spacing at most the configured
  // distance, at least 30, even (MRPT's generateRingSOG).
  std::size_t B =
      static_cast<std::size_t>(2.0 * kPi * R / io.sog_max_dist_between_gaussians) + 1;
  B = std::max<std::size_t>(B, 30);
  if (B % 2 != 0) ++B;
  const double step = 2.0 * kPi / static_cast<double>(B);
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  S(0, 0) = lo.range_std * lo.range_std;
  S(1, 1) = S(2, 2) = std::pow(step * R / io.sog_separation_constant, 2);
  const bool flat = std::abs(min_el - max_el) < 1e-6;

  std::vector<BeaconMode> modes;
  for (std::size_t ie = 0; ie <= 1 + B / 2; ++ie) {
    const double el = min_el + static_cast<double>(ie) * step;
    if (el > max_el + 0.5 * step) continue;
    const std::size_t n_th = std::abs(std::cos(el)) < 1e-4 ? 1 : B;
    for (std::size_t it = 0; it < n_th; ++it) {
      const double th = static_cast<double>(it) * step;
      BeaconMode m;
      const Eigen::Vector3d dir(R * std::cos(th) * std::cos(el), R * std::sin(th) * std::cos(el),
                                R * std::sin(el));
      m.gaussian.mean = sensor + dir;
      const Eigen::Matrix3d P = axis_base_from_direction(dir);
      m.gaussian.covariance = P * S * P.transpose();
      if (flat) {
        m.gaussian.covariance.row(2).setZero();
        m.gaussian.covariance.col(2).setZero();
      }
      modes.push_back(m);
    }
  }
  return modes;
}

BeaconMap::BeaconMap(BeaconMapInsertOptions io, BeaconMapLikelihoodOptions lo)
    : insert_options(io), likelihood_options(lo), rng_(io.random_seed) {}

const Beacon* BeaconMap::find(std::int32_t id) const noexcept {
  for (const auto& b : beacons_) {
    if (b.id == id) return &b;
  }
  return nullptr;
}

Beacon* BeaconMap::find_mutable(std::int32_t id) noexcept {
  for (auto& b : beacons_) {
    if (b.id == id) return &b;
  }
  return nullptr;
}

void BeaconMap::add(Beacon beacon) {
  switch (beacon.kind) {
    case BeaconPdfKind::MonteCarlo: ROVE_CHECK(!beacon.samples.empty()); break;
    case BeaconPdfKind::SumOfGaussians: ROVE_CHECK(!beacon.modes.empty()); break;
    case BeaconPdfKind::Gaussian:
      ROVE_CHECK_FINITE(beacon.gaussian.mean);
      ROVE_CHECK_FINITE(beacon.gaussian.covariance);
      break;
  }
  if (Beacon* b = find_mutable(beacon.id)) {
    *b = std::move(beacon);
  } else {
    beacons_.push_back(std::move(beacon));
  }
}

bool BeaconMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  const auto* o = dynamic_cast<const BeaconRanges*>(&observation);
  if (o == nullptr) return false;
  ROVE_CHECK_MSG(likelihood_options.range_std > 0, "rangeStd must be > 0, got {}",
                 likelihood_options.range_std);
  ROVE_CHECK_LE(insert_options.min_elevation_deg, insert_options.max_elevation_deg);
  for (const auto& r : o->readings) {
    const double range = r.range;
    if (!(range > 0.0) || !std::isfinite(range)) continue;  // only sensible ranges
    const Eigen::Vector3d sensor = robot_to_map(T_map_robot, r.position_on_robot);
    if (Beacon* b = find_mutable(r.beacon_id)) {
      fuse(*b, range, sensor);
    } else {
      insert_new(r.beacon_id, range, sensor);
    }
  }
  return true;
}

void BeaconMap::insert_new(std::int32_t id, double range, const Eigen::Vector3d& sensor) {
  Beacon b;
  b.id = id;
  if (insert_options.insert_as_monte_carlo) {
    b.kind = BeaconPdfKind::MonteCarlo;
    const auto n = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(insert_options.mc_samples_per_meter * range)));
    const double min_el = insert_options.min_elevation_deg * kDegToRad;
    const double max_el = insert_options.max_elevation_deg * kDegToRad;
    std::uniform_real_distribution<double> u_th(-kPi, kPi);
    std::normal_distribution<double> n_r(range, likelihood_options.range_std);
    b.samples.resize(n);
    for (auto& s : b.samples) {
      const double th = u_th(rng_);
      const double el =
          max_el > min_el ? std::uniform_real_distribution<double>(min_el, max_el)(rng_) : min_el;
      const double R = n_r(rng_);
      s.position = sensor + Eigen::Vector3d(R * std::cos(th) * std::cos(el),
                                            R * std::sin(th) * std::cos(el), R * std::sin(el));
      s.log_weight = 0.0;
    }
  } else {
    b.kind = BeaconPdfKind::SumOfGaussians;
    b.modes = beacon_ring_modes(range, sensor, insert_options, likelihood_options);
  }
  beacons_.push_back(std::move(b));
}

void BeaconMap::fuse(Beacon& b, double range, const Eigen::Vector3d& sensor) {
  const double sigma = likelihood_options.range_std;
  const double var_r = sigma * sigma;
  switch (b.kind) {
    case BeaconPdfKind::MonteCarlo: {
      double max_w = -std::numeric_limits<double>::infinity();
      for (auto& s : b.samples) {
        const double expected = (s.position - sensor).norm();
        s.log_weight += -0.5 * std::pow((range - expected) / sigma, 2);
        max_w = std::max(max_w, s.log_weight);
      }
      std::vector<double> lw(b.samples.size());
      for (std::size_t i = 0; i < lw.size(); ++i) lw[i] = b.samples[i].log_weight;
      if (insert_options.mc_perform_resampling) {
        const std::vector<double> w = weights_from_log_weights(lw);
        double sum_w2 = 0.0;
        for (double wi : w) sum_w2 += wi * wi;
        const double ess = 1.0 / (sum_w2 * static_cast<double>(w.size()));  // in (0, 1]
        if (ess < 0.5) {
          // Systematic resampling (Kitagawa 1996), then jitter against
          // sample impoverishment.
          const std::size_t n = w.size();
          std::vector<BeaconSample> out;
          out.reserve(n);
          const double step = 1.0 / static_cast<double>(n);
          double u = std::uniform_real_distribution<double>(0.0, step)(rng_);
          double cum = w[0];
          std::size_t j = 0;
          for (std::size_t i = 0; i < n; ++i) {
            while (u > cum && j + 1 < n) cum += w[++j];
            out.push_back({b.samples[j].position, 0.0});
            u += step;
          }
          std::normal_distribution<double> noise(0.0, insert_options.mc_after_resampling_noise);
          const bool flat = is_2d(insert_options);
          for (auto& s : out) {
            s.position.x() += noise(rng_);
            s.position.y() += noise(rng_);
            if (!flat) s.position.z() += noise(rng_);
          }
          b.samples = std::move(out);
        }
      } else {
        std::erase_if(b.samples, [&](const BeaconSample& s) {
          return s.log_weight < max_w - insert_options.mc_threshold_negligible;
        });
      }
      lw.resize(b.samples.size());
      for (std::size_t i = 0; i < lw.size(); ++i) lw[i] = b.samples[i].log_weight;
      normalize_log_weights(lw);
      for (std::size_t i = 0; i < lw.size(); ++i) b.samples[i].log_weight = lw[i];
      PointGaussian3 g = b.moments();
      if (max_axis_std(g.covariance) < insert_options.mc_max_std_to_gauss) {
        if (g.covariance.topLeftCorner<2, 2>().determinant() == 0.0) {
          // Guarantee a usable covariance (as MRPT).
          g.covariance = Eigen::Matrix3d::Identity() * (0.01 * 0.01);
          if (is_2d(insert_options)) g.covariance(2, 2) = 0.0;
        }
        b.kind = BeaconPdfKind::Gaussian;
        b.gaussian = g;
        b.samples.clear();
      }
      break;
    }
    case BeaconPdfKind::Gaussian:
      ekf_range_update(b.gaussian, sensor, range, var_r, nullptr);
      break;
    case BeaconPdfKind::SumOfGaussians: {
      // Per-mode EKF and reweighting by the predicted range likelihood
      // (Blanco et al., IROS 2008, Eqs. 9-10).
      double max_w = -std::numeric_limits<double>::infinity();
      for (auto& m : b.modes) {
        double ll = 0.0;
        ekf_range_update(m.gaussian, sensor, range, var_r, &ll);
        m.log_weight += ll;
        max_w = std::max(max_w, m.log_weight);
      }
      std::erase_if(b.modes, [&](const BeaconMode& m) {
        return max_w - m.log_weight > insert_options.sog_threshold_negligible;
      });
      for (auto& m : b.modes) m.log_weight -= max_w;
      const PointGaussian3 g = b.moments();
      if (max_axis_std(g.covariance) < 0.10) {  // MRPT's fixed collapse threshold
        b.kind = BeaconPdfKind::Gaussian;
        b.gaussian = g;
        b.modes.clear();
      }
      break;
    }
  }
}

bool BeaconMap::can_compute_likelihood(const Observation& observation) const {
  return dynamic_cast<const BeaconRanges*>(&observation) != nullptr;
}

double BeaconMap::log_likelihood(const Observation& observation, const Pose3& T_map_robot) const {
  const auto* o = dynamic_cast<const BeaconRanges*>(&observation);
  if (o == nullptr) return 0.0;
  const double sigma = likelihood_options.range_std;
  ROVE_CHECK_MSG(sigma > 0, "rangeStd must be > 0, got {}", sigma);
  const double var_r = sigma * sigma;
  double ret = 0.0;
  for (const auto& r : o->readings) {
    const Beacon* b = find(r.beacon_id);
    const double range = r.range;
    if (b != nullptr && range > 0.0 && std::isfinite(range)) {
      const Eigen::Vector3d sensor = robot_to_map(T_map_robot, r.position_on_robot);
      switch (b->kind) {
        case BeaconPdfKind::MonteCarlo: {
          std::vector<double> lw, ll;
          lw.reserve(b->samples.size());
          ll.reserve(b->samples.size());
          for (const auto& s : b->samples) {
            const double expected = (s.position - sensor).norm();
            lw.push_back(s.log_weight);
            ll.push_back(-0.5 * std::pow((range - expected) / sigma, 2));
          }
          if (!lw.empty()) ret += average_log_likelihood_log_weights(lw, ll);
          break;
        }
        case BeaconPdfKind::Gaussian: {
          double expected = 0.0, var_z = var_r;
          Eigen::RowVector3d H;
          if (!range_model(b->gaussian, sensor, var_r, expected, H, var_z)) var_z = var_r;
          ret += -0.5 * (range - expected) * (range - expected) / var_z;
          break;
        }
        case BeaconPdfKind::SumOfGaussians: {
          std::vector<double> lw, ll;
          for (const auto& m : b->modes) {
            double expected = 0.0, var_z = var_r;
            Eigen::RowVector3d H;
            if (!range_model(m.gaussian, sensor, var_r, expected, H, var_z)) var_z = var_r;
            lw.push_back(m.log_weight);
            ll.push_back(-0.5 * (range - expected) * (range - expected) / var_z);
          }
          if (!lw.empty()) ret += average_log_likelihood_log_weights(lw, ll);
          break;
        }
      }
    } else if (o->max_sensor_distance != o->min_sensor_distance) {
      // Unknown beacon or unusable range: uniform over the sensor's span.
      ret += std::log(1.0 / std::abs(static_cast<double>(o->max_sensor_distance) -
                                     o->min_sensor_distance));
    }
  }
  return ret;
}

MapBounds BeaconMap::bounding_box() const {
  MapBounds box;
  for (const auto& b : beacons_) box.extend(b.moments().mean);
  return box;
}

MapStatistics BeaconMap::statistics() const {
  MapStatistics s;
  s.elements = beacons_.size();
  s.unit = "beacons";
  s.bounds = bounding_box();
  return s;
}

}  // namespace rove
