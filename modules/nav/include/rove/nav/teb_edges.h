#pragma once
/// \file
/// The edges of the timed elastic band (Rösmann, Feiten, Wösch, Hoffmann,
/// Bertram, "Trajectory modification considering dynamic constraints of
/// autonomous robots", ROBOTIK 2012; "Efficient trajectory optimization
/// using a sparse model", ECMR 2013): each a small residual of the poses
/// s = (x, y, θ) and time intervals ΔT it connects, with its analytic
/// Jacobian (the optional output, rows = residual components, columns =
/// the variables in the order of the arguments: x, y, θ of each pose, then
/// each ΔT). The optimizer minimizes Σ weight · residual².
///
/// Bounds are soft: the penalties of teb_local_planner,
///   below(v, a, ε)      = max(0, a + ε − v),
///   interval(v, a, b, ε) = below(v, a, ε) + max(0, v − (b − ε)),
/// and a signed speed uses the smooth direction factor of its fast
/// sigmoid, σ(u) = 100u / (1 + |100u|), u the step projected on the
/// heading. Where a residual is not differentiable (a zero-length step, an
/// obstacle exactly on a pose) the Jacobian is a defined one-sided choice,
/// never NaN.

#include <Eigen/Core>

#include "rove/nav/teb_options.h"

namespace rove::teb {

/// A pose of the band: x, y (m), θ (rad).
using PoseVec = Eigen::Vector3d;

/// below(v, a, ε) and its derivative in v.
double penalty_below(double v, double a, double eps, double* d = nullptr);
/// interval(v, a, b, ε) and its derivative in v.
double penalty_interval(double v, double a, double b, double eps, double* d = nullptr);

/// Velocity limits between poses a, b over dt: [interval(v, −max_vel_x_backwards,
/// max_vel_x), interval(ω, −max_vel_theta, max_vel_theta)]. Variables a, b, dt.
Eigen::Vector2d velocity_error(const PoseVec& a, const PoseVec& b, double dt, const TebOptions& o,
                               Eigen::Matrix<double, 2, 7>* J = nullptr);

/// Acceleration limits over poses a, b, c and intervals dt1, dt2:
/// a = 2 (v₂ − v₁) / (dt1 + dt2), α likewise. Variables a, b, c, dt1, dt2.
Eigen::Vector2d acceleration_error(const PoseVec& a, const PoseVec& b, const PoseVec& c, double dt1,
                                   double dt2, const TebOptions& o,
                                   Eigen::Matrix<double, 2, 11>* J = nullptr);

/// Acceleration limits from the robot's current velocity (v0, ω0) to the
/// first step a → b over dt. Variables a, b, dt.
Eigen::Vector2d acceleration_start_error(const PoseVec& a, const PoseVec& b, double dt, double v0,
                                         double omega0, const TebOptions& o,
                                         Eigen::Matrix<double, 2, 7>* J = nullptr);

/// Acceleration limits from the last step a → b over dt to the goal
/// velocity (v1, ω1). Variables a, b, dt.
Eigen::Vector2d acceleration_goal_error(const PoseVec& a, const PoseVec& b, double dt, double v1,
                                        double omega1, const TebOptions& o,
                                        Eigen::Matrix<double, 2, 7>* J = nullptr);

/// The time-optimal objective: dt itself.
double time_optimal_error(double dt, double* J = nullptr);

/// The shortest-path objective: |b − a| (positions). Variables a, b.
double shortest_path_error(const PoseVec& a, const PoseVec& b, Eigen::Matrix<double, 1, 6>* J = nullptr);

/// Differential drive: [|(cos θa + cos θb) Δy − (sin θa + sin θb) Δx| (the
/// non-holonomic constraint: both headings tangent to one arc),
/// below((cos θa, sin θa)·Δ, 0, 0) (no backward motion)]. Variables a, b.
Eigen::Vector2d diff_drive_error(const PoseVec& a, const PoseVec& b,
                                 Eigen::Matrix<double, 2, 6>* J = nullptr);

/// Car-like: [the non-holonomic constraint as above, below(|Δ| / |Δθ|,
/// min_turning_radius, 0) (0 when Δθ is 0)]. Variables a, b.
Eigen::Vector2d car_like_error(const PoseVec& a, const PoseVec& b, const TebOptions& o,
                               Eigen::Matrix<double, 2, 6>* J = nullptr);

/// An obstacle at the point `c` nearest to the pose's position:
/// below(|p − c| − robot_radius, min_obstacle_dist, penalty_epsilon).
/// Variables a (θ does not enter). With p = c the Jacobian pushes along
/// the pose's left normal.
double obstacle_error(const PoseVec& a, const Eigen::Vector2d& c, const TebOptions& o,
                      Eigen::Matrix<double, 1, 3>* J = nullptr);

/// A via-point: |p − v|. Variables a.
double via_point_error(const PoseVec& a, const Eigen::Vector2d& v, Eigen::Matrix<double, 1, 3>* J = nullptr);

/// θ wrapped to (−π, π].
double wrap_angle(double theta);

}  // namespace rove::teb
