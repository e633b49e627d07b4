// libFuzzer target for the occupancy-grid file readers: the same bytes go to
// the PNG and PGM decoders (gray, and the colour and depth images of RGB-D
// frames), the map.yaml parser, rove's binary grid record
// and MRPT's serialized COccupancyGridMap2D (.gridmap). Any bytes must
// either read or be rejected with a rove::Error; what reads must survive a
// write/read round trip unchanged, an image must become a grid of its size,
// and a .gridmap must give a grid whose cells match its sizes and whose
// entropy is finite.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "rove/core/error.h"
#include "rove/io/frame_images.h"
#include "rove/io/gray_image.h"
#include "rove/io/grid_binary.h"
#include "rove/io/grid_image.h"
#include "rove/io/mrpt_gridmap.h"
#include "rove/io/ros_map_yaml.h"
#include "rove/maps/grid_entropy.h"
#include "rove/serialization/memory_stream.h"

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "grid_io_fuzz: %s\n", what);
  std::abort();
}

void check_image(const rove::GrayImage& img) {
  if (img.width == 0 || img.height == 0 ||
      img.pixels.size() != static_cast<std::size_t>(img.width) * img.height) {
    die("decoded image has inconsistent sizes");
  }
  if (!(rove::decode_png(rove::encode_png(img), "again.png") == img)) die("PNG round trip changed the image");
  if (!(rove::decode_pgm(rove::encode_pgm(img), "again.pgm") == img)) die("PGM round trip changed the image");
  rove::RosMapYaml y;
  y.image = "x.png";
  const rove::OccupancyGrid g = rove::grid_from_image(img, y);
  if (g.size_x() != img.width || g.size_y() != img.height) die("grid size differs from the image");
}

// The grid written as a .rovegrid record and read back.
rove::OccupancyGrid rovegrid_round_trip(const rove::OccupancyGrid& g) {
  rove::MemoryOutStream out;
  rove::OutArchive oa(out);
  save(oa, g);
  rove::MemoryInStream in(out.data(), "again.rovegrid");
  rove::InArchive ar(in);
  rove::OccupancyGrid h(0, 1, 0, 1, 1);
  load(ar, h);
  return h;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  rove::ImageLimits limits;
  limits.max_side = 4096;
  limits.max_pixels = std::uint64_t{1} << 22;
  try {
    check_image(rove::decode_png(bytes, "fuzz.png", limits));
  } catch (const rove::Error&) {
  }
  try {
    check_image(rove::decode_pgm(bytes, "fuzz.pgm", limits));
  } catch (const rove::Error&) {
  }
  try {
    const rove::ColorImage8 c = rove::decode_color_image(bytes, "fuzz.png", limits);
    if (c.width == 0 || c.height == 0 || c.rgb.size() != std::size_t{3} * c.width * c.height) {
      die("decoded colour image has inconsistent sizes");
    }
  } catch (const rove::Error&) {
  }
  try {
    const rove::DepthImage16 d = rove::decode_depth_image(bytes, "fuzz.png", limits);
    if (d.width == 0 || d.height == 0 || d.values.size() != std::size_t{d.width} * d.height) {
      die("decoded depth image has inconsistent sizes");
    }
  } catch (const rove::Error&) {
  }
  try {
    const rove::RosMapYaml y = rove::parse_ros_map_yaml(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
    const rove::RosMapYaml z = rove::parse_ros_map_yaml(rove::format_ros_map_yaml(y), "again.yaml");
    if (z.image != y.image || z.resolution != y.resolution || z.origin != y.origin ||
        z.negate != y.negate || z.mode != y.mode || z.occupied_thresh != y.occupied_thresh ||
        z.free_thresh != y.free_thresh) {
      die("yaml format/parse round trip changed the values");
    }
  } catch (const rove::Error&) {
  }
  try {
    rove::MemoryInStream in(std::as_bytes(bytes), "fuzz.rovegrid");
    rove::ArchiveLimits al;
    al.max_length = std::uint64_t{1} << 22;
    rove::InArchive ar(in, al);
    rove::OccupancyGrid g(0, 1, 0, 1, 1);  // not the 800 x 800 default: keeps runs fast
    load(ar, g);
    const rove::OccupancyGrid h = rovegrid_round_trip(g);
    if (!(h == g) || h.empty() != g.empty()) die("binary round trip changed the grid");
  } catch (const rove::Error&) {
  }
  try {
    rove::MemoryInStream in(std::as_bytes(bytes), "fuzz.gridmap");
    rove::ArchiveLimits al;
    al.max_length = std::uint64_t{1} << 22;
    rove::InArchive ar(in, al);
    const rove::MrptGridmap m = rove::read_mrpt_gridmap(ar);
    const rove::OccupancyGrid& g = m.grid;
    if (g.cells().size() != static_cast<std::size_t>(g.size_x()) * g.size_y()) {
      die("gridmap cells disagree with its sizes");
    }
    if (!(g.resolution() > 0) || !(g.x_max() > g.x_min()) || !(g.y_max() > g.y_min())) {
      die("gridmap geometry is not a grid");
    }
    const rove::GridEntropy e = rove::grid_entropy(g);
    if (!std::isfinite(e.entropy) || !std::isfinite(e.information) ||
        e.mapped_cells > g.cells().size()) {
      die("gridmap entropy is not finite");
    }
    if (!(rovegrid_round_trip(g) == g)) die("a .gridmap grid did not survive the binary round trip");
  } catch (const rove::Error&) {
  }
  return 0;
}
