#include "rove/slam/ekf_slam_options.h"

#include <cmath>

#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// MRPT's TKFMethod.
enum class KfMethod : std::uint8_t { Naive = 0, AlaDavison = 1, IkfFull = 2, Ikf = 3 };

std::vector<double> default_stds(int dim) {
  if (dim == 2) return {0.10, 0.10, 4.0 * kDeg};
  return {0.10, 0.10, 0.10, 0.10, 0.10, 0.10};  // 2 × MRPT's 0.05 per quaternion component
}

// MRPT's stds_Q_no_odo as the right-tangent stds of a `dim`-D robot.
std::vector<double> read_stds_no_odometry(const ConfigSection& s, int dim) {
  if (!s.has("stds_Q_no_odo")) return default_stds(dim);
  const std::vector<double> v = s.get_vector<double>("stds_Q_no_odo", {});
  const std::size_t expected = dim == 2 ? 3 : 7;
  if (v.size() != expected) {
    s.fail("stds_Q_no_odo",
           fmt::format("{} values given; a {}-D robot takes {} ({})", v.size(), dim, expected,
                       dim == 2 ? "x y phi_deg" : "x y z qr qx qy qz"));
  }
  for (double x : v) {
    if (!(x >= 0.0) || !std::isfinite(x)) {
      s.fail("stds_Q_no_odo", fmt::format("{} is not a standard deviation (>= 0)", x));
    }
  }
  if (dim == 2) return {v[0], v[1], v[2] * kDeg};
  return {v[0], v[1], v[2], 2.0 * v[4], 2.0 * v[5], 2.0 * v[6]};
}

}  // namespace

std::string_view to_string(EkfSlamUpdate update) noexcept {
  return update == EkfSlamUpdate::Batch ? "batch" : "sequential";
}

EkfSlamOptions EkfSlamOptions::defaults(int dim) {
  ROVE_CHECK_MSG(dim == 2 || dim == 3, "dimension {} is neither 2 nor 3", dim);
  EkfSlamOptions o;
  o.stds_no_odometry = default_stds(dim);
  return o;
}

EkfSlamOptions EkfSlamOptions::from_config(const ConfigSection& s, const ConfigSection& kf,
                                           int dim) {
  EkfSlamOptions o = defaults(dim);
  o.stds_no_odometry = read_stds_no_odometry(s, dim);
  o.std_sensor_range = s.get_in_range("std_sensor_range", o.std_sensor_range, 1e-12, 1e6);
  o.std_sensor_yaw = s.get_in_range("std_sensor_yaw_deg", o.std_sensor_yaw / kDeg, 1e-12, 180.0) *
                     kDeg;
  o.std_sensor_pitch =
      s.get_in_range("std_sensor_pitch_deg", o.std_sensor_pitch / kDeg, 1e-12, 180.0) * kDeg;
  o.std_odometry_z_additional =
      s.get_in_range("std_odo_z_additional", o.std_odometry_z_additional, 0.0, 1e6);
  o.force_ignore_odometry = s.get<bool>("force_ignore_odometry", o.force_ignore_odometry);
  o.use_landmark_ids = s.get<bool>("use_landmark_ids", o.use_landmark_ids);
  o.quantiles = s.get_in_range("quantiles_3D_representation", o.quantiles, 1e-3, 1e3);
  o.data_association = DataAssociationOptions::from_config(s);
  s.ignore({"stdXY_no_odo", "stdPhi_no_odo_deg"},
           "MRPT 2.5 no longer reads it (its motion noise without odometry is stds_Q_no_odo)");
  s.ignore({"create_simplemap"}, "rove's kf-slam writes no simplemap");
  s.ignore({"doPartitioningExperiment", "partitioningMethod", "partitionThreshold",
            "useMapMatching", "minimumNumberElementsEachCluster", "maxKeyFrameDistanceToEval",
            "forceBisectionOnly", "simil_method", "maxDistForCorrespondence", "debugSaveAllEigenvectors",
            "minDistForCorrespondence", "useMapMatching"},
           "MRPT's map-partitioning experiment (it does not change the estimate) is not part of "
           "rove");

  if (kf.has("method")) {
    const KfMethod m = kf.get_enum<KfMethod>("method", KfMethod::Naive,
                                             {{"kfEKFNaive", KfMethod::Naive},
                                              {"kfEKFAlaDavison", KfMethod::AlaDavison},
                                              {"kfIKFFull", KfMethod::IkfFull},
                                              {"kfIKF", KfMethod::Ikf}});
    if (m == KfMethod::IkfFull || m == KfMethod::Ikf) {
      kf.fail("method", "MRPT's iterated filters (kfIKFFull, kfIKF) are not implemented in rove; "
                        "use kfEKFNaive or kfEKFAlaDavison");
    }
    o.update = static_cast<EkfSlamUpdate>(m);
  }
  kf.ignore({"verbose", "enable_profiler", "IKF_iterations", "use_analytic_transition_jacobian",
             "use_analytic_observation_jacobian", "debug_verify_analytic_jacobians",
             "debug_verify_analytic_jacobians_threshold"},
            "rove always uses its analytic Jacobians and has no per-filter log or profiler");
  o.check(dim);
  return o;
}

void EkfSlamOptions::check(int dim) const {
  ROVE_CHECK_MSG(dim == 2 || dim == 3, "dimension {} is neither 2 nor 3", dim);
  ROVE_CHECK_EQ(stds_no_odometry.size(), static_cast<std::size_t>(dim == 2 ? 3 : 6));
  for (double x : stds_no_odometry) ROVE_CHECK_MSG(x >= 0.0 && std::isfinite(x), "std {} < 0", x);
  ROVE_CHECK_MSG(std_sensor_range > 0.0 && std::isfinite(std_sensor_range),
                 "std_sensor_range {} not > 0", std_sensor_range);
  ROVE_CHECK_MSG(std_sensor_yaw > 0.0 && std::isfinite(std_sensor_yaw), "std_sensor_yaw {} not > 0",
                 std_sensor_yaw);
  ROVE_CHECK_MSG(dim == 2 || (std_sensor_pitch > 0.0 && std::isfinite(std_sensor_pitch)),
                 "std_sensor_pitch {} not > 0", std_sensor_pitch);
  ROVE_CHECK_MSG(std_odometry_z_additional >= 0.0 && std::isfinite(std_odometry_z_additional),
                 "std_odometry_z_additional {} < 0", std_odometry_z_additional);
  ROVE_CHECK_MSG(quantiles > 0.0 && std::isfinite(quantiles), "quantiles {} not > 0", quantiles);
  data_association.check();
}

}  // namespace rove
