#pragma once
/// \file
/// Parameterized trajectory generators (PTGs) for differential-drive
/// robots (rove's own velocity laws for MRPT's families, not MRPT's
/// code): Blanco, González, Fernández-Madrigal, "Extending obstacle
/// avoidance methods through multiple parameter-space transformations",
/// Autonomous Robots 24(1), 2008. A PTG is a family of K trajectories
/// from the robot, trajectory k driven by the velocity law of its
/// parameter α_k = π·(−1 + (2k + 1)/K); a point along one is addressed by
/// (k, d), d its distance along it. In this "TP-space" the robot is a point
/// with a free direction per trajectory: obstacles map to the distance at
/// which the robot's disc, following trajectory k, first touches them.
///
/// The families, with MRPT's class and parameter names (robot frame: x
/// forward, y left; R = v_max / ω_max):
/// - `CPTG_DiffDrive_C` (`K`): circular arcs, v = K·v_max, ω = K·ω_max·α/π;
///   K = −1 drives backwards.
/// - `CPTG_DiffDrive_alpha` (`cte_a0v_deg`, `cte_a0w_deg`): toward heading
///   α, slowing down while the heading error e = α − φ is large:
///   v = v_max·exp(−(e/a0v)²), ω = ω_max·(2/(1 + exp(−e/a0w)) − 1).
/// - `CPTG_DiffDrive_CCS` (C|C,S): a backward arc then a forward arc, both
///   turning toward α at ω_max, each for |α|/(2 ω_max), then straight ahead
///   on heading α (a cusp between the arcs: it reaches sideways targets).
/// - `CPTG_DiffDrive_CS` (C,S): a forward arc at ω_max toward α for
///   |α|/ω_max, then straight ahead on heading α.
/// Distances are pseudo-meters, d = ∫ √(v² + (r_ref·ω)²) dt with r_ref =
/// 0.1 m (MRPT's turningRadiusReference), so turning in place advances d.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/math/se2.h"
#include "rove/nav/simulator.h"

namespace rove {

/// The PTG families.
enum class PtgFamily : std::uint8_t {
  DiffDriveC,      ///< `CPTG_DiffDrive_C`
  DiffDriveAlpha,  ///< `CPTG_DiffDrive_alpha`
  DiffDriveCCS,    ///< `CPTG_DiffDrive_CCS`
  DiffDriveCS,     ///< `CPTG_DiffDrive_CS`
};

/// Options of one PTG (MRPT's `PTGn_*` keys of [CReactiveNavigationSystem]).
struct PtgOptions {
  PtgFamily family = PtgFamily::DiffDriveC;  ///< `PTGn_Type`
  double resolution = 0.05;     ///< `PTGn_resolution`: collision grid cell, m. > 0
  double ref_distance = 10.0;   ///< `PTGn_refDistance`: trajectories' length, m. > 0
  int num_paths = 121;          ///< `PTGn_num_paths`: K, ≥ 3
  double v_max = 1.0;           ///< `PTGn_v_max_mps`, m/s. > 0
  double w_max = 60.0 * 3.14159265358979323846 / 180.0;  ///< `PTGn_w_max_dps` (degrees in the file), rad/s. > 0
  double k = 1.0;               ///< `PTGn_K` (C): +1 forward, −1 backward
  double cte_a0v = 57.0 * 3.14159265358979323846 / 180.0;  ///< `PTGn_cte_a0v_deg`, rad. > 0
  double cte_a0w = 57.0 * 3.14159265358979323846 / 180.0;  ///< `PTGn_cte_a0w_deg`, rad. > 0
  double score_priority = 1.0;  ///< `PTGn_score_priority`, ≥ 0
  double robot_radius = 0.5;    ///< the footprint's radius (`RobotModel_circular_shape_radius`), m. > 0
  /// Throws InvalidArgument naming the first bad field.
  void check() const;
};

/// MRPT's class name of a family.
std::string_view to_string(PtgFamily family);

/// A PTG with its trajectories sampled and its collision grid built.
/// Immutable after construction; const use is thread-safe.
class Ptg {
 public:
  /// Builds the K trajectories (samples every `resolution`/2 of distance up
  /// to ref_distance) and the collision grid (for each cell near them, the
  /// first sample of each trajectory whose footprint holds the cell's
  /// center; an obstacle is taken at the center of its cell). Throws
  /// InvalidArgument if the options fail check(); ResourceError when the
  /// grid would exceed the memory budget.
  explicit Ptg(const PtgOptions& options);

  /// The options.
  const PtgOptions& options() const noexcept { return o_; }
  /// K.
  int path_count() const noexcept { return o_.num_paths; }
  /// α of trajectory k, radians.
  double alpha(int k) const;
  /// The trajectory whose α is nearest to `alpha`.
  int alpha_to_index(double alpha) const;
  /// The pose at distance d along trajectory k (robot frame), d clamped to
  /// the trajectory's length.
  SE2d pose_at(int k, double d) const;
  /// Length of trajectory k, m (ref_distance unless it stops earlier).
  double path_length(int k) const;
  /// The velocity command that starts trajectory k (robot frame).
  VelocityCommand command(int k) const;
  /// TP coordinates of a point in the robot frame: the trajectory and
  /// distance of the sample nearest to it among all trajectories (ties: the
  /// shorter distance). Returns the Euclidean distance from that sample to
  /// the point.
  double inverse_map(const Eigen::Vector2d& p_robot, int& k, double& d) const;
  /// For each trajectory, the distance the footprint travels along it before
  /// touching one of `obstacles_robot` (robot frame), at most its length;
  /// written into `free` (resized to K). An obstacle the footprint already
  /// holds blocks a trajectory only where it comes nearer to it (so a robot
  /// closer to something than its footprint's margin can still back away).
  void free_distances(const std::vector<Eigen::Vector2d>& obstacles_robot, std::vector<double>& free) const;
  /// Smallest distance from the point to the samples of trajectory k up to
  /// distance `up_to`, m.
  double distance_to_path(int k, double up_to, const Eigen::Vector2d& p_robot) const;

 private:
  struct Sample {
    float x, y, phi, d;
  };
  struct Hit {
    std::uint16_t k, sample;
  };
  void velocity(double alpha, double t, double phi, double& v, double& w) const;
  void build_paths();
  void build_grid();

  PtgOptions o_;
  std::vector<std::vector<Sample>> paths_;
  // Collision grid: cells of `resolution` over [−half, half]², each with
  // its hits, in one array (offsets per cell).
  double half_ = 0;
  int cells_ = 0;
  std::vector<std::uint32_t> cell_start_;
  std::vector<Hit> hits_;
};

}  // namespace rove
