#pragma once
/// \file
/// Holonomic obstacle-avoidance methods, run in a PTG's TP-space (ptg.h)
/// where the robot is a free-flying point: K directions, direction k at
/// angle α_k = π·(−1 + (2k + 1)/K), each with the obstacle-free distance
/// along it normalized to [0, 1] by the PTG's reference distance; a target
/// at angle α_t and normalized distance d_t. Each method picks a direction
/// and a speed in [0, 1]. Options carry MRPT's key names (sections
/// [CHolonomicVFF], [CHolonomicND], [CHolonomicFullEval]).
///
/// - VFF, virtual force field (Borenstein & Koren 1989): each direction
///   with an obstacle inside the range pushes the robot away with
///   (1/d_k)²/K along −u(α_k); the target pulls with
///   TARGET_ATTRACTIVE_FORCE along u(α_t); the direction is the resultant's.
/// - ND, nearness diagram (Minguez & Montano, IEEE T-RA 20(1), 2004): the
///   directions free beyond min(d_t, MAX_SECTOR_DIST_FOR_D2_PERCENT) form
///   regions; the region to take is scored by free space, distance in
///   directions to the target, nearness of its best point to the target and
///   hysteresis (factorWeights); then the situation decides: the target
///   direction itself when it is free, a wide region's edge nearer the
///   target moved WIDE_GAP_SIZE_PERCENT·K/2 inward, or a narrow region's
///   middle; when obstacles within RISK_EVALUATION_SECTORS_PERCENT·K of it
///   are nearer than RISK_EVALUATION_DISTANCE, the direction turns away from
///   the nearer side (low safety).
/// - FullEval (MRPT's CHolonomicFullEval, its factors and phases): every
///   direction is scored by the factors [0] free distance, [1] nearness in
///   directions to the target, [2] nearness of the free path's end to the
///   target (Euclidean, TP-space), [3] hysteresis, [4] clearance (smallest
///   free distance in the directions around it), [5] as [2] without the
///   penalty when the path is blocked short of the target, [6] exp(−|k −
///   k_t|/(K/10)); each phase keeps the directions whose weighted sum of its
///   factors lies within its threshold of the best (relative to the range),
///   and the last phase's best wins. Directions freer than
///   TOO_CLOSE_OBSTACLE only.

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rove/core/config_section.h"

namespace rove {

/// The holonomic methods.
enum class HolonomicMethod : std::uint8_t {
  FullEval,  ///< `CHolonomicFullEval`
  NearnessDiagram,  ///< `CHolonomicND`
  Vff,       ///< `CHolonomicVFF`
};

/// MRPT's class name of a method.
std::string_view to_string(HolonomicMethod method);

/// The TP-space view a holonomic method decides on.
struct HolonomicInput {
  std::span<const double> free;  ///< per direction, normalized free distance in [0, 1]; K ≥ 3
  double target_alpha = 0;       ///< radians
  double target_distance = 1;    ///< normalized (may exceed 1)
  int last_direction = -1;       ///< the previous cycle's choice (−1: none)
};

/// A method's choice.
struct HolonomicOutput {
  int direction = 0;   ///< k
  double speed = 0;    ///< in [0, 1] of the top speed
};

/// [CHolonomicVFF].
struct VffOptions {
  double target_slow_approaching_distance = 0.10;  ///< `TARGET_SLOW_APPROACHING_DISTANCE`
  double target_attractive_force = 20.0;           ///< `TARGET_ATTRACTIVE_FORCE`
  static VffOptions from_config(const ConfigSection& section);
};

/// [CHolonomicND].
struct NdOptions {
  double wide_gap_size_percent = 0.25;            ///< `WIDE_GAP_SIZE_PERCENT`
  double max_sector_dist_for_d2_percent = 0.25;   ///< `MAX_SECTOR_DIST_FOR_D2_PERCENT`
  double risk_evaluation_sectors_percent = 0.10;  ///< `RISK_EVALUATION_SECTORS_PERCENT`
  double risk_evaluation_distance = 0.4;          ///< `RISK_EVALUATION_DISTANCE`
  double too_close_obstacle = 0.15;               ///< `TOO_CLOSE_OBSTACLE`
  double target_slow_approaching_distance = 0.6;  ///< `TARGET_SLOW_APPROACHING_DISTANCE`
  std::array<double, 4> factor_weights = {1.0, 0.5, 2.0, 0.4};  ///< `factorWeights`
  static NdOptions from_config(const ConfigSection& section);
};

/// A phase of FullEval.
struct FullEvalPhase {
  std::vector<int> factors;  ///< `PHASEn_FACTORS`
  double threshold = 0.75;   ///< `PHASEn_THRESHOLD`
};

/// [CHolonomicFullEval]; the defaults are reactive2d_config.ini's values.
struct FullEvalOptions {
  std::array<double, 7> factor_weights = {0.25, 0.1, 1, 0.05, 0.5, 1, 1};  ///< `factorWeights`
  std::array<bool, 7> factor_normalize = {false, false, false, false, true, true, false};  ///< `factorNormalizeOrNot`
  double too_close_obstacle = 0.15;                 ///< `TOO_CLOSE_OBSTACLE`
  double target_slow_approaching_distance = 0.10;   ///< `TARGET_SLOW_APPROACHING_DISTANCE`
  double obstacle_slow_down_distance = 0.15;        ///< `OBSTACLE_SLOW_DOWN_DISTANCE`
  double hysteresis_sector_count = 5;               ///< `HYSTERESIS_SECTOR_COUNT`
  /// `clearance_threshold_ratio`: × K directions on each side enter factor [4].
  double clearance_threshold_ratio = 0.10;
  /// `gap_width_ratio_threshold`: × K, the free gap around the target's
  /// direction that allows driving straight at it.
  double gap_width_ratio_threshold = 0.20;
  /// `PHASE_COUNT`, `PHASEn_FACTORS`, `PHASEn_THRESHOLD`.
  std::vector<FullEvalPhase> phases = {{{6}, 0.5}, {{4}, 0.7}, {{0, 2}, 0.7}};
  static FullEvalOptions from_config(const ConfigSection& section);
};

/// VFF. Precondition: K ≥ 3.
HolonomicOutput holonomic_vff(const HolonomicInput& in, const VffOptions& o);
/// Nearness diagram.
HolonomicOutput holonomic_nd(const HolonomicInput& in, const NdOptions& o);
/// FullEval.
HolonomicOutput holonomic_full_eval(const HolonomicInput& in, const FullEvalOptions& o);

}  // namespace rove
