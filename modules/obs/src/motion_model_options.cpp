#include "rove/obs/motion_model_options.h"

#include <cmath>
#include <string>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

void check_param(double value, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(value) && value >= 0.0,
                 "motion model parameter {} = {} must be finite and >= 0", name, value);
}

// Reads `key` (if present) in file units, stores value·to_si in `out`.
void read_param(const ConfigSection& section, std::string_view key, double to_si, double& out) {
  if (!section.has(key)) return;
  const double v = section.get<double>(key, 0.0);
  if (!(std::isfinite(v) && v >= 0.0)) {
    section.fail(key, "must be finite and >= 0, found " + std::to_string(v));
  }
  out = v * to_si;
}

constexpr double kDeg = kPi / 180.0;  // radians per degree
constexpr double kPerDeg = 180.0 / kPi;  // (1/deg) -> (1/rad)

}  // namespace

void GaussianMotionOptions::check() const {
  check_param(a1_m_per_m, "a1");
  check_param(a2_m_per_rad, "a2");
  check_param(a3_rad_per_m, "a3");
  check_param(a4_rad_per_rad, "a4");
  check_param(min_std_xy_m, "minStdXY");
  check_param(min_std_phi_rad, "minStdPHI");
}

void ThrunMotionOptions::check() const {
  ROVE_CHECK_MSG(particle_count >= 1, "Thrun motion model: particle_count must be >= 1");
  check_param(alpha1_rot_rot, "alfa1_rot_rot");
  check_param(alpha2_rot_trans_rad_per_m, "alfa2_rot_trans");
  check_param(alpha3_trans_trans, "alfa3_trans_trans");
  check_param(alpha4_trans_rot_m_per_rad, "alfa4_trans_rot");
  check_param(additional_std_xy_m, "additional_std_XY");
  check_param(additional_std_phi_rad, "additional_std_phi");
}

void MotionModelOptions::check() const {
  gaussian.check();
  thrun.check();
}

MotionModelOptions MotionModelOptions::from_config(const ConfigSection& section) {
  MotionModelOptions o;
  o.model = section.get_enum<MotionModel>(
      "modelSelection", o.model,
      {{"mmGaussian", MotionModel::Gaussian}, {"mmThrun", MotionModel::Thrun}});
  // Gaussian model: a1 m/m, a2 m/deg, a3 deg/m, a4 deg/deg, minStdXY m, minStdPHI deg.
  read_param(section, "a1", 1.0, o.gaussian.a1_m_per_m);
  read_param(section, "a2", kPerDeg, o.gaussian.a2_m_per_rad);
  read_param(section, "a3", kDeg, o.gaussian.a3_rad_per_m);
  read_param(section, "a4", 1.0, o.gaussian.a4_rad_per_rad);
  read_param(section, "minStdXY", 1.0, o.gaussian.min_std_xy_m);
  read_param(section, "minStdPHI", kDeg, o.gaussian.min_std_phi_rad);
  // Thrun model: alfa1 deg/deg, alfa2 deg/m, alfa3 m/m, alfa4 m/deg, std m and deg.
  if (section.has("nParticlesCount")) {
    const unsigned n = section.get<unsigned>("nParticlesCount", 0);
    if (n == 0) section.fail("nParticlesCount", "must be >= 1");
    o.thrun.particle_count = n;
  }
  read_param(section, "alfa1_rot_rot", 1.0, o.thrun.alpha1_rot_rot);
  read_param(section, "alfa2_rot_trans", kDeg, o.thrun.alpha2_rot_trans_rad_per_m);
  read_param(section, "alfa3_trans_trans", 1.0, o.thrun.alpha3_trans_trans);
  read_param(section, "alfa4_trans_rot", kPerDeg, o.thrun.alpha4_trans_rot_m_per_rad);
  read_param(section, "additional_std_XY", 1.0, o.thrun.additional_std_xy_m);
  read_param(section, "additional_std_phi", kDeg, o.thrun.additional_std_phi_rad);
  return o;
}

void save(OutArchive& ar, const GaussianMotionOptions& o) {
  write_version(ar, 1);
  for (const double v : {o.a1_m_per_m, o.a2_m_per_rad, o.a3_rad_per_m, o.a4_rad_per_rad,
                         o.min_std_xy_m, o.min_std_phi_rad}) {
    ar.write_scalar(v);
  }
}

void load(InArchive& ar, GaussianMotionOptions& o) {
  read_version(ar, "GaussianMotionOptions", 1);
  for (double* v : {&o.a1_m_per_m, &o.a2_m_per_rad, &o.a3_rad_per_m, &o.a4_rad_per_rad,
                    &o.min_std_xy_m, &o.min_std_phi_rad}) {
    *v = ar.read_scalar<double>("GaussianMotionOptions");
  }
}

void save(OutArchive& ar, const ThrunMotionOptions& o) {
  write_version(ar, 1);
  ar.write_scalar(o.particle_count);
  for (const double v : {o.alpha1_rot_rot, o.alpha2_rot_trans_rad_per_m, o.alpha3_trans_trans,
                         o.alpha4_trans_rot_m_per_rad, o.additional_std_xy_m,
                         o.additional_std_phi_rad}) {
    ar.write_scalar(v);
  }
}

void load(InArchive& ar, ThrunMotionOptions& o) {
  read_version(ar, "ThrunMotionOptions", 1);
  o.particle_count = ar.read_scalar<std::uint32_t>("particle_count");
  for (double* v : {&o.alpha1_rot_rot, &o.alpha2_rot_trans_rad_per_m, &o.alpha3_trans_trans,
                    &o.alpha4_trans_rot_m_per_rad, &o.additional_std_xy_m,
                    &o.additional_std_phi_rad}) {
    *v = ar.read_scalar<double>("ThrunMotionOptions");
  }
}

void save(OutArchive& ar, const MotionModelOptions& o) {
  write_version(ar, 1);
  ar.write_scalar(static_cast<std::uint8_t>(o.model));
  save(ar, o.gaussian);
  save(ar, o.thrun);
}

void load(InArchive& ar, MotionModelOptions& o) {
  read_version(ar, "MotionModelOptions", 1);
  const std::uint64_t at = ar.offset();
  const auto m = ar.read_scalar<std::uint8_t>("motion model");
  if (m > static_cast<std::uint8_t>(MotionModel::Thrun)) {
    ar.fail_at(at, "motion model", "unknown motion model " + std::to_string(m));
  }
  o.model = static_cast<MotionModel>(m);
  load(ar, o.gaussian);
  load(ar, o.thrun);
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    ar.fail_at(at, "MotionModelOptions", e.message());
  }
}

}  // namespace rove
