#pragma once
/// \file
/// Writing the maps of a multi-metric map to files, one writer per map kind
/// (what MRPT's saveMetricMapRepresentationToFile writes for each):
///  - occupancy grid: `<prefix>.pgm` (8-bit, row 0 = largest y,
///    round(255·p(free)): 255 free, 0 occupied, as MRPT's bitmap) and
///    `<prefix>_limits.txt` (MRPT's `% Grid limits: [x_min x_max y_min y_max]`);
///  - point map: `<prefix>.ply` (binary PLY) and `<prefix>.pcd` (binary PCD);
///  - beacon map: `<prefix>_beacons.txt`, one row per beacon
///    `id x y z var_x var_y var_z det2d det3d c_xy c_xz c_yz kind` (MRPT's
///    saveToTextFile columns, with the id first and the density kind last);
///  - landmark map: `<prefix>_landmarks.txt`, one row per landmark
///    `id x y z c_xx c_yy c_zz c_xy c_xz c_yz times_seen`;
///  - height map: `<prefix>_mean.txt` (MRPT's format: one row per cy, one
///    column per cx, the cell's mean height) and `<prefix>_count.txt`
///    (points per cell, same layout);
///  - octree (octoMap, colourOctoMap): `<prefix>.bt` (OctoMap's binary file,
///    the tree as it is, as MRPT's `_binary.bt`), for the colour map also
///    `<prefix>.ot` (OctoMap's full ColorOcTree file, with the colours), and
///    `<prefix>_occupied.ply` (the centres of the occupied leaves, binary PLY);
///  - multi-metric map: map i to `<prefix>_<ii>_<kind>` as above.
/// Every file is written atomically (rove/core/files.h).

#include <string>
#include <vector>

#include "rove/maps/metric_map.h"

namespace rove {

/// Writes `map` to files whose names start with `path_prefix` (e.g.
/// "out/map"), each with its own suffix and extension (see the file
/// comment); returns the paths written, in order. Throws IoError if a file
/// cannot be written, InvalidArgument for a map kind without a file format.
std::vector<std::string> save_metric_map(const std::string& path_prefix, const MetricMap& map);

}  // namespace rove
