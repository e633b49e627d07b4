#pragma once
/// \file
/// Options of EKF landmark SLAM (rove/slam/ekf_slam.h), read from MRPT's
/// kf-slam configuration sections unchanged:
/// - [RangeBearingKFSLAM]: `stds_Q_no_odo`, `std_sensor_range` (m),
///   `std_sensor_yaw_deg`, `std_sensor_pitch_deg`, `std_odo_z_additional`
///   (m), `force_ignore_odometry`, `data_assoc_*`
///   (DataAssociationOptions::from_config), `quantiles_3D_representation`;
///   rove's `use_landmark_ids` (false: associate by the data-association
///   method even when the readings carry IDs);
/// - [RangeBearingKFSLAM_KalmanFilter]: `method` (kfEKFNaive = 0: one update
///   with every reading of a frame; kfEKFAlaDavison = 1: one update per
///   landmark, relinearized after each; MRPT's iterated variants kfIKFFull
///   and kfIKF are rejected with a ConfigError).
/// Keys MRPT's files carry that change nothing in rove (`verbose`, the
/// Jacobian switches, the partitioning experiment, the old
/// `stdXY_no_odo`/`stdPhi_no_odo_deg` that MRPT 2.5 no longer reads) are
/// listed as ignored.

#include <cstdint>
#include <numbers>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/slam/data_association.h"

namespace rove {

/// How the measurements of a frame update the filter (MRPT's TKFMethod).
enum class EkfSlamUpdate : std::uint8_t {
  /// kfEKFNaive: one update with every paired reading of the frame.
  Batch = 0,
  /// kfEKFAlaDavison: one update per paired landmark, relinearized after each.
  Sequential = 1,
};

/// "batch" or "sequential".
std::string_view to_string(EkfSlamUpdate update) noexcept;

/// Options of EkfSlam (see the file comment for the config keys).
struct EkfSlamOptions {
  /// How a frame updates the filter (`method`). Default Batch.
  EkfSlamUpdate update = EkfSlamUpdate::Batch;
  /// Motion noise when a step has no odometry or force_ignore_odometry is
  /// set: standard deviations over the robot pose's right tangent
  /// (2D: ρx, ρy in m and θ in rad; 3D: ρx, ρy, ρz in m and ωx, ωy, ωz in
  /// rad). Read from MRPT's `stds_Q_no_odo`: in 2D (x, y, phi_deg), phi in
  /// degrees; in 3D MRPT's 7 values over (x, y, z, qr, qx, qy, qz), a
  /// quaternion component's std σ becoming 2σ rad about its axis (q ≈ (1,
  /// ω/2) near the identity; qr's value is not used). Defaults MRPT's:
  /// 0.1 m, 4° (2D) and 0.1 m, 0.1 rad (3D).
  std::vector<double> stds_no_odometry;
  /// Range noise std, m (`std_sensor_range`). Default 0.01.
  double std_sensor_range = 0.01;
  /// Yaw noise std, rad (`std_sensor_yaw_deg`, degrees). Default 0.2°.
  double std_sensor_yaw = 0.2 * std::numbers::pi / 180.0;
  /// Pitch noise std, rad (`std_sensor_pitch_deg`, degrees; 3D). Default 0.2°.
  double std_sensor_pitch = 0.2 * std::numbers::pi / 180.0;
  /// Std added to the odometry's z, m (`std_odo_z_additional`; 3D). Default 0.
  double std_odometry_z_additional = 0.0;
  /// Ignore the log's odometry and predict with stds_no_odometry
  /// (`force_ignore_odometry`). Default false.
  bool force_ignore_odometry = false;
  /// Readings with a landmark ID are paired by it (`use_landmark_ids`,
  /// rove). Default true, as MRPT.
  bool use_landmark_ids = true;
  /// Data association of readings without an ID.
  DataAssociationOptions data_association;
  /// Ellipse scale of pictures, in standard deviations
  /// (`quantiles_3D_representation`). Default 3.
  double quantiles = 3.0;

  /// MRPT's defaults for a `dim`-D robot (2 or 3): stds_no_odometry set.
  static EkfSlamOptions defaults(int dim);
  /// Reads [RangeBearingKFSLAM] (`slam`) and [RangeBearingKFSLAM_KalmanFilter]
  /// (`kf`) for a `dim`-D robot. Throws ConfigError naming the key for a
  /// malformed or out-of-range value.
  static EkfSlamOptions from_config(const ConfigSection& slam, const ConfigSection& kf, int dim);
  /// Throws InvalidArgument naming the first field out of range for a
  /// `dim`-D robot.
  void check(int dim) const;
};

}  // namespace rove
