#pragma once
/// \file
/// Options of the two probabilistic odometry motion models of MRPT's
/// CActionRobotMovement2D (TMotionModelOptions), with MRPT 2.5.8's
/// defaults, stored in SI units, and loadable from an INI section.
///
/// INI keys are MRPT's member names; angles there are in degrees, so a file
/// reads as MRPT documents the parameters (m/deg, deg/m, deg):
///
///   [MotionModel]
///   modelSelection = mmGaussian    # or mmThrun
///   a1 = 0.01                      # m/m
///   a2 = 0.001                     # m/deg
///   a3 = 1.0                       # deg/m
///   a4 = 0.05                      # deg/deg
///   minStdXY = 0.01                # m
///   minStdPHI = 0.2                # deg
///   nParticlesCount = 300
///   alfa1_rot_rot = 0.05           # deg/deg
///   alfa2_rot_trans = 4.0          # deg/m
///   alfa3_trans_trans = 0.01       # m/m
///   alfa4_trans_rot = 0.0001       # m/deg
///   additional_std_XY = 0.001      # m
///   additional_std_phi = 0.05      # deg
///
/// MRPT itself has no loader for these options; its pf-localization app
/// reads `minStdXY` (m) and `minStdPHI` (deg) from [DummyOdometryParams],
/// and the other names are MRPT's struct members.

#include <cstdint>
#include <string_view>

#include "rove/core/config_section.h"
#include "rove/serialization/archive.h"

namespace rove {

/// Parameters of the Gaussian motion model (gaussian_motion_model).
/// Defaults are MRPT 2.5.8's (CActionRobotMovement2D.h); MRPT's tutorial
/// page quotes older values (α1 = 0.05 m/m, α3 = 5°/m), which are not what
/// MRPT's code uses.
struct GaussianMotionOptions {
  /// α1: std of x, y per meter traveled, m/m (MRPT `a1`, default 0.01).
  double a1_m_per_m = 0.01;
  /// α2: std of x, y per radian turned, m/rad (MRPT `a2`, default
  /// 0.001 m/deg = 0.0572958 m/rad).
  double a2_m_per_rad = 0.001 * 180.0 / 3.14159265358979323846;
  /// α3: std of phi per meter traveled, rad/m (MRPT `a3`, default 1°/m).
  double a3_rad_per_m = 1.0 * 3.14159265358979323846 / 180.0;
  /// α4: std of phi per radian turned, rad/rad (MRPT `a4`, default 0.05).
  double a4_rad_per_rad = 0.05;
  /// Additional std of x and y, meters (MRPT `minStdXY`, default 0.01).
  double min_std_xy_m = 0.01;
  /// Additional std of phi, radians (MRPT `minStdPHI`, default 0.2°).
  double min_std_phi_rad = 0.2 * 3.14159265358979323846 / 180.0;

  /// Throws InvalidArgument unless every parameter is finite and >= 0.
  void check() const;
  /// Exact equality.
  friend bool operator==(const GaussianMotionOptions&, const GaussianMotionOptions&) = default;
};

/// Parameters of Thrun's sampling model as MRPT implements it
/// (sample_thrun_motion). Defaults are MRPT 2.5.8's.
struct ThrunMotionOptions {
  /// Particles in the sampled PDF (MRPT `nParticlesCount`, default 300).
  std::uint32_t particle_count = 300;
  /// α1: std of each rotation per radian of that rotation, rad/rad
  /// (MRPT `alfa1_rot_rot`, default 0.05).
  double alpha1_rot_rot = 0.05;
  /// α2: std of each rotation per meter traveled, rad/m (MRPT
  /// `alfa2_rot_trans`, default 4°/m).
  double alpha2_rot_trans_rad_per_m = 4.0 * 3.14159265358979323846 / 180.0;
  /// α3: std of the translation per meter, m/m (MRPT `alfa3_trans_trans`,
  /// default 0.01).
  double alpha3_trans_trans = 0.01;
  /// α4: std of the translation per radian turned, m/rad (MRPT
  /// `alfa4_trans_rot`, default 0.0001 m/deg).
  double alpha4_trans_rot_m_per_rad = 0.0001 * 180.0 / 3.14159265358979323846;
  /// Additional std added to x and y, meters (MRPT `additional_std_XY`,
  /// default 0.001).
  double additional_std_xy_m = 0.001;
  /// Additional std added to phi, radians (MRPT `additional_std_phi`,
  /// default 0.05°).
  double additional_std_phi_rad = 0.05 * 3.14159265358979323846 / 180.0;

  /// Throws InvalidArgument unless every parameter is finite and >= 0 and
  /// particle_count >= 1.
  void check() const;
  /// Exact equality.
  friend bool operator==(const ThrunMotionOptions&, const ThrunMotionOptions&) = default;
};

/// Which motion model RobotMovement2D uses to sample and give its PDF.
enum class MotionModel : std::uint8_t {
  Gaussian = 0,  ///< MRPT's mmGaussian
  Thrun = 1,     ///< MRPT's mmThrun
};

/// Both models' parameters and the selected model (MRPT's
/// TMotionModelOptions).
struct MotionModelOptions {
  /// The model used (MRPT `modelSelection`, default Gaussian).
  MotionModel model = MotionModel::Gaussian;
  /// Gaussian model parameters.
  GaussianMotionOptions gaussian;
  /// Thrun model parameters.
  ThrunMotionOptions thrun;

  /// Defaults overridden by the keys listed in this file's comment that are
  /// present in `section`. Throws ConfigError (file, section, key) on a
  /// malformed, negative or non-finite value, an unknown model name, or
  /// nParticlesCount = 0. Other keys are left unread (the caller decides
  /// whether the section may hold more: ConfigSection::check_all_read).
  static MotionModelOptions from_config(const ConfigSection& section);

  /// Throws InvalidArgument unless both parameter sets pass their checks.
  void check() const;
  /// Exact equality.
  friend bool operator==(const MotionModelOptions&, const MotionModelOptions&) = default;
};

/// Writes GaussianMotionOptions (versioned record).
void save(OutArchive& ar, const GaussianMotionOptions& o);
/// Reads GaussianMotionOptions written by save.
void load(InArchive& ar, GaussianMotionOptions& o);
/// Writes ThrunMotionOptions (versioned record).
void save(OutArchive& ar, const ThrunMotionOptions& o);
/// Reads ThrunMotionOptions written by save.
void load(InArchive& ar, ThrunMotionOptions& o);
/// Writes MotionModelOptions (versioned record).
void save(OutArchive& ar, const MotionModelOptions& o);
/// Reads MotionModelOptions written by save.
void load(InArchive& ar, MotionModelOptions& o);

}  // namespace rove
