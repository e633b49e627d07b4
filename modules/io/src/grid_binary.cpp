#include "rove/io/grid_binary.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/serialization/file_stream.h"
#include "rove/serialization/gzip_stream.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

constexpr std::uint8_t kVersion = 1;

template <GridCell Cell>
void save_record(OutArchive& ar, const OccupancyGridT<Cell>& g) {
  write_version(ar, kVersion);
  ar.write_scalar(static_cast<std::uint8_t>(sizeof(Cell)));
  for (float v : {g.x_min(), g.x_max(), g.y_min(), g.y_max(), g.resolution()}) ar.write_scalar(v);
  ar.write_scalar(g.size_x());
  ar.write_scalar(g.size_y());
  ar.write_length(g.cells().size(), "cells");
  ar.write_scalars(g.cells());
  ar.write_scalar(g.empty());
}

template <GridCell Cell>
void load_record(InArchive& ar, OccupancyGridT<Cell>& g) {
  (void)read_version(ar, "OccupancyGrid", kVersion);
  const std::uint64_t at = ar.offset();
  const auto bytes = ar.read_scalar<std::uint8_t>("cell bytes");
  if (bytes != sizeof(Cell)) {
    ar.fail_at(at, "cell bytes",
               fmt::format("the file holds {}-bit cells; load it into a grid of {}-bit cells",
                           8 * bytes, 8 * sizeof(Cell)));
  }
  const std::uint64_t geo = ar.offset();
  const float x_min = ar.read_scalar<float>("x_min"), x_max = ar.read_scalar<float>("x_max");
  const float y_min = ar.read_scalar<float>("y_min"), y_max = ar.read_scalar<float>("y_max");
  const float res = ar.read_scalar<float>("resolution");
  if (!std::isfinite(x_min) || !std::isfinite(x_max) || !std::isfinite(y_min) ||
      !std::isfinite(y_max) || !(x_max >= x_min) || !(y_max >= y_min)) {
    ar.fail_at(geo, "limits",
               fmt::format("limits x [{}, {}] y [{}, {}] are not finite and ordered", x_min, x_max,
                           y_min, y_max));
  }
  if (!(res > 0) || !std::isfinite(res)) {
    ar.fail_at(geo + 16, "resolution", fmt::format("must be finite and > 0, got {}", res));
  }
  const std::uint64_t sizes = ar.offset();
  const auto sx = ar.read_scalar<std::uint32_t>("size_x");
  const auto sy = ar.read_scalar<std::uint32_t>("size_y");
  const std::uint64_t count_at = ar.offset();
  const auto n = ar.read_scalar<std::uint32_t>("cells");
  if (static_cast<std::uint64_t>(sx) * sy != n) {
    ar.fail_at(sizes, "size_x",
               fmt::format("{} x {} cells declared but {} stored", sx, sy, n));
  }
  if (n > (std::uint64_t{1} << 31)) ar.fail_at(count_at, "cells", fmt::format("{} cells: above 2^31", n));
  ar.check_length(n, sizeof(Cell), "cells", count_at);
  std::vector<Cell> cells;
  ar.append_scalars(cells, n, "cells");
  const bool empty = ar.read_scalar<bool>("empty");
  g.assign(x_min, x_max, y_min, y_max, res, sx, sy, std::move(cells));
  g.set_empty(empty);
}

}  // namespace

void save(OutArchive& ar, const OccupancyGrid& grid) { save_record(ar, grid); }
void save(OutArchive& ar, const OccupancyGrid16& grid) { save_record(ar, grid); }
void load(InArchive& ar, OccupancyGrid& grid) { load_record(ar, grid); }
void load(InArchive& ar, OccupancyGrid16& grid) { load_record(ar, grid); }

namespace {

void save_grid_to(const std::string& path, const OccupancyGrid& grid, FileCompression compression) {
  auto out = open_output_file(path, compression);
  OutArchive ar(*out);
  ar.write_bytes(std::as_bytes(std::span<const char>(kRoveGridMagic)));
  save(ar, grid);
  if (auto* gz = dynamic_cast<GzipFileOutStream*>(out.get())) {
    gz->close();
  } else if (auto* f = dynamic_cast<FileOutStream*>(out.get())) {
    f->close();
  } else {
    out->flush();
  }
}

}  // namespace

void save_grid(const std::string& path, const OccupancyGrid& grid, FileCompression compression) {
  write_file_atomically(path, [&](const std::filesystem::path& tmp) {
    save_grid_to(tmp.string(), grid, compression);
  });
}

OccupancyGrid load_grid(const std::string& path, ArchiveLimits limits) {
  check_regular_input(path, "rove grid");
  auto in = open_input_file(path);
  InArchive ar(*in, limits);
  std::array<char, 8> magic{};
  if (in->read_some(std::as_writable_bytes(std::span<char>(magic))) != magic.size() ||
      magic != kRoveGridMagic) {
    ar.fail_at(0, "magic", "not a rove grid: the file does not start with \"ROVEGRID\"");
  }
  OccupancyGrid grid(0.0f, 1.0f, 0.0f, 1.0f, 1.0f);  // one cell, replaced by load
  load(ar, grid);
  if (!ar.at_end()) ar.fail("end", "bytes after the grid record");
  return grid;
}

}  // namespace rove
