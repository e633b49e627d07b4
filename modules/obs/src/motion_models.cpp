#include "rove/obs/motion_models.h"

#include <array>
#include <cmath>

#include "rove/core/check.h"
#include "rove/poses/angle.h"

namespace rove {

Pose2Gaussian gaussian_motion_model(const Pose2& u, const GaussianMotionOptions& o) {
  o.check();
  // Standard deviations grow linearly with distance and turn (MRPT's
  // computeFromOdometry_modelGaussian; Eliazar & Parr 2004).
  const double d = u.norm();
  const double turn = std::abs(u.phi());
  const double s_xy = o.min_std_xy_m + o.a1_m_per_m * d + o.a2_m_per_rad * turn;
  const double s_phi = o.min_std_phi_rad + o.a3_rad_per_m * d + o.a4_rad_per_rad * turn;
  const Eigen::Vector3d sigma2(s_xy * s_xy, s_xy * s_xy, s_phi * s_phi);

  // J: rotation by Δφ/2 in the xy block, and MRPT's third column.
  const double c = std::cos(u.phi() / 2.0), s = std::sin(u.phi() / 2.0);
  Eigen::Matrix3d J;
  J << c, -s, -s * u.x() - c * u.y(),
       s, c, c * u.x() - s * u.y(),
       0.0, 0.0, 1.0;
  const Eigen::Matrix3d C = J * sigma2.asDiagonal() * J.transpose();
  return Pose2Gaussian(u, C);
}

ThrunMotionSampler::ThrunMotionSampler(const Pose2& u, const ThrunMotionOptions& o)
    : add_xy_(o.additional_std_xy_m), add_phi_(o.additional_std_phi_rad) {
  o.check();
  // Probabilistic Robotics, table 5.6, with MRPT's linear standard deviations.
  rot1_ = (u.x() != 0.0 || u.y() != 0.0) ? std::atan2(u.y(), u.x()) : 0.0;
  trans_ = u.norm();
  rot2_ = wrap_to_pi(u.phi() - rot1_);
  s_rot1_ = o.alpha1_rot_rot * std::abs(rot1_) + o.alpha2_rot_trans_rad_per_m * trans_;
  s_trans_ = o.alpha3_trans_trans * trans_ +
             o.alpha4_trans_rot_m_per_rad * (std::abs(rot1_) + std::abs(rot2_));
  s_rot2_ = o.alpha1_rot_rot * std::abs(rot2_) + o.alpha2_rot_trans_rad_per_m * trans_;
}

ThrunMotionSample ThrunMotionSampler::sample(const std::array<double, 6>& n) const noexcept {
  const double rot1_hat = rot1_ - s_rot1_ * n[0];
  const double trans_hat = trans_ - s_trans_ * n[1];
  const double rot2_hat = rot2_ - s_rot2_ * n[2];
  return {trans_hat * std::cos(rot1_hat) + add_xy_ * n[3],
          trans_hat * std::sin(rot1_hat) + add_xy_ * n[4],
          rot1_hat + rot2_hat + add_phi_ * n[5]};
}

Pose2 sample_thrun_motion(const Pose2& u, const ThrunMotionOptions& o, std::mt19937_64& rng) {
  const ThrunMotionSampler sampler(u, o);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::array<double, 6> n{};
  for (double& v : n) v = n01(rng);
  const ThrunMotionSample s = sampler.sample(n);
  return Pose2(s.x, s.y, s.phi);
}

Pose2Particles thrun_motion_particles(const Pose2& u, const ThrunMotionOptions& o,
                                      std::mt19937_64& rng) {
  o.check();
  Pose2Particles out;
  for (std::uint32_t i = 0; i < o.particle_count; ++i) out.push_back(sample_thrun_motion(u, o, rng));
  return out;
}

}  // namespace rove
