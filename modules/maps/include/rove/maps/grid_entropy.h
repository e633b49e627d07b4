#pragma once
/// \file
/// Entropy and information of an occupancy grid (MRPT's
/// COccupancyGridMap2D::computeEntropy, Blanco et al., "A novel measure of
/// uncertainty for mobile robot SLAM with Rao-Blackwellized particle
/// filters", IJRR 2008: the "EMMI" information measure).
///
/// Each cell of probability p (of being free) has the binary entropy
/// h = −p·ln p − (1 − p)·ln(1 − p) ∈ [0, ln 2] nats, computed in float as
/// MRPT does; values within 1e-4 of ln 2 count as ln 2. A cell is *mapped*
/// when h < ln 2 − 0.001 (p farther than about 0.02 from 0.5), and carries
/// the information 1 − h/ln 2 ∈ [0, 1].
///
/// MRPT 2.5.8 zeroes the entries of its per-value table at cell values 0
/// (p = 0.5: unknown) and −1, meant as a guard against rounding at p = 0 and
/// p = 1; as a result its H leaves out the unknown cells and counts each of
/// them as one mapped cell of full information. `EntropyTable::Mrpt`
/// reproduces those numbers (bit for bit on MRPT's grids, tests
/// `GridEntropy.*`); the default `kExact` uses every cell's own entropy.

#include <cstdint>

#include "rove/maps/occupancy_grid.h"

namespace rove {

/// Which per-cell entropy table grid_entropy uses (see the file comment).
enum class EntropyTable {
  Exact,  ///< h(p) of every cell value
  Mrpt,   ///< MRPT 2.5.8's table: cell values 0 and −1 have h = 0
};

/// Entropy and information of a grid (MRPT's TEntropyInfo).
struct GridEntropy {
  /// Σ h over all cells, nats.
  double entropy = 0;
  /// Σ (1 − h/ln 2) over the mapped cells.
  double information = 0;
  /// entropy / mapped_cells (0 when no cell is mapped), as MRPT.
  double mean_entropy = 0;
  /// information / mapped_cells (0 when no cell is mapped).
  double mean_information = 0;
  /// mapped_cells × resolution², m².
  double mapped_area = 0;
  /// Cells with h < ln 2 − 0.001.
  std::uint64_t mapped_cells = 0;
};

/// Entropy and information of every cell of `grid` (see the file comment).
/// O(cells).
template <GridCell Cell>
GridEntropy grid_entropy(const OccupancyGridT<Cell>& grid,
                         EntropyTable table = EntropyTable::Exact);

}  // namespace rove
