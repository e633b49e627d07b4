#include "rove/maps/landmark_map.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/poses/angle.h"

namespace rove {

namespace {

constexpr std::string_view kImageFeatures =
    "image-feature (SIFT) landmarks are not implemented in rove";
constexpr std::string_view kOtherSensors =
    "GPS, robot-pose and laser-scan landmark likelihoods are not implemented in rove";

/// Pseudo-inverse of a symmetric positive semi-definite matrix (a 2D map has
/// zero z variance, so innovation covariances may be singular).
Eigen::Matrix3d psd_pseudo_inverse(const Eigen::Matrix3d& S) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S);
  const Eigen::Vector3d ev = es.eigenvalues();
  const double tol = std::max(1e-12, 1e-12 * ev.cwiseAbs().maxCoeff());
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) inv(i) = ev(i) > tol ? 1.0 / ev(i) : 0.0;
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

/// Kalman fusion of two independent Gaussian estimates of the same point
/// (the product of the densities, in covariance form so that singular
/// covariances are handled).
void fuse_gaussians(PointGaussian3& a, const PointGaussian3& b) {
  const Eigen::Matrix3d K = a.covariance * psd_pseudo_inverse(a.covariance + b.covariance);
  a.mean += K * (b.mean - a.mean);
  a.covariance = ((Eigen::Matrix3d::Identity() - K) * a.covariance).eval();
  a.covariance = (0.5 * (a.covariance + a.covariance.transpose())).eval();
}

double mahalanobis2(const PointGaussian3& a, const PointGaussian3& b) {
  const Eigen::Vector3d d = b.mean - a.mean;
  return d.dot(psd_pseudo_inverse(a.covariance + b.covariance) * d);
}

/// Predicted (range, yaw, pitch) of a map point seen from T_map_sensor, and
/// its Jacobian with respect to the point (map frame).
Eigen::Vector3d predict_rng_yaw_pitch(const Eigen::Vector3d& p_map, const Pose3& T_map_sensor,
                                      Eigen::Matrix3d& H) {
  const Eigen::Matrix3d& R = T_map_sensor.rotation();
  const Eigen::Vector3d p = R.transpose() * (p_map - T_map_sensor.translation());
  const double rxy2 = p.x() * p.x() + p.y() * p.y();
  const double rxy = std::sqrt(rxy2);
  const double r = p.norm();
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();  // d(r, yaw, pitch) / d p_sensor
  if (r > 1e-12) J.row(0) = p.transpose() / r;
  if (rxy2 > 1e-24) {
    J(1, 0) = -p.y() / rxy2;
    J(1, 1) = p.x() / rxy2;
    // pitch = -atan2(z, rxy)
    const double r2 = r * r;
    J(2, 0) = p.z() * p.x() / (r2 * rxy);
    J(2, 1) = p.z() * p.y() / (r2 * rxy);
    J(2, 2) = -rxy / r2;
  }
  H = J * R.transpose();
  return {r, std::atan2(p.y(), p.x()), -std::atan2(p.z(), rxy)};
}

double uniform_log_density(double lo, double hi) {
  if (hi == lo) return 0.0;
  return std::log(1.0 / std::abs(hi - lo));
}

}  // namespace

PointGaussian3 bearing_range_to_point(const LandmarkMeasurement& m, const Eigen::Matrix3d& Sigma,
                                      const Pose3& T_map_sensor) {
  ROVE_CHECK_FINITE(m.range);
  ROVE_CHECK_FINITE(m.yaw);
  ROVE_CHECK_FINITE(m.pitch);
  const double r = m.range, yaw = m.yaw, pitch = m.pitch;
  const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
  const Eigen::Vector3d p_s(r * cp * cy, r * cp * sy, -r * sp);
  Eigen::Matrix3d J;
  J.col(0) << cp * cy, cp * sy, -sp;
  J.col(1) << -r * cp * sy, r * cp * cy, 0.0;
  J.col(2) << -r * sp * cy, -r * sp * sy, -r * cp;
  const Eigen::Matrix3d& R = T_map_sensor.rotation();
  PointGaussian3 g;
  g.mean = R * p_s + T_map_sensor.translation();
  g.covariance = R * J * Sigma * J.transpose() * R.transpose();
  g.covariance = (0.5 * (g.covariance + g.covariance.transpose())).eval();
  return g;
}

LandmarkMapCreationOptions LandmarkMapCreationOptions::from_config(const ConfigSection& s) {
  LandmarkMapCreationOptions o;
  const int n = s.get<int>("nBeacons", 0);
  if (n < 0) s.fail("nBeacons", fmt::format("must be >= 0, got {}", n));
  for (int q = 1; q <= n; ++q) {
    Landmark l;
    l.id = s.get<int>(fmt::format("beacon_{:03}_ID", q), 0);
    l.position.mean.x() = s.get<double>(fmt::format("beacon_{:03}_x", q), 0.0);
    l.position.mean.y() = s.get<double>(fmt::format("beacon_{:03}_y", q), 0.0);
    l.position.mean.z() = s.get<double>(fmt::format("beacon_{:03}_z", q), 0.0);
    o.initial.push_back(l);
  }
  return o;
}

LandmarkMapInsertOptions LandmarkMapInsertOptions::from_config(const ConfigSection& s) {
  LandmarkMapInsertOptions o;
  o.insert_bearing_range = s.get<bool>("insert_bearing_range", o.insert_bearing_range);
  o.association_gate_chi2 =
      s.get_in_range("association_gate_chi2", o.association_gate_chi2, 0.0, 1e300);
  if (s.get<bool>("insert_Landmarks_from_range_scans", true) &&
      s.has("insert_Landmarks_from_range_scans")) {
    s.ignore({"insert_Landmarks_from_range_scans"}, kOtherSensors);
  }
  const ConfigSection& m = s;
  m.ignore({"insert_SIFTs_from_monocular_images", "insert_SIFTs_from_stereo_images",
            "SiftCorrRatioThreshold", "SiftLikelihoodThreshold", "SiftEDDThreshold",
            "SIFTMatching3DMethod", "SIFTLikelihoodMethod", "SIFTsLoadDistanceOfTheMean",
            "SIFTsLoadEllipsoidWidth", "SIFTs_stdXY", "SIFTs_stdDisparity",
            "SIFTs_numberOfKLTKeypoints", "SIFTs_stereo_maxDepth", "SIFTs_epipolar_TH",
            "PLOT_IMAGES", "featsType", "FIND_SUBPIXEL", "addNewFeatures", "patchSize", "useMask"},
           kImageFeatures);
  for (std::string_view p :
       {"AKAZEOptions.", "BLDOptions.", "FASTOptions.", "KLTOptions.", "LATCHOptions.",
        "LSDOptions.", "LogPolarImagesOptions.", "ORBOptions.", "PolarImagesOptions.",
        "SIFTOptions.", "SURFOptions.", "SpinImagesOptions.", "harrisOptions."}) {
    m.ignore_prefix(p, kImageFeatures);
  }
  return o;
}

LandmarkMapLikelihoodOptions LandmarkMapLikelihoodOptions::from_config(const ConfigSection& s) {
  LandmarkMapLikelihoodOptions o;
  o.beacon_ranges_std = s.get_in_range("beaconRangesStd", o.beacon_ranges_std, 1e-12, 1e9);
  o.beacon_ranges_use_observation_std =
      s.get<bool>("beaconRangesUseObservationStd", o.beacon_ranges_use_observation_std);
  const ConfigSection& m = s;
  m.ignore({"rangeScan2D_decimation", "extRobotPoseStd", "GPSOriginLatitude",
            "GPSOriginLongitude", "GPSOriginAltitude", "GPSOriginAngle", "GPSOriginXshift",
            "GPSOriginYshift", "GPSOriginMinSat", "GPSSigma"},
           kOtherSensors);
  m.ignore({"SIFTs_sigma_euclidean_dist", "SIFTs_sigma_descriptor_dist", "SIFTs_mahaDist_std",
            "SIFTs_decimation", "SIFTnullCorrespondenceDistance", "featsType", "FIND_SUBPIXEL",
            "addNewFeatures", "patchSize", "useMask"},
           kImageFeatures);
  for (std::string_view p :
       {"AKAZEOptions.", "BLDOptions.", "FASTOptions.", "KLTOptions.", "LATCHOptions.",
        "LSDOptions.", "LogPolarImagesOptions.", "ORBOptions.", "PolarImagesOptions.",
        "SIFTOptions.", "SURFOptions.", "SpinImagesOptions.", "harrisOptions."}) {
    m.ignore_prefix(p, kImageFeatures);
  }
  // Keys of MRPT 1.x that MRPT 2.5.8 itself no longer reads.
  m.ignore({"alphaRatio", "beaconMaxRange"}, "not read by MRPT 2.x either");
  return o;
}

LandmarkMap::LandmarkMap(LandmarkMapCreationOptions creation, LandmarkMapInsertOptions io,
                         LandmarkMapLikelihoodOptions lo)
    : insert_options(io), likelihood_options(lo) {
  for (auto& l : creation.initial) add(std::move(l));
}

const Landmark* LandmarkMap::find(std::int32_t id) const noexcept {
  for (const auto& l : landmarks_) {
    if (l.id == id) return &l;
  }
  return nullptr;
}

Landmark* LandmarkMap::find_mutable(std::int32_t id) noexcept {
  for (auto& l : landmarks_) {
    if (l.id == id) return &l;
  }
  return nullptr;
}

void LandmarkMap::add(Landmark l) {
  ROVE_CHECK_FINITE(l.position.mean);
  ROVE_CHECK_FINITE(l.position.covariance);
  if (Landmark* e = find_mutable(l.id)) {
    *e = std::move(l);
  } else {
    landmarks_.push_back(std::move(l));
  }
}

bool LandmarkMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  const auto* o = dynamic_cast<const BearingRange*>(&observation);
  if (o == nullptr || !insert_options.insert_bearing_range) return false;
  const Pose3 T_map_sensor = T_map_robot + o->T_robot_sensor;
  for (std::size_t i = 0; i < o->measurements.size(); ++i) {
    const auto& m = o->measurements[i];
    if (!std::isfinite(m.range) || !std::isfinite(m.yaw) || !std::isfinite(m.pitch) ||
        !(m.range >= 0)) {
      throw InvalidArgument(fmt::format(
          "LandmarkMap::insert: measurement {} of sensor '{}' is not finite or has a negative "
          "range (range {}, yaw {}, pitch {})",
          i, o->sensor_label, m.range, m.yaw, m.pitch));
    }
    const PointGaussian3 g = bearing_range_to_point(m, o->measurement_covariance(i), T_map_sensor);
    Landmark* target = nullptr;
    if (m.landmark_id >= 0) {
      target = find_mutable(m.landmark_id);
    } else {
      double best = insert_options.association_gate_chi2;
      for (auto& l : landmarks_) {
        const double d2 = mahalanobis2(l.position, g);
        if (d2 <= best) {
          best = d2;
          target = &l;
        }
      }
    }
    if (target != nullptr) {
      fuse_gaussians(target->position, g);
      ++target->times_seen;
    } else {
      Landmark l;
      if (m.landmark_id >= 0) {
        l.id = m.landmark_id;
      } else {
        std::int32_t next = 0;
        for (const auto& e : landmarks_) next = std::max(next, e.id + 1);
        l.id = next;
      }
      l.position = g;
      l.times_seen = 1;
      landmarks_.push_back(std::move(l));
    }
  }
  return true;
}

bool LandmarkMap::can_compute_likelihood(const Observation& observation) const {
  return dynamic_cast<const BearingRange*>(&observation) != nullptr ||
         dynamic_cast<const BeaconRanges*>(&observation) != nullptr;
}

double LandmarkMap::log_likelihood(const Observation& observation,
                                   const Pose3& T_map_robot) const {
  if (const auto* o = dynamic_cast<const BeaconRanges*>(&observation)) {
    const double sigma = likelihood_options.beacon_ranges_use_observation_std
                             ? static_cast<double>(o->std_error)
                             : likelihood_options.beacon_ranges_std;
    ROVE_CHECK_MSG(sigma > 0, "beacon range std. dev. must be > 0, got {}", sigma);
    const double unif = uniform_log_density(o->min_sensor_distance, o->max_sensor_distance);
    double ret = 0.0;
    for (const auto& r : o->readings) {
      if (std::isnan(r.range)) continue;
      const Landmark* l = find(r.beacon_id);
      if (l == nullptr) {
        ret += unif;
        continue;
      }
      const Eigen::Vector3d sensor =
          T_map_robot.rotation() * r.position_on_robot + T_map_robot.translation();
      const double expected = (l->position.mean - sensor).norm();
      const double sensed = std::max(0.0, static_cast<double>(r.range));
      ret += -0.5 * std::pow((expected - sensed) / sigma, 2);
    }
    return ret;
  }
  const auto* o = dynamic_cast<const BearingRange*>(&observation);
  if (o == nullptr) return 0.0;
  const Pose3 T_map_sensor = T_map_robot + o->T_robot_sensor;
  const double unif = uniform_log_density(o->min_sensor_distance, o->max_sensor_distance);
  double ret = 0.0;
  for (std::size_t i = 0; i < o->measurements.size(); ++i) {
    const auto& m = o->measurements[i];
    if (!std::isfinite(m.range) || !std::isfinite(m.yaw) || !std::isfinite(m.pitch)) continue;
    const Eigen::Matrix3d Rm = o->measurement_covariance(i);
    const auto eval = [&](const Landmark& l) {
      Eigen::Matrix3d H;
      const Eigen::Vector3d z_hat = predict_rng_yaw_pitch(l.position.mean, T_map_sensor, H);
      const Eigen::Matrix3d S = H * l.position.covariance * H.transpose() + Rm;
      Eigen::Vector3d nu(m.range - z_hat(0), wrap_to_pi(static_cast<double>(m.yaw) - z_hat(1)),
                         wrap_to_pi(static_cast<double>(m.pitch) - z_hat(2)));
      // A zero-variance component (e.g. pitch of a planar sensor) carries no
      // information: drop it instead of dividing by zero.
      for (int k = 0; k < 3; ++k) {
        if (!(S(k, k) > 1e-18)) nu(k) = 0.0;
      }
      return -0.5 * nu.dot(psd_pseudo_inverse(S) * nu);
    };
    double best = -std::numeric_limits<double>::infinity();
    if (m.landmark_id >= 0) {
      if (const Landmark* l = find(m.landmark_id)) best = eval(*l);
    } else {
      for (const auto& l : landmarks_) best = std::max(best, eval(l));
    }
    ret += std::isfinite(best) ? best : unif;
  }
  return ret;
}

MapBounds LandmarkMap::bounding_box() const {
  MapBounds b;
  for (const auto& l : landmarks_) b.extend(l.position.mean);
  return b;
}

MapStatistics LandmarkMap::statistics() const {
  MapStatistics s;
  s.elements = landmarks_.size();
  s.unit = "landmarks";
  s.bounds = bounding_box();
  return s;
}

}  // namespace rove
