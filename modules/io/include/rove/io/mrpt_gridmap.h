#pragma once
/// \file
/// Reading MRPT's serialized COccupancyGridMap2D (`.gridmap`, plain or
/// gzip): all stored versions 0–6, 8- and 16-bit cell streams (converted to
/// 8 bits as MRPT does), pre-log-odds versions 0–2 converted with p2l.
///
/// The stored limits are snapped to the resolution as MRPT's setSize does;
/// a file whose stored size disagrees with its limits is rejected (MRPT
/// would read a different number of cells than were written). The stored
/// insertion/likelihood options are returned too.

#include <string>

#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/serialization/archive.h"

namespace rove {

/// A grid read from an MRPT stream, with the options stored beside it
/// (defaults for versions that do not store them).
struct MrptGridmap {
  OccupancyGrid grid;                   ///< the cells and geometry
  GridInsertionOptions insertion;       ///< stored insertion options
  GridLikelihoodOptions likelihood;     ///< stored likelihood options
  int version = 0;                      ///< the stored class version
};

/// Reads one COccupancyGridMap2D object at the current position of `ar`.
/// Throws ParseError (source, byte offset, field) on another class, an
/// unknown version, inconsistent sizes, or truncated data.
MrptGridmap read_mrpt_gridmap(InArchive& ar);

/// Reads the `.gridmap` file at `path` (gzip detected); the file must hold
/// exactly one COccupancyGridMap2D. Throws IoError if it cannot be opened,
/// ParseError as read_mrpt_gridmap or if bytes follow the object.
MrptGridmap load_mrpt_gridmap(const std::string& path, ArchiveLimits limits = {});

}  // namespace rove
