#pragma once
/// \file
/// The timed-elastic-band (TEB) local planner (Rösmann et al., ROBOTIK
/// 2012, ECMR 2013; teb_local_planner's behaviour without ROS): a band of
/// poses s₀…s_{n−1} and time intervals ΔT₀…ΔT_{n−2} from the robot to a
/// local goal on the global plan, optimized each control cycle as a sparse
/// least-squares problem (teb_edges.h: velocity, acceleration with start
/// and goal variants, time-optimal, shortest-path, kinematics, obstacle and
/// via-point edges) by Levenberg–Marquardt on the band's banded normal
/// equations; the first step of the optimized band gives the command.
///
/// Each cycle: the band is kept from the previous one (its poses behind the
/// robot pruned, its ends moved to the robot and the local goal) or made
/// anew from the plan; then `no_outer_iterations` times: resize toward
/// dt_ref (teb's autoResize, with hysteresis), associate obstacles with
/// poses, `no_inner_iterations` LM iterations; then the first
/// `feasibility_check_no_poses` poses are checked against the obstacles.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/nav/simulator.h"
#include "rove/nav/teb_options.h"
#include "rove/obs/odometry_data.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {

/// An obstacle: one vertex = a point, two = a segment, three or more = a
/// closed polygon (map frame, meters).
struct TebObstacle {
  std::vector<Eigen::Vector2d> vertices;
};

/// The point of `obstacle` nearest to p (p itself when p lies inside a
/// polygon). Precondition: at least one vertex.
Eigen::Vector2d closest_point(const TebObstacle& obstacle, const Eigen::Vector2d& p);

/// Point obstacles from points (a scan's, a grid's cells), thinned to one
/// per square of `cell` meters (the first point in each). cell > 0.
std::vector<TebObstacle> point_obstacles(const std::vector<Eigen::Vector2d>& points, double cell);

/// The points of a scan in the map frame, given the robot's pose.
std::vector<Eigen::Vector2d> scan_points_in_map(const RangeScan2D& scan, const SE2d& T_map_robot);

/// The band: poses and the time intervals between consecutive ones.
struct TimedElasticBand {
  std::vector<SE2d> poses;  ///< s₀ (the robot) … s_{n−1} (the local goal)
  std::vector<double> dts;  ///< ΔT_i between poses i and i+1, seconds (poses.size() − 1)
  /// Sum of the intervals, s.
  double duration() const;
  /// Sum of the step lengths, m.
  double length() const;
};

/// Why a cycle ended as it did.
enum class TebTermination : std::uint8_t {
  Optimized,    ///< the band was optimized; the command follows it
  GoalReached,  ///< the robot is within the goal tolerances: stop
  Infeasible,   ///< the optimized band's first poses hit an obstacle: stop (the band is reset)
  NoPlan,       ///< the global plan is empty: stop
};

/// "optimized", "goal-reached", "infeasible", "no-plan".
std::string_view to_string(TebTermination t);

/// The outcome of one control cycle.
struct TebResult {
  TebTermination termination = TebTermination::NoPlan;
  std::string message;          ///< one line for a person
  VelocityCommand command;      ///< the velocity to send (zero unless Optimized)
  double cost = 0;              ///< the band's final weighted squared error
  double initial_cost = 0;      ///< before the cycle's optimization
  int iterations = 0;           ///< LM iterations run (accepted or not)
  int poses = 0;                ///< band size after the cycle
  int obstacle_edges = 0;       ///< obstacle edges in the last outer iteration
  /// True when a command to follow was produced (Optimized) or the goal is
  /// reached.
  bool ok() const noexcept {
    return termination == TebTermination::Optimized || termination == TebTermination::GoalReached;
  }
};

/// The planner; keeps the band between cycles (warm start).
/// Thread-compatible.
class TebPlanner {
 public:
  /// Throws InvalidArgument if the options fail check().
  explicit TebPlanner(TebOptions options = {});

  /// One control cycle: the robot at `T_map_robot` moving with `velocity`
  /// (vx forward, omega), the global plan (map frame, the goal last; poses
  /// the robot has passed may be included: the plan is cut at its point
  /// nearest to the robot), and the obstacles around. Preconditions:
  /// finite inputs.
  TebResult plan(const SE2d& T_map_robot, const Twist2& velocity, const std::vector<SE2d>& global_plan,
                 const std::vector<TebObstacle>& obstacles);

  /// The current band (after the last cycle).
  const TimedElasticBand& band() const noexcept { return band_; }
  /// Forgets the band: the next cycle builds it from the plan.
  void reset() noexcept { band_ = {}; }
  /// The options.
  const TebOptions& options() const noexcept { return options_; }

  /// Optimizes `band` (poses 0 and n−1 fixed) against the obstacles and
  /// via-points, as one cycle does after building it: the building block
  /// beneath plan(). The band needs at least 2 poses. Returns the result's
  /// cost fields and iterations.
  TebResult optimize(TimedElasticBand& band, const Twist2& start_velocity,
                     const std::vector<TebObstacle>& obstacles,
                     const std::vector<Eigen::Vector2d>& via_points) const;

 private:
  TebOptions options_;
  TimedElasticBand band_;
};

/// Splits intervals longer than dt_ref + dt_hysteresis and merges those
/// shorter than dt_ref − dt_hysteresis (teb's autoResize), within
/// [min_samples, max_samples] poses.
void resize_band(TimedElasticBand& band, const TebOptions& o);

}  // namespace rove
