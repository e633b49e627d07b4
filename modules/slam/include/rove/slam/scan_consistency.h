#pragma once
/// \file
/// Do a map's scans contradict each other? A 2D SLAM run that closed a loop
/// wrong, or drifted on its way back through a place, holds two passes that
/// disagree: the later scans see free space through the earlier scans'
/// walls. The check replays the scans in order into a tiled occupancy grid
/// at their estimated poses, and before inserting each one traces its rays
/// through the grid of the scans before it (rays_through_occupied,
/// rove/maps/tiled_grid.h). A scan counts as contradicted when more than
/// kContradictedRays of its rays cross a wall; a run whose contradicted
/// scans exceed kContradictedScans of those checked (and are at least
/// kMinContradicted) is flagged.
///
/// What it catches and what not (docs/filter-slam.md, "Scans against the
/// map"; docs/icp-slam.md): maps whose wrong parts the robot drove through
/// again (doubled corridors, loops closed at an angle); not a map bent where
/// no pass overlaps another: only a comparison with another map tells those.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/mrpt_simplemap.h"
#include "rove/maps/grid_insertion.h"
#include "rove/math/se2.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {

/// A scan's rays through walls above which it counts as contradicted.
inline constexpr double kContradictedRays = 0.2;
/// The share of contradicted scans (or filter updates) above which a run is
/// flagged. On the Radish logs and the Telecom loop, consistent maps had
/// 0–3 % of their updates contradicted, maps with a loop closed wrong
/// 14–41 % (docs/filter-slam.md).
inline constexpr double kContradictedScans = 0.1;
/// Contradicted scans a run needs at least to be flagged.
inline constexpr std::size_t kMinContradicted = 3;
/// Free space kept clear before a return when tracing its ray, meters (4
/// cells if more): grazing rays along a wall stay within it.
inline constexpr double kThroughWallsMargin = 0.5;

/// True if `contradicted` of `checked` scans flag a run (see the file
/// comment).
inline bool contradicted_run(std::size_t contradicted, std::size_t checked) {
  return contradicted >= kMinContradicted &&
         static_cast<double>(contradicted) > kContradictedScans * static_cast<double>(checked);
}

/// The message of a flagged replay: "C of N <what> saw more than 20 % of
/// their rays through walls of the <what> before them<where> (> 10 % of the
/// <what>): <consequence>".
std::string contradiction_message(std::size_t contradicted, std::size_t checked, std::string_view what,
                                  std::string_view where, std::string_view consequence);

/// One scan of the replay and where the robot was.
struct PosedScan {
  SE2d T_map_robot;
  const RangeScan2D* scan = nullptr;
};

/// The most tiles (of 32 × 32 cells) the replay's grid may span: the grid
/// is made coarser, by factors of 2, until the scans' extent fits, up to
/// kMaxCoarsening times the resolution asked for; beyond that the scans are
/// not checked (about 3.3 km a side at 5 cm).
inline constexpr std::size_t kMaxReplayTiles = std::size_t{1} << 16;
inline constexpr int kMaxCoarsening = 8;

/// The replay's result.
struct ScanConsistency {
  /// The cell side the replay used, meters (coarser than asked for when the
  /// scans span more than kMaxReplayTiles); 0 when they span too much to be
  /// checked (nothing was: checked = 0).
  double resolution = 0.0;
  /// Per scan, in order: the share of its rays through walls of the grid of
  /// the scans before it (0 for the first, and for a scan none of whose
  /// returns is longer than the margin).
  std::vector<double> through_walls;
  /// Scans checked against a grid that held something (all but the first).
  std::size_t checked = 0;
  /// Of those, scans with more than kContradictedRays of their rays through
  /// walls.
  std::size_t contradicted = 0;
  /// contradicted_run(contradicted, checked).
  bool flagged() const { return contradicted_run(contradicted, checked); }
};

/// Replays `scans` into a tiled grid of `resolution` meters (or coarser,
/// see kMaxReplayTiles) with the insertion `options` (MRPT's defaults when
/// not given) and checks each against the ones before it (see the file
/// comment). Preconditions
/// (InvalidArgument): resolution finite and > 0, options.check(), every scan
/// non-null and passing check(), every pose finite.
ScanConsistency scan_consistency(const std::vector<PosedScan>& scans, float resolution = 0.05f,
                                 const GridInsertionOptions& options = {});

/// The 2D scans of a simple map's keyframes at their poses (the pose PDF's
/// mean: x, y and yaw), in keyframe order, each frame's scans in its order;
/// the scans stay owned by `map`. A keyframe whose mean is not finite is
/// refused (InvalidArgument naming it).
std::vector<PosedScan> posed_scans(const SimpleMap& map);

/// Something a simplemap check must tell its user.
struct ScanCheckIssue {
  /// "map-contradicts-scans" (ScanConsistency::flagged) or "not-checked"
  /// (the scans span too much to replay).
  std::string code;
  /// One line for a person, with the counts.
  std::string message;
};

/// What `rove map check` reports of a simple map.
struct SimplemapCheck {
  std::size_t keyframes = 0;
  /// Where each 2D scan was taken (posed_scans' order).
  std::vector<SE2d> poses;
  ScanConsistency consistency;
  std::vector<ScanCheckIssue> issues;
};

/// The simple map's 2D scans (posed_scans) replayed against each other
/// (scan_consistency) on cells of `resolution` meters, and the issues.
/// Throws SelectionError (rove/obs/selection_error.h) when the map holds
/// fewer than two 2D scans, InvalidArgument as posed_scans and
/// scan_consistency.
SimplemapCheck check_simplemap(const SimpleMap& map, float resolution = 0.05f);

}  // namespace rove
