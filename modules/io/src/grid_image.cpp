#include "rove/io/grid_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/io/file_bytes.h"

namespace rove {
namespace {

enum class PixelClass : unsigned char { Free, Occupied, Unknown, Percent };

// map_server's image_loader for one gray value: the class, and for Percent
// the occupancy in percent.
PixelClass classify(std::uint8_t v, const RosMapYaml& y, int* percent) {
  if (y.mode == RosMapMode::Raw) {
    if (v > 100) return PixelClass::Unknown;
    *percent = v;
    return PixelClass::Percent;
  }
  const double occ = (y.negate ? v : 255.0 - v) / 255.0;
  if (occ > y.occupied_thresh) return PixelClass::Occupied;
  if (occ < y.free_thresh) return PixelClass::Free;
  if (y.mode == RosMapMode::Trinary) return PixelClass::Unknown;
  const double span = y.occupied_thresh - y.free_thresh;
  const double ratio = span > 0 ? (occ - y.free_thresh) / span : 0.0;
  *percent = static_cast<int>(1 + 98 * ratio);  // truncated, as map_server's int8 value
  return PixelClass::Percent;
}

std::string file_name(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

}  // namespace

GrayImage grid_to_image(const OccupancyGrid& grid, const GridImageOptions& o) {
  ROVE_CHECK_MSG(grid.size_x() > 0 && grid.size_y() > 0, "the grid has no cells");
  ROVE_CHECK_MSG(o.free_thresh >= 0 && o.free_thresh <= o.occupied_thresh && o.occupied_thresh <= 1,
                 "thresholds must satisfy 0 <= free_thresh ({}) <= occupied_thresh ({}) <= 1",
                 o.free_thresh, o.occupied_thresh);
  ROVE_CHECK_MSG(o.mode != RosMapMode::Raw, "grid images are written in trinary or scale mode");
  const std::uint32_t w = grid.size_x(), h = grid.size_y();
  GrayImage img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<std::size_t>(w) * h);
  // map_saver's gray for unknown is 205; keep it whenever these thresholds
  // read it back as unknown, else take the gray in the middle of them.
  RosMapYaml reader;
  reader.occupied_thresh = o.occupied_thresh;
  reader.free_thresh = o.free_thresh;
  int unused = 0;
  std::uint8_t unknown = 205;
  if (classify(unknown, reader, &unused) != PixelClass::Unknown) {
    unknown = static_cast<std::uint8_t>(
        std::lround(255.0 * (1.0 - 0.5 * (o.free_thresh + o.occupied_thresh))));
  }
  const auto& lut = LogOddsLut<std::int8_t>::instance();
  for (std::uint32_t cy = 0; cy < h; ++cy) {
    std::uint8_t* row = img.pixels.data() + static_cast<std::size_t>(h - 1 - cy) * w;
    const std::int8_t* cells = grid.cells().data() + static_cast<std::size_t>(cy) * w;
    for (std::uint32_t cx = 0; cx < w; ++cx) {
      const float p_free = lut.l2p(cells[cx]);
      if (o.mode == RosMapMode::Scale) {
        row[cx] = static_cast<std::uint8_t>(std::clamp(std::lround(255.0f * p_free), 0L, 255L));
      } else {
        const double occ = 1.0 - static_cast<double>(p_free);
        row[cx] = occ > o.occupied_thresh ? 0 : occ < o.free_thresh ? 254 : unknown;
      }
    }
  }
  return img;
}

OccupancyGrid grid_from_image(const GrayImage& image, const RosMapYaml& yaml,
                              std::string_view source) {
  ROVE_CHECK_EQ(image.pixels.size(), static_cast<std::size_t>(image.width) * image.height);
  const auto bad = [&](std::string_view field, std::string problem) {
    throw ParseError({std::string(source), std::nullopt, std::nullopt, std::string(field)},
                     std::move(problem));
  };
  if (yaml.origin[2] != 0) {
    bad("origin", fmt::format("yaw {} rad: rove grids are axis-aligned; only a yaw of 0 is "
                              "supported (rotate the image instead)",
                              yaml.origin[2]));
  }
  if (image.width == 0 || image.height == 0) bad("image", "empty image");
  const float res = static_cast<float>(yaml.resolution);
  const float x0 = static_cast<float>(yaml.origin[0]), y0 = static_cast<float>(yaml.origin[1]);
  const float x1 = x0 + static_cast<float>(image.width) * res;
  const float y1 = y0 + static_cast<float>(image.height) * res;
  if (!(res > 0) || !std::isfinite(res)) {
    bad("resolution", fmt::format("{} is not a positive float", yaml.resolution));
  }
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1) ||
      !(x1 > x0) || !(y1 > y0)) {
    bad("origin", fmt::format("origin ({}, {}) with {} x {} cells of {} m does not fit in float "
                              "limits",
                              yaml.origin[0], yaml.origin[1], image.width, image.height,
                              yaml.resolution));
  }
  const auto& lut = LogOddsLut<std::int8_t>::instance();
  // Cell value of each gray level, computed once.
  std::array<std::int8_t, 256> cell_of{};
  for (int v = 0; v < 256; ++v) {
    int percent = 0;
    float p_free = 0.5f;
    switch (classify(static_cast<std::uint8_t>(v), yaml, &percent)) {
      case PixelClass::Free: p_free = 1.0f; break;
      case PixelClass::Occupied: p_free = 0.0f; break;
      case PixelClass::Unknown: p_free = 0.5f; break;
      case PixelClass::Percent: p_free = 1.0f - static_cast<float>(percent) / 100.0f; break;
    }
    cell_of[static_cast<std::size_t>(v)] = lut.p2l(p_free);
  }
  const std::uint32_t w = image.width, h = image.height;
  std::vector<std::int8_t> cells(static_cast<std::size_t>(w) * h);
  for (std::uint32_t cy = 0; cy < h; ++cy) {
    const std::uint8_t* row = image.pixels.data() + static_cast<std::size_t>(h - 1 - cy) * w;
    std::int8_t* out = cells.data() + static_cast<std::size_t>(cy) * w;
    for (std::uint32_t cx = 0; cx < w; ++cx) out[cx] = cell_of[row[cx]];
  }
  OccupancyGrid grid(0.0f, 1.0f, 0.0f, 1.0f, 1.0f);  // one cell, replaced below
  grid.assign(x0, x1, y0, y1, res, w, h, std::move(cells));
  grid.set_empty(false);
  return grid;
}

RosMapFiles save_ros_map(const std::string& prefix, const OccupancyGrid& grid,
                         const GridImageOptions& options) {
  RosMapFiles files;
  files.image = prefix + (options.format == ImageFormat::Png ? ".png" : ".pgm");
  files.yaml = prefix + ".yaml";
  if (options.format == ImageFormat::Png && options.fast_png) {
    PngEncoding fast;
    fast.fast = true;
    write_png(files.image, grid_to_image(grid, options), fast);
  } else {
    write_gray_image(files.image, grid_to_image(grid, options), options.format);
  }
  RosMapYaml y;
  y.image = file_name(files.image);
  y.resolution = grid.resolution();
  y.origin = {grid.x_min(), grid.y_min(), 0.0};
  y.occupied_thresh = options.occupied_thresh;
  y.free_thresh = options.free_thresh;
  y.mode = options.mode;
  const std::string text = format_ros_map_yaml(y);
  write_file_bytes(files.yaml, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
  return files;
}

RosMap load_ros_map(const std::string& yaml_path, const ImageLimits& limits) {
  RosMap m;
  m.yaml = read_ros_map_yaml(yaml_path);
  m.image_path = resolve_image_path(m.yaml, yaml_path);
  if (m.yaml.origin[2] != 0) {
    throw ParseError({yaml_path, std::nullopt, std::nullopt, "origin"},
                     fmt::format("yaw {} rad: rove grids are axis-aligned; only a yaw of 0 is "
                                 "supported",
                                 m.yaml.origin[2]));
  }
  m.grid = grid_from_image(read_gray_image(m.image_path, limits), m.yaml, yaml_path);
  return m;
}

}  // namespace rove
