#pragma once
/// \file
/// rove's own binary occupancy-grid format: the cells and geometry exactly
/// as held in memory, so a save/load round trip is bit-exact.
///
/// Record (version 1, little-endian, see serialization/archive.h):
/// u8 version, u8 cell bytes (1 = int8, 2 = int16), f32 x_min x_max y_min
/// y_max resolution, u32 size_x size_y, u32 cell count, the cells row by
/// row (cy growing with y), bool empty. A file (`.rovegrid`, optionally
/// gzip-compressed) is the 8 bytes "ROVEGRID" followed by one record.
/// Version 1 is frozen by `modules/io/tests/data/grid_v1.rovegrid`.

#include <array>
#include <string>

#include "rove/maps/occupancy_grid.h"
#include "rove/serialization/archive.h"
#include "rove/serialization/input_file.h"

namespace rove {

/// The first 8 bytes of a rove grid file (after gunzip).
inline constexpr std::array<char, 8> kRoveGridMagic = {'R', 'O', 'V', 'E', 'G', 'R', 'I', 'D'};

/// Writes the record of an 8-bit grid.
void save(OutArchive& ar, const OccupancyGrid& grid);
/// Writes the record of a 16-bit grid.
void save(OutArchive& ar, const OccupancyGrid16& grid);
/// Reads a record into an 8-bit grid. Throws ParseError (source, byte
/// offset, field) on a newer version, a record of 16-bit cells, non-finite
/// or inconsistent geometry, or truncated data.
void load(InArchive& ar, OccupancyGrid& grid);
/// Reads a record into a 16-bit grid (see the 8-bit overload).
void load(InArchive& ar, OccupancyGrid16& grid);

/// Writes a grid file. Throws IoError if it cannot be written.
void save_grid(const std::string& path, const OccupancyGrid& grid,
               FileCompression compression = FileCompression::None);
/// Reads an 8-bit grid file (plain or gzip). Throws IoError if it cannot be
/// opened, ParseError on a bad magic, a bad record or bytes after it.
OccupancyGrid load_grid(const std::string& path, ArchiveLimits limits = {});

}  // namespace rove
