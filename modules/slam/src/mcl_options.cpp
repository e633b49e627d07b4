#include "rove/slam/mcl_options.h"

#include <cmath>
#include <numbers>

#include "rove/core/check.h"
#include "rove/core/parallel.h"

namespace rove {

void ParticleInit::check() const {
  ROVE_CHECK_MSG(count >= 1, "particles_count must be at least 1, got {}", count);
  ROVE_CHECK_FINITE(min_x);
  ROVE_CHECK_FINITE(max_x);
  ROVE_CHECK_FINITE(min_y);
  ROVE_CHECK_FINITE(max_y);
  ROVE_CHECK_FINITE(min_yaw);
  ROVE_CHECK_FINITE(max_yaw);
  ROVE_CHECK_FINITE(std_xy);
  ROVE_CHECK_FINITE(std_yaw);
  ROVE_CHECK_MSG(min_x <= max_x && min_y <= max_y,
                 "the initial box needs min <= max: x [{}, {}], y [{}, {}]", min_x, max_x, min_y,
                 max_y);
  ROVE_CHECK_MSG(min_yaw <= max_yaw, "the initial heading range needs min <= max: [{}, {}] rad",
                 min_yaw, max_yaw);
  ROVE_CHECK_GE(std_xy, 0.0);
  ROVE_CHECK_GE(std_yaw, 0.0);
  ROVE_CHECK_MSG(free_threshold >= 0.0 && free_threshold <= 1.0,
                 "free_threshold must lie in [0, 1], got {}", free_threshold);
}

void RecoveryOptions::check() const {
  ROVE_CHECK_MSG(alpha_slow >= 0.0 && alpha_slow < 1.0,
                 "recovery_alpha_slow must lie in [0, 1), got {}", alpha_slow);
  ROVE_CHECK_MSG(alpha_fast >= 0.0 && alpha_fast < 1.0,
                 "recovery_alpha_fast must lie in [0, 1), got {}", alpha_fast);
  ROVE_CHECK_MSG((alpha_slow == 0.0 && alpha_fast == 0.0) || (alpha_slow > 0.0 && alpha_slow < alpha_fast),
                 "recovery needs 0 < recovery_alpha_slow < recovery_alpha_fast (or both 0 to "
                 "disable it), got {} and {}",
                 alpha_slow, alpha_fast);
}

void ConvergenceOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(radius) && radius > 0.0, "converged_radius must be > 0, got {}",
                 radius);
  ROVE_CHECK_MSG(std::isfinite(heading_radius) && heading_radius > 0.0,
                 "converged_heading_radius must be > 0, got {}", heading_radius);
  ROVE_CHECK_MSG(min_mass > 0.0 && min_mass <= 1.0, "converged_min_mass must lie in (0, 1], got {}",
                 min_mass);
  ROVE_CHECK_MSG(min_steps >= 1, "converged_min_steps must be at least 1");
  ROVE_CHECK_MSG(min_scan_fit >= 0.0 && min_scan_fit <= 1.0,
                 "converged_min_scan_fit must lie in [0, 1], got {}", min_scan_fit);
  ROVE_CHECK_MSG(std::isfinite(fit_distance) && fit_distance > 0.0,
                 "converged_fit_distance must be > 0, got {}", fit_distance);
  ROVE_CHECK_MSG(std::isfinite(max_range_residual) && max_range_residual > 0.0,
                 "converged_max_range_residual must be > 0, got {}", max_range_residual);
}

GaussianMotionOptions MclOptions::default_dummy_odometry() {
  GaussianMotionOptions g;  // a1..a4 keep MRPT's defaults, as its app leaves them
  g.min_std_xy_m = 0.04;
  g.min_std_phi_rad = 2.0 * std::numbers::pi / 180.0;
  return g;
}

void MclOptions::check() const {
  pf.check();
  if (pf.adaptive_sample_size) kld.check();
  init.check();
  recovery.check();
  convergence.check();
  if (motion_model) motion_model->check();
  dummy_odometry.check();
  resolve_thread_count(num_threads, "num_threads");
}

}  // namespace rove
