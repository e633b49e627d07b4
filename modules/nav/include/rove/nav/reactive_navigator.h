#pragma once
/// \file
/// The PTG-based reactive navigator (Blanco et al. 2008; MRPT's
/// CReactiveNavigationSystem and CAbstractPTGBasedReactive, re-derived):
/// each cycle, for every PTG (ptg.h), the obstacles and the target are
/// mapped into its TP-space, a holonomic method (holonomic.h) picks a
/// direction there, and the candidate motions are scored as MRPT's default
/// motion decider (CMultiObjMotionOpt_Scalarization with the scores of
/// reactive2d_config.ini):
///   score = ptg_priority · (0.3·target_distance + 0.5·collision_free_distance_score
///           + 8·euclidean_nearness + 0.1·hysteresis + 0.2·path_index_near_target)
/// with target_distance = 1/(1 + d_t²) when the path is free beyond the
/// target (else 0), collision_free_distance_score = 1 when free beyond
/// d_t + 0.05 (else the free distance), euclidean_nearness = 1/(1 + e²) (e
/// the path's nearest approach to the target, normalized), hysteresis 1
/// for the same PTG and direction as the last cycle (whose motion is scored
/// as a candidate of its own when the holonomic method picks another one,
/// as MRPT's PTG continuation), path_index_near_target
/// = exp(−|k_t − k|/(K/10)). The best candidate's PTG command, scaled by
/// the holonomic speed and the secure-distance ramp (0 below
/// secure_distance_start, 1 above secure_distance_end of free distance;
/// no ramp on a trajectory toward the target that is free up to it), within
/// the robot's top speeds, is the velocity command.
///
/// Configuration: MRPT's `navigation-ptgs/reactive2d_config.ini` is read
/// unchanged. Keys MRPT documents but rove does not use are accepted and
/// listed as without effect; the score formulas are checked to be MRPT's
/// default ones (the scoring above), and other formulas are refused.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/math/se2.h"
#include "rove/nav/holonomic.h"
#include "rove/nav/ptg.h"
#include "rove/nav/simulator.h"

namespace rove {

/// Options of ReactiveNavigator, MRPT's names in the comments.
struct ReactiveNavigatorOptions {
  double robot_max_v = 1.0;  ///< [CAbstractPTGBasedReactive] `robotMax_V_mps`, m/s. > 0
  double robot_max_w = 60.0 * 3.14159265358979323846 / 180.0;  ///< `robotMax_W_degps` (degrees in the file), rad/s. > 0
  HolonomicMethod holonomic = HolonomicMethod::FullEval;  ///< `holonomic_method`
  double ref_distance = 10.0;           ///< `ref_distance`: obstacles farther are ignored, m. > 0
  double secure_distance_start = 0.05;  ///< `secure_distance_start`, normalized
  double secure_distance_end = 0.15;    ///< `secure_distance_end`, normalized, > start
  /// [CReactiveNavigationSystem] `PTG_COUNT`, `PTGn_*` (defaults: the three
  /// of reactive2d_config.ini).
  std::vector<PtgOptions> ptgs;
  VffOptions vff;              ///< [CHolonomicVFF]
  NdOptions nd;                ///< [CHolonomicND]
  FullEvalOptions full_eval;   ///< [CHolonomicFullEval]

  /// MRPT's defaults with the three PTGs of reactive2d_config.ini, footprint
  /// radius `robot_radius`.
  static ReactiveNavigatorOptions defaults(double robot_radius);
  /// From an MRPT reactive-navigation INI (see the file comment). Keys
  /// without effect are appended to `ignored` (may be null). Throws
  /// ConfigError naming file, section and key on a bad or unknown value.
  static ReactiveNavigatorOptions from_config(const IniFile& ini, std::vector<IgnoredConfigKey>* ignored = nullptr);
  /// Throws InvalidArgument naming the first bad field.
  void check() const;
};

/// Why a cycle ended as it did.
enum class ReactiveTermination : std::uint8_t {
  Moving,         ///< a motion was chosen
  TargetReached,  ///< the target is within the allowed distance: stop
  Blocked,        ///< no PTG can move toward the target: stop
};

/// "moving", "target-reached", "blocked".
std::string_view to_string(ReactiveTermination t);

/// The outcome of one cycle.
struct ReactiveResult {
  ReactiveTermination termination = ReactiveTermination::Blocked;
  std::string message;        ///< one line for a person
  VelocityCommand command;    ///< to send (zero unless Moving)
  int ptg = -1;               ///< the chosen PTG
  int direction = -1;         ///< its trajectory k
  double score = 0;           ///< the motion decider's score
  double free_distance = 0;   ///< along the chosen trajectory, m
  std::vector<SE2d> trajectory;  ///< the chosen trajectory up to its free distance, map frame
  /// True when a motion was chosen or the target is reached.
  bool ok() const noexcept { return termination != ReactiveTermination::Blocked; }
};

/// The navigator: its PTGs (built once) and the last choice (hysteresis).
class ReactiveNavigator {
 public:
  /// Builds the PTGs (their collision grids). Throws InvalidArgument if the
  /// options fail check().
  explicit ReactiveNavigator(ReactiveNavigatorOptions options);

  /// One cycle toward `target` (map frame) from `T_map_robot`, with the
  /// obstacle points around (map frame). Stops within `allowed_distance`
  /// of the target.
  ReactiveResult step(const SE2d& T_map_robot, const std::vector<Eigen::Vector2d>& obstacles,
                      const Eigen::Vector2d& target, double allowed_distance);

  /// The options.
  const ReactiveNavigatorOptions& options() const noexcept { return options_; }

 private:
  struct Candidate {
    int ptg = -1, k = -1;
    double score = -1, speed = 0, free = 0;
  };
  // Scores trajectory k of PTG i (free distances of this cycle, target at
  // TP direction kt and normalized distance target_d, point t in the robot
  // frame) and keeps it in `best` if it moves and scores higher.
  void consider(std::size_t i, int k, double holonomic_speed, int kt, double target_d, const std::vector<double>& free,
                const std::vector<double>& normalized, const Eigen::Vector2d& t, Candidate& best) const;

  ReactiveNavigatorOptions options_;
  std::vector<std::unique_ptr<Ptg>> ptgs_;
  int last_ptg_ = -1, last_direction_ = -1;
};

}  // namespace rove
