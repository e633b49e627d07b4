#include "rove/maps/metric_map_occupancy_grid.h"

#include <cmath>
#include <utility>
#include <fstream>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/memory_budget.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {

OccupancyGridCreationOptions OccupancyGridCreationOptions::from_config(const ConfigSection& s) {
  OccupancyGridCreationOptions o;
  o.min_x = s.get<float>("min_x", o.min_x);
  o.max_x = s.get<float>("max_x", o.max_x);
  o.min_y = s.get<float>("min_y", o.min_y);
  o.max_y = s.get<float>("max_y", o.max_y);
  o.resolution = s.get<float>("resolution", o.resolution);
  if (!(o.max_x > o.min_x)) s.fail("max_x", fmt::format("max_x ({}) must exceed min_x ({})", o.max_x, o.min_x));
  if (!(o.max_y > o.min_y)) s.fail("max_y", fmt::format("max_y ({}) must exceed min_y ({})", o.max_y, o.min_y));
  if (!(o.resolution > 0) || !std::isfinite(o.resolution)) {
    s.fail("resolution", fmt::format("must be finite and > 0, got {}", o.resolution));
  }
  for (const auto& [key, v] : {std::pair{"min_x", o.min_x}, std::pair{"max_x", o.max_x},
                               std::pair{"min_y", o.min_y}, std::pair{"max_y", o.max_y}}) {
    if (!std::isfinite(v)) s.fail(key, fmt::format("must be finite, got {}", v));
  }
  o.origin = fmt::format("[{}]", s.name());
  // The grid's size as OccupancyGrid::set_size computes it (limits snapped
  // to whole cells), checked before anything is allocated.
  const auto snap = [&](float v) { return o.resolution * std::round(v / o.resolution); };
  const double nx = std::round((snap(o.max_x) - snap(o.min_x)) / o.resolution);
  const double ny = std::round((snap(o.max_y) - snap(o.min_y)) / o.resolution);
  const std::string what =
      fmt::format("[{}] resolution={} over x [{}, {}] y [{}, {}] m gives a {} \u00d7 {} grid",
                  s.name(), o.resolution, o.min_x, o.max_x, o.min_y, o.max_y, nx, ny);
  if (!(nx * ny <= 2147483648.0)) s.fail("resolution", what + ", above rove's limit of 2^31 cells");
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(nx * ny), 1), what);
  return o;
}

OccupancyGridMetricMap::OccupancyGridMetricMap(OccupancyGridCreationOptions c,
                                               GridInsertionOptions io, GridLikelihoodOptions lo)
    : insert_options(io),
      likelihood_options(std::move(lo)),
      creation_(c),
      grid_(c.min_x, c.max_x, c.min_y, c.max_y, c.resolution) {}

OccupancyGridMetricMap::~OccupancyGridMetricMap() = default;

bool OccupancyGridMetricMap::can_compute_likelihood(const Observation& observation) const {
  return dynamic_cast<const RangeScan2D*>(&observation) != nullptr;
}

double OccupancyGridMetricMap::log_likelihood(const Observation& observation,
                                              const Pose3& T_map_robot) const {
  const auto* scan = dynamic_cast<const RangeScan2D*>(&observation);
  if (scan == nullptr) return 0.0;
  if (!model_ || model_revision_ != grid_.revision()) {
    model_ = std::make_unique<GridLikelihoodModel<std::int8_t>>(grid_, likelihood_options,
                                                                insert_options);
    model_revision_ = grid_.revision();
  }
  return model_->log_likelihood(*scan, T_map_robot);
}

bool OccupancyGridMetricMap::insert(const Observation& observation, const Pose3& T_map_robot) {
  const auto* scan = dynamic_cast<const RangeScan2D*>(&observation);
  if (scan == nullptr) return false;
  try {
    return insert_scan(grid_, *scan, T_map_robot, insert_options).inserted();
  } catch (const ResourceError& e) {
    if (creation_.origin.empty()) throw;
    // The grid grows with what it sees; name the key that set its cell size.
    throw ResourceError(fmt::format("{} resolution={}: growing {}", creation_.origin,
                                    creation_.resolution, e.message()));
  }
}

void OccupancyGridMetricMap::clear() {
  grid_.set_size(creation_.min_x, creation_.max_x, creation_.min_y, creation_.max_y,
                 creation_.resolution);
  grid_.set_empty(true);
}

MapBounds OccupancyGridMetricMap::bounding_box() const {
  MapBounds b;
  if (grid_.empty()) return b;
  b.extend(Eigen::Vector3d(grid_.x_min(), grid_.y_min(), 0.0));
  b.extend(Eigen::Vector3d(grid_.x_max(), grid_.y_max(), 0.0));
  return b;
}

MapStatistics OccupancyGridMetricMap::statistics() const {
  MapStatistics s;
  s.unit = "cells";
  s.total_cells = grid_.cells().size();
  for (std::uint32_t cy = 0; cy < grid_.size_y(); ++cy) {
    for (std::uint32_t cx = 0; cx < grid_.size_x(); ++cx) {
      if (grid_.free_probability(static_cast<int>(cx), static_cast<int>(cy)) != 0.5f) ++s.elements;
    }
  }
  s.bounds = bounding_box();
  return s;
}

std::unique_ptr<MetricMap> make_occupancy_grid_metric_map(const IniFile& ini,
                                                          const std::string& p,
                                                          std::vector<IgnoredConfigKey>* ign) {
  ConfigSection cs(ini, p + "_creationOpts", ign), is(ini, p + "_insertOpts", ign),
      ls(ini, p + "_likelihoodOpts", ign);
  const auto creation = OccupancyGridCreationOptions::from_config(cs);
  const auto io = GridInsertionOptions::from_config(is);
  is.ignore({"minLaserScanNoiseStd"}, "MRPT 1.x key, not read by MRPT 2.x");
  auto lo = GridLikelihoodOptions::from_config(ls);
  is.check_all_read();
  ls.check_all_read();
  return std::make_unique<OccupancyGridMetricMap>(creation, io, std::move(lo));
}

}  // namespace rove
