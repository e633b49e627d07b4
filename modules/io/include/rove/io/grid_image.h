#pragma once
/// \file
/// Occupancy grids as images with a ROS map_server `map.yaml`, both ways.
///
/// Geometry: image column u is grid column cx = u, image row 0 is the top
/// of the map (largest y), so image row v is grid row cy = height − 1 − v.
/// The yaml's origin is (x_min, y_min) of the grid, its resolution the cell
/// side; x_max = x_min + width·resolution and y_max likewise (float, as the
/// grid). A yaml origin with a yaw other than 0 is rejected (ParseError on
/// `origin`): the grid is axis-aligned and rotating it would resample cells.
///
/// Reading a gray value v (map_server's image_loader): occupancy
/// p = (255 − v) / 255, or v / 255 with `negate`; then
///  - trinary: occupied if p > occupied_thresh, free if p < free_thresh,
///    else unknown;
///  - scale: the same outside the thresholds, between them an occupancy of
///    ⌊1 + 98·(p − free_thresh)/(occupied_thresh − free_thresh)⌋ percent;
///  - raw: v itself is the occupancy in percent (0–100), above 100 unknown
///    (negate does not apply, as in map_server).
/// Occupied cells get free probability 0, free cells 1, unknown 0.5 and
/// percentages q the free probability 1 − q/100, each stored in the grid's
/// log-odds cells (so values round to the nearest cell value).
///
/// Writing (one writer, its mode stated in the yaml as map_server's `mode`):
///  - trinary: map_saver's image (occupied 0, free 254, unknown 205, by the
///    occupancy of each cell against the thresholds, 0.65 and 0.196 by
///    default, which the yaml repeats so that map_server reads back the same
///    classes);
///  - scale: the full probability, gray 255·p(free) (white free, black
///    occupied, 128 unknown), with `mode: scale` in the yaml so that
///    map_server reads the cells between the thresholds as percentages.

#include <string>

#include "rove/io/gray_image.h"
#include "rove/io/ros_map_yaml.h"
#include "rove/maps/occupancy_grid.h"

namespace rove {

/// Options of grid_to_image / save_ros_map.
struct GridImageOptions {
  /// How cells become gray values, written to the yaml as `mode`:
  /// Trinary (map_saver: 0 occupied, 254 free, 205 unknown) or Scale
  /// (round(255·p(free)), the whole probability in 256 levels). Raw is not
  /// written (InvalidArgument).
  RosMapMode mode = RosMapMode::Trinary;
  /// Occupancy above this is occupied (written to the yaml too).
  double occupied_thresh = 0.65;
  /// Occupancy below this is free (written to the yaml too).
  double free_thresh = 0.196;
  /// Image file format for save_ros_map.
  ImageFormat format = ImageFormat::Png;
  /// PNG only: PngEncoding::fast (no row filters, run-length deflate at
  /// level 1: faster, larger files) instead of libpng's defaults.
  bool fast_png = false;
};

/// The image of a grid (row 0 = largest y). Precondition (InvalidArgument):
/// the grid has cells, 0 ≤ free_thresh ≤ occupied_thresh ≤ 1, mode trinary
/// or scale.
GrayImage grid_to_image(const OccupancyGrid& grid, const GridImageOptions& options = {});

/// The grid an image describes under the yaml's interpretation (negate,
/// thresholds, mode; see the file comment), with its lower-left corner at
/// (origin x, origin y) and cells of `resolution`. Throws ParseError naming
/// `source` if the origin has a yaw or the geometry is not representable
/// (non-finite limits in float).
OccupancyGrid grid_from_image(const GrayImage& image, const RosMapYaml& yaml,
                              std::string_view source = "<map.yaml>");

/// The files of a saved map.
struct RosMapFiles {
  std::string yaml;   ///< the map.yaml
  std::string image;  ///< the image it names
};

/// The grid writer of rove: writes `<prefix>.png` (or `.pgm`) and
/// `<prefix>.yaml`, the yaml naming the image by its file name (relative to
/// the yaml's folder) and stating the mode, each file atomically. Throws
/// IoError if a file cannot be written.
RosMapFiles save_ros_map(const std::string& prefix, const OccupancyGrid& grid,
                         const GridImageOptions& options = {});

/// A map read from a map.yaml and its image.
struct RosMap {
  OccupancyGrid grid;  ///< the cells
  RosMapYaml yaml;     ///< the description (unknown_keys lists what was ignored)
  std::string image_path;  ///< the image file read
};

/// Reads a map.yaml and the image it names (PNG or PGM, by content).
/// Throws IoError if a file cannot be read, ParseError (file, line or byte
/// offset, field) if either is malformed, the image larger than `limits`,
/// or the origin has a yaw.
RosMap load_ros_map(const std::string& yaml_path, const ImageLimits& limits = {});

}  // namespace rove
