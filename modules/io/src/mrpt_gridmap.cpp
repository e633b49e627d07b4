#include "rove/io/mrpt_gridmap.h"

#include <cmath>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/mrpt_format.h"

namespace rove {
namespace {

float read_f(InArchive& ar, std::string_view field) { return ar.read_scalar<float>(field); }

}  // namespace

MrptGridmap read_mrpt_gridmap(InArchive& ar) {
  const MrptObjectHeader h = read_mrpt_object_header(ar);
  if (h.class_name != "COccupancyGridMap2D" &&
      h.class_name != "mrpt::maps::COccupancyGridMap2D") {
    ar.fail_at(h.offset, "class", "expected COccupancyGridMap2D, found " + h.class_name);
  }
  if (h.version > 6) throw_unknown_mrpt_version(ar, h);
  MrptGridmap out;
  out.version = h.version;
  std::uint8_t bits = 8;
  if (h.version >= 2) {
    const std::uint64_t at = ar.offset();
    bits = ar.read_scalar<std::uint8_t>("bitsPerCell");
    if (bits != 8 && bits != 16) ar.fail_at(at, "bitsPerCell", "must be 8 or 16, found " + std::to_string(bits));
  }
  const std::uint64_t geom_at = ar.offset();
  const auto sx = ar.read_scalar<std::uint32_t>("size_x");
  const auto sy = ar.read_scalar<std::uint32_t>("size_y");
  const float x_min = read_f(ar, "x_min"), x_max = read_f(ar, "x_max");
  const float y_min = read_f(ar, "y_min"), y_max = read_f(ar, "y_max");
  const float res = read_f(ar, "resolution");
  for (const float v : {x_min, x_max, y_min, y_max, res}) {
    if (!std::isfinite(v)) ar.fail_at(geom_at, "limits", "non-finite grid limit or resolution");
  }
  if (!(res > 0.0f) || !(x_max > x_min) || !(y_max > y_min)) {
    ar.fail_at(geom_at, "limits", "resolution must be > 0 and max > min");
  }
  // MRPT's setSize snaps the limits; the cells read are those of the
  // snapped size, which must be the stored one.
  const double nx_d = std::round(static_cast<double>(std::round((res * std::round(x_max / res) -
                                                                   res * std::round(x_min / res)) /
                                                                  res)));
  const double ny_d = std::round(static_cast<double>(std::round((res * std::round(y_max / res) -
                                                                   res * std::round(y_min / res)) /
                                                                  res)));
  if (nx_d != sx || ny_d != sy) {
    ar.fail_at(geom_at, "size_x",
               "stored size " + std::to_string(sx) + " x " + std::to_string(sy) +
                   " does not match the limits and resolution");
  }
  const std::uint64_t n = std::uint64_t{sx} * sy;
  const std::uint64_t cells_at = ar.offset();
  ar.check_length(n, bits / 8, "cells", cells_at);
  if (n > (std::uint64_t{1} << 31)) ar.fail_at(cells_at, "cells", "more than 2^31 cells");
  OccupancyGrid grid(x_min, x_max, y_min, y_max, res);
  std::vector<std::int8_t> cells;
  cells.reserve(static_cast<std::size_t>(n));
  if (bits == 8) {
    ar.append_scalars(cells, n, "cells");
  } else {
    std::vector<std::uint16_t> wide;
    ar.append_scalars(wide, n, "cells");
    for (const std::uint16_t w : wide) cells.push_back(static_cast<std::int8_t>(w >> 8));
  }
  if (h.version < 3) {
    // Stored as probabilities 0..255: convert to log-odds.
    const auto& lut = LogOddsLut<std::int8_t>::instance();
    for (auto& c : cells) {
      const double p = static_cast<std::uint8_t>(c) * (1.0f / 0xFF);
      c = lut.p2l(static_cast<float>(p));
    }
  }
  grid.assign(grid.x_min(), grid.x_max(), grid.y_min(), grid.y_max(), grid.resolution(), sx, sy,
              std::move(cells));
  grid.set_empty(false);
  out.grid = std::move(grid);
  if (h.version >= 1) {
    auto& io = out.insertion;
    io.map_altitude = read_f(ar, "mapAltitude");
    io.use_map_altitude = read_mrpt_bool(ar, "useMapAltitude");
    io.max_distance_insertion = read_f(ar, "maxDistanceInsertion");
    io.max_occupancy_update_certainty = read_f(ar, "maxOccupancyUpdateCertainty");
    io.consider_invalid_ranges_as_free_space = read_mrpt_bool(ar, "considerInvalidRangesAsFreeSpace");
    io.decimation = ar.read_scalar<std::uint16_t>("decimation");
    io.horizontal_tolerance = read_f(ar, "horizontalTolerance");
    auto& lo = out.likelihood;
    const std::uint64_t m_at = ar.offset();
    const auto method = ar.read_scalar<std::int32_t>("likelihoodMethod");
    if (method < 0 || method > 6) ar.fail_at(m_at, "likelihoodMethod", "unknown method " + std::to_string(method));
    lo.method = static_cast<GridLikelihoodMethod>(method);
    lo.lf_std_hit = read_f(ar, "LF_stdHit");
    lo.lf_z_hit = read_f(ar, "LF_zHit");
    lo.lf_z_random = read_f(ar, "LF_zRandom");
    lo.lf_max_range = read_f(ar, "LF_maxRange");
    lo.lf_decimation = ar.read_scalar<std::uint32_t>("LF_decimation");
    lo.lf_max_corrs_distance = read_f(ar, "LF_maxCorrsDistance");
    lo.lf_alternate_average_method = read_mrpt_bool(ar, "LF_alternateAverageMethod");
    lo.mi_exponent = read_f(ar, "MI_exponent");
    lo.mi_skip_rays = ar.read_scalar<std::uint32_t>("MI_skip_rays");
    lo.mi_ratio_max_distance = read_f(ar, "MI_ratio_max_distance");
    lo.ray_tracing_use_distance_filter = read_mrpt_bool(ar, "rayTracing_useDistanceFilter");
    lo.ray_tracing_decimation = ar.read_scalar<std::int32_t>("rayTracing_decimation");
    lo.ray_tracing_std_hit = read_f(ar, "rayTracing_stdHit");
    lo.consensus_take_each_range = ar.read_scalar<std::int32_t>("consensus_takeEachRange");
    lo.consensus_pow = read_f(ar, "consensus_pow");
    lo.owa_weights = read_mrpt_vector<float>(ar, "OWA_weights");
    lo.enable_likelihood_cache = read_mrpt_bool(ar, "enableLikelihoodCache");
    if (h.version >= 6) {
      const MrptObjectHeader gp = read_mrpt_object_header(ar);
      if (gp.is_null || gp.version != 0 ||
          (gp.class_name != "TMapGenericParams" &&
           gp.class_name != "mrpt::maps::TMapGenericParams")) {
        ar.fail_at(gp.offset, "genericMapParams",
                   "expected TMapGenericParams version 0, found " + gp.class_name);
      }
      for (const char* f : {"enableSaveAs3DObject", "enableObservationLikelihood",
                            "enableObservationInsertion"}) {
        read_mrpt_bool(ar, f);
      }
      expect_mrpt_end_marker(ar, gp);
    } else {
      read_mrpt_bool(ar, "disableSaveAs3DObject");
    }
  }
  if (h.version >= 4) {
    out.insertion.cfd_features_gaussian_size = read_f(ar, "CFD_features_gaussian_size");
    out.insertion.cfd_features_median_size = read_f(ar, "CFD_features_median_size");
  }
  if (h.version >= 5) {
    out.insertion.widening_beams_with_distance = read_mrpt_bool(ar, "wideningBeamsWithDistance");
  }
  expect_mrpt_end_marker(ar, h);
  return out;
}

MrptGridmap load_mrpt_gridmap(const std::string& path, ArchiveLimits limits) {
  check_regular_input(path, "MRPT gridmap");
  auto stream = open_input_file(path);
  InArchive ar(*stream, limits);
  MrptGridmap g = read_mrpt_gridmap(ar);
  if (!ar.at_end()) ar.fail_at(ar.offset(), "", "unexpected bytes after the gridmap object");
  return g;
}

}  // namespace rove
