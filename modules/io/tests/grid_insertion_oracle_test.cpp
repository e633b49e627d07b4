// Oracle for the fast thin-ray insertion: insert_scan against a
// straightforward transcription of MRPT's loop (one ray after the other,
// every cell bounds-checked and updated in place), cell for cell, on the
// real scans of three MRPT datasets and on random scans built to reach the
// corner cases (sensor outside the grid, rays without echo, unequal free
// and no-echo strengths, 16-bit cells).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rove/io/mrpt_simplemap.h"
#include "rove/io/rawlog_reader.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/serialization/input_file.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = ROVE_SOURCE_DIR "/modules/io/tests/data/";
const std::string kDatasets = test_data::bundled_file("mrpt/");

// MRPT's thin-ray insertion written plainly (options as GridInsertionOptions,
// wideningBeamsWithDistance false, no int8 wrap of the occupied strength),
// with MRPT's float ray geometry: the oracle of insert_scan with
// Arithmetic::Mrpt (as_mrpt). The fast paths it checks (the integer tracer)
// are the same in rove's default geometry.
GridInsertionOptions as_mrpt(GridInsertionOptions o) {
  o.arithmetic = Arithmetic::Mrpt;
  return o;
}

template <GridCell Cell>
void oracle_insert(OccupancyGridT<Cell>& g, const RangeScan2D& scan, const Pose3& T_map_robot,
                   const GridInsertionOptions& opt) {
  using Traits = LogOddsTraits<Cell>;
  const auto& lut = LogOddsLut<Cell>::instance();
  const Pose3 T_map_sensor = T_map_robot + scan.T_robot_sensor;
  if (!is_horizontal(scan.T_robot_sensor, opt.horizontal_tolerance)) return;
  if (opt.use_map_altitude && std::fabs(opt.map_altitude - T_map_sensor.z()) > 0.001) return;
  const float certainty = opt.max_occupancy_update_certainty;
  const float p_free =
      opt.max_freeness_update_certainty == 0.0f ? certainty : opt.max_freeness_update_certainty;
  const float p_noecho =
      opt.max_freeness_invalid_ranges == 0.0f ? certainty : opt.max_freeness_invalid_ranges;
  const int obs_free = std::max<int>(1, lut.p2l(p_free));
  const int obs_noecho = std::max<int>(1, lut.p2l(p_noecho));
  const int obs_occ = std::min(Traits::kMax, 3 * std::max<int>(1, lut.p2l(certainty)));
  const int thres_free = Traits::kMax - std::max(obs_free, obs_noecho);
  const int thres_occ = Traits::kMin + obs_occ;

  const auto n = static_cast<int>(scan.size());
  const int step = opt.decimation;
  const bool ccw = scan.right_to_left != (T_map_sensor.rotation()(2, 2) < 0);
  const auto aperture = static_cast<float>(scan.aperture);
  const double yaw = T_map_sensor.yaw();
  const auto px = static_cast<float>(T_map_sensor.x());
  const auto py = static_cast<float>(T_map_sensor.y());
  const float max_dist = opt.max_distance_insertion;
  const auto valid = [&](int i) {
    const float r = scan.ranges[static_cast<std::size_t>(i)];
    return scan.valid[static_cast<std::size_t>(i)] && std::isfinite(r) && r >= 0.0f;
  };
  const float d_angle = (ccw ? 1.0f : -1.0f) * static_cast<float>(step) * aperture /
                        static_cast<float>(n);
  float a = static_cast<float>(ccw ? yaw - 0.5f * aperture : yaw + 0.5f * aperture);
  std::vector<float> ex(scan.size()), ey(scan.size());
  float x0 = std::numeric_limits<float>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  float last_valid = max_dist;
  for (int i = 0; i < n; i += step, a += d_angle) {
    float rr = -1;
    if (valid(i)) {
      rr = std::min(max_dist, scan.ranges[static_cast<std::size_t>(i)]);
      last_valid = scan.ranges[static_cast<std::size_t>(i)];
    } else if (opt.consider_invalid_ranges_as_free_space) {
      rr = std::min(max_dist, 0.5f * last_valid);
    }
    const auto si = static_cast<std::size_t>(i);
    ex[si] = rr < 0 ? px : px + std::cos(a) * rr;
    ey[si] = rr < 0 ? py : py + std::sin(a) * rr;
    x0 = std::min(x0, ex[si]);
    x1 = std::max(x1, ex[si]);
    y0 = std::min(y0, ey[si]);
    y1 = std::max(y1, ey[si]);
  }
  const float margin = 15.0f * g.resolution();
  x1 = x1 > g.x_max() - margin ? x1 + 2 * margin : g.x_max();
  x0 = x0 < g.x_min() + margin ? x0 - 2 : g.x_min();
  y1 = y1 > g.y_max() - margin ? y1 + 2 * margin : g.y_max();
  y0 = y0 < g.y_min() + margin ? y0 - 2 : g.y_min();
  g.resize(x0, x1, y0, y1, 0.5f, true);
  g.set_empty(false);

  std::vector<Cell> cells(g.cells().begin(), g.cells().end());
  const auto at = [&](int cx, int cy) -> Cell* {
    return g.contains(cx, cy) ? &cells[g.index(cx, cy)] : nullptr;
  };
  const int cx0 = g.x_to_idx(px), cy0 = g.y_to_idx(py);
  for (int i = 0; i < n; i += step) {
    const auto si = static_cast<std::size_t>(i);
    if (!valid(i) && !opt.consider_invalid_ranges_as_free_space) continue;
    const int tx = g.x_to_idx(ex[si]), ty = g.y_to_idx(ey[si]);
    const int dx = tx - cx0, dy = ty - cy0;
    const int steps = std::max(std::abs(dx), std::abs(dy));
    if (steps == 0) continue;
    const float inv = 1.0f / static_cast<float>(steps);
    const auto fr = [inv](int d) {
      const auto m = static_cast<int>(std::round(static_cast<float>(std::abs(d) * 512) * inv));
      return d < 0 ? -m : m;
    };
    const int frx = fr(dx), fry = fr(dy);
    const int obs = valid(i) ? obs_free : obs_noecho;
    int fx = cx0 * 512, fy = cy0 * 512, cx = cx0, cy = cy0;
    for (int s = 0; s < steps; ++s) {
      if (Cell* c = at(cx, cy)) {
        *c = static_cast<Cell>(*c < thres_free ? *c + obs : Traits::kMax);
      }
      fx += frx;
      fy += fry;
      cx = fx >> 9;
      cy = fy >> 9;
    }
    if (valid(i) && scan.ranges[si] < max_dist) {
      if (Cell* c = at(tx, ty)) {
        *c = static_cast<Cell>(*c > thres_occ ? *c - obs_occ : Traits::kMin);
      }
    }
  }
  g.assign(g.x_min(), g.x_max(), g.y_min(), g.y_max(), g.resolution(), g.size_x(), g.size_y(),
           std::move(cells));
}

std::vector<Pose3> ref_poses(const std::string& name) {
  auto s = open_input_file(kData + name);
  InArchive ar(*s);
  ar.read_scalar<std::uint32_t>();
  for (int k = 0; k < 5; ++k) ar.read_scalar<float>();
  const auto sx = ar.read_scalar<std::uint32_t>(), sy = ar.read_scalar<std::uint32_t>();
  std::vector<std::int8_t> cells;
  ar.append_scalars(cells, std::uint64_t{sx} * sy);
  const auto n = ar.read_scalar<std::uint32_t>();
  std::vector<Pose3> poses;
  for (std::uint32_t i = 0; i < n; ++i) {
    double v[6];
    for (double& d : v) d = ar.read_scalar<double>();
    poses.emplace_back(v[0], v[1], v[2], v[3], v[4], v[5]);
  }
  return poses;
}

using Scans = std::vector<std::shared_ptr<const RangeScan2D>>;

Scans simplemap_scans(const std::string& file) {
  const SimpleMap sm = load_mrpt_simplemap(kDatasets + file);
  Scans out;
  for (const auto& kf : sm.keyframes) {
    for (const auto& o : kf.frame->observations) {
      if (auto s = std::dynamic_pointer_cast<const RangeScan2D>(o)) out.push_back(s);
    }
  }
  return out;
}

Scans rawlog_scans(const std::string& file) {
  const Rawlog log = load_rawlog(kDatasets + file);
  Scans out;
  bool after_action = false;
  for (const auto& e : log.entries) {
    if (std::holds_alternative<std::shared_ptr<const ActionCollection>>(e)) after_action = true;
    if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&e);
        sf != nullptr && after_action) {
      after_action = false;
      for (const auto& o : (*sf)->observations) {
        if (auto s = std::dynamic_pointer_cast<const RangeScan2D>(o)) out.push_back(s);
      }
    }
  }
  return out;
}

// If the grid's saturation summary is current, every block it flags as
// saturated must hold only cells at the free limit. Returns the number of
// cells in flagged blocks (0 when the summary is not current), so that the
// tests' expectations do not depend on the block size.
template <GridCell Cell>
std::size_t expect_summary_sound(OccupancyGridT<Cell>& g) {
  const GridSaturationSummary& s = g.saturation_summary();
  if (s.revision != g.revision()) return 0;
  constexpr int kB = GridSaturationSummary::kBlock;
  EXPECT_EQ(s.blocks_x, (g.size_x() + kB - 1) / kB);
  EXPECT_EQ(s.blocks_y, (g.size_y() + kB - 1) / kB);
  EXPECT_EQ(s.blocks.size(), std::size_t{s.blocks_x} * s.blocks_y);
  std::size_t flagged = 0;
  for (std::uint32_t by = 0; by < s.blocks_y; ++by) {
    for (std::uint32_t bx = 0; bx < s.blocks_x; ++bx) {
      if (s.blocks[bx + std::size_t{by} * s.blocks_x] != GridSaturationSummary::kFull) continue;
      for (std::uint32_t y = by * kB; y < std::min<std::uint32_t>(g.size_y(), (by + 1) * kB); ++y) {
        for (std::uint32_t x = bx * kB; x < std::min<std::uint32_t>(g.size_x(), (bx + 1) * kB);
             ++x) {
          ++flagged;
          if (g.cells()[g.index(static_cast<int>(x), static_cast<int>(y))] !=
              LogOddsTraits<Cell>::kMax) {
            ADD_FAILURE() << "block (" << bx << ", " << by << ") flagged but cell (" << x << ", "
                          << y << ") is not saturated";
            return flagged;
          }
        }
      }
    }
  }
  return flagged;
}

// Inserts every scan into two grids, one by insert_scan and one by the
// oracle, and compares all cells after every 8th scan and at the end.
// `saturates`: the scans saturate whole blocks of an 8-bit grid, so the
// summary's skips must have been taken.
template <GridCell Cell>
void expect_same_as_oracle(const Scans& scans, const std::vector<Pose3>& poses, float res,
                           const GridInsertionOptions& opt, bool saturates = true) {
  ASSERT_EQ(scans.size(), poses.size());
  OccupancyGridT<Cell> fast(-10, 10, -10, 10, res), slow(-10, 10, -10, 10, res);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    ASSERT_TRUE(insert_scan(fast, *scans[i], poses[i], as_mrpt(opt)).inserted());
    oracle_insert(slow, *scans[i], poses[i], opt);
    if (i % 8 == 7 || i + 1 == scans.size()) {
      ASSERT_TRUE(fast == slow) << "after scan " << i << " of " << scans.size();
      expect_summary_sound(fast);
    }
  }
  // The real scans saturate large areas of 8-bit grids (16-bit cells need
  // hundreds of free updates): the summary's skips were taken.
  if (sizeof(Cell) == 1 && saturates) {
    EXPECT_GT(expect_summary_sound(fast), 0u);
  }
}

GridInsertionOptions unequal_strengths() {
  GridInsertionOptions o;
  o.max_occupancy_update_certainty = 0.8f;
  o.max_freeness_update_certainty = 0.6f;   // free step smaller than the no-echo step
  o.max_freeness_invalid_ranges = 0.75f;
  return o;
}

TEST(GridInsertionOracle, TelecomRawlogEqualsStraightforwardLoop) {
  const Scans scans = rawlog_scans("2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog");
  const auto poses = ref_poses("grid_telecom_005.bin.gz");
  expect_same_as_oracle<std::int8_t>(scans, poses, 0.05f, {});
  expect_same_as_oracle<std::int16_t>(scans, poses, 0.05f, {});
  expect_same_as_oracle<std::int8_t>(scans, poses, 0.05f, unequal_strengths());
  GridInsertionOptions fine;
  fine.max_distance_insertion = 60.0f;  // rays of up to 1,200 cells
  expect_same_as_oracle<std::int8_t>(scans, poses, 0.05f, fine);
}

TEST(GridInsertionOracle, MalagaSimplemapEqualsStraightforwardLoop) {
  const Scans scans = simplemap_scans("malaga-cs-fac-building.simplemap.gz");
  const auto poses = ref_poses("grid_malaga_005.bin.gz");
  expect_same_as_oracle<std::int8_t>(scans, poses, 0.05f, {});
  expect_same_as_oracle<std::int16_t>(scans, poses, 0.05f, unequal_strengths());
}

TEST(GridInsertionOracle, LocalizationDemoEqualsStraightforwardLoop) {
  const Scans scans = simplemap_scans("localization_demo.simplemap.gz");
  const auto poses = ref_poses("grid_locdemo_widening_010.bin.gz");
  GridInsertionOptions o;
  // Decimated scans of a short run: no whole block reaches the free limit.
  o.decimation = 2;
  o.consider_invalid_ranges_as_free_space = false;
  expect_same_as_oracle<std::int8_t>(scans, poses, 0.10f, o, false);
  o.decimation = 3;
  o.consider_invalid_ranges_as_free_space = true;
  o.max_freeness_invalid_ranges = 0.9f;
  expect_same_as_oracle<std::int8_t>(scans, poses, 0.10f, o, false);
}

// Random scans: many rays through the same cells (the sensor stays near
// the origin), invalid rays, cut rays, and sensors far outside the grid so
// that rays enter it from outside (the bounds-checked path).
TEST(GridInsertionOracle, RandomScansEqualStraightforwardLoop) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int trial = 0; trial < 16; ++trial) {
    GridInsertionOptions opt = trial % 3 == 0 ? unequal_strengths() : GridInsertionOptions{};
    opt.decimation = static_cast<std::uint16_t>(1 + trial % 4);
    opt.consider_invalid_ranges_as_free_space = trial % 2 == 0;
    opt.max_distance_insertion = 4.0f + 8.0f * u01(rng);
    OccupancyGrid fast(-3, 3, -3, 3, 0.05f), slow(-3, 3, -3, 3, 0.05f);
    OccupancyGrid16 fast16(-3, 3, -3, 3, 0.05f), slow16(-3, 3, -3, 3, 0.05f);
    for (int k = 0; k < 20; ++k) {
      RangeScan2D scan;
      const int n = 2 + static_cast<int>(400 * u01(rng));
      scan.aperture = (0.2 + 1.8 * u01(rng)) * 3.14159265358979;
      scan.right_to_left = u01(rng) < 0.7f;
      std::vector<float> ranges(static_cast<std::size_t>(n));
      for (float& r : ranges) {
        const float v = u01(rng);
        r = v < 0.05f ? 0.0f : (v < 0.1f ? 100.0f : 0.3f + 12.0f * u01(rng));
      }
      scan.set_ranges(ranges);
      for (std::size_t i = 0; i < scan.valid.size(); ++i) scan.valid[i] = u01(rng) > 0.1f;
      const bool far = k % 5 == 4;
      const Pose2 pose(far ? 40.0 : 2.0 * u01(rng) - 1.0, far ? -35.0 : 2.0 * u01(rng) - 1.0,
                       6.283 * u01(rng));
      insert_scan(fast, scan, pose, as_mrpt(opt));
      oracle_insert(slow, scan, Pose3(pose), opt);
      ASSERT_TRUE(fast == slow) << "trial " << trial << " scan " << k;
      insert_scan(fast16, scan, pose, as_mrpt(opt));
      oracle_insert(slow16, scan, Pose3(pose), opt);
      ASSERT_TRUE(fast16 == slow16) << "trial " << trial << " scan " << k;
    }
  }
}

// Scans that saturate the area around the origin: long rays (most cut at
// max_distance_insertion, so few occupied cells) from poses near (x, y).
// 720 rays all around; a share hit_fraction of them ends at a range in
// [min_hit, 2.5) m, the others reach beyond the insertion distance.
RangeScan2D saturating_scan(std::mt19937& rng, float hit_fraction, float min_hit = 0.5f) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  RangeScan2D scan;
  scan.aperture = 2.0 * 3.14159265358979;
  std::vector<float> ranges(720);
  for (float& r : ranges) r = u01(rng) < hit_fraction ? min_hit + (2.5f - min_hit) * u01(rng) : 50.0f;
  scan.set_ranges(ranges);
  return scan;
}

Pose2 near(std::mt19937& rng, double x, double y) {
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  return Pose2(x + u(rng), y + u(rng), 10.0 * u(rng));
}

template <GridCell Cell>
void insert_both(OccupancyGridT<Cell>& fast, OccupancyGridT<Cell>& slow, const RangeScan2D& scan,
                 const Pose2& pose, const GridInsertionOptions& opt) {
  ASSERT_TRUE(insert_scan(fast, scan, pose, as_mrpt(opt)).inserted());
  oracle_insert(slow, scan, Pose3(pose), opt);
  ASSERT_TRUE(fast == slow);
  expect_summary_sound(fast);
}

// Many scans over the same area: blocks become saturated and stay flagged
// across scans, while some rays end (occupied) inside flagged blocks (the
// hits fall 1.5 to 2.5 m from the sensor, so the blocks nearer stay
// flagged). 16-bit cells need more scans to saturate.
template <GridCell Cell>
void saturated_blocks_across_scans(const GridInsertionOptions& opt) {
  std::mt19937 rng(7);
  OccupancyGridT<Cell> fast(-4, 4, -4, 4, 0.05f), slow(-4, 4, -4, 4, 0.05f);
  const int n_free = sizeof(Cell) == 1 ? 40 : 80;
  for (int k = 0; k < n_free + 20; ++k) {
    SCOPED_TRACE(k);
    insert_both(fast, slow, saturating_scan(rng, k < n_free ? 0.0f : 0.2f, 1.5f), near(rng, 0, 0),
                opt);
    if (k == n_free - 1) {
      EXPECT_GT(expect_summary_sound(fast), sizeof(Cell) == 1 ? 6400u : 128u);
    }
  }
  EXPECT_GT(expect_summary_sound(fast), sizeof(Cell) == 1 ? 320u : 128u);
}

TEST(GridInsertionOracle, SaturatedBlocksAcrossScans) {
  GridInsertionOptions opt;
  opt.max_distance_insertion = 3.0f;
  saturated_blocks_across_scans<std::int8_t>(opt);
  saturated_blocks_across_scans<std::int8_t>(unequal_strengths());
  opt.max_freeness_update_certainty = 0.999f;  // 16-bit cells saturate sooner
  opt.max_freeness_invalid_ranges = 0.99f;
  saturated_blocks_across_scans<std::int16_t>(opt);
}

// The grid grows between scans (cells move by whole cells that are not
// whole blocks): the summary is rebuilt, never reused at the old layout.
TEST(GridInsertionOracle, SaturatedBlocksWithGrowthBetweenScans) {
  std::mt19937 rng(11);
  GridInsertionOptions opt;
  opt.max_distance_insertion = 3.0f;
  OccupancyGrid fast(-5.05f, 5, -5.15f, 5, 0.05f), slow(-5.05f, 5, -5.15f, 5, 0.05f);
  for (int k = 0; k < 30; ++k) {
    SCOPED_TRACE(k);
    insert_both(fast, slow, saturating_scan(rng, 0.0f), near(rng, 0, 0), opt);
  }
  const std::uint32_t sx = fast.size_x();
  insert_both(fast, slow, saturating_scan(rng, 0.1f), near(rng, -2.5, -2.7), opt);
  ASSERT_GT(fast.size_x(), sx);  // it grew
  for (int k = 0; k < 20; ++k) {
    SCOPED_TRACE(k);
    insert_both(fast, slow, saturating_scan(rng, 0.1f), near(rng, k % 2 ? 0.0 : -2.0, 0), opt);
  }
  EXPECT_GT(expect_summary_sound(fast), 0u);
}

// An occupied update at a cell of a saturated block clears the block's
// flag, so later rays through that cell update it again.
TEST(GridInsertionOracle, OccupiedHitInsideSaturatedBlock) {
  std::mt19937 rng(5);
  GridInsertionOptions opt;
  opt.max_distance_insertion = 3.0f;
  OccupancyGrid fast(-4, 4, -4, 4, 0.05f), slow(-4, 4, -4, 4, 0.05f);
  for (int k = 0; k < 40; ++k) insert_both(fast, slow, saturating_scan(rng, 0.0f), near(rng, 0, 0), opt);
  const GridSaturationSummary& sum = fast.saturation_summary();
  ASSERT_EQ(sum.revision, fast.revision());
  // A flagged block about 1 m east of the origin, and a one-ray scan that
  // ends at its center cell.
  const int cx = fast.x_to_idx(1.0), cy = fast.y_to_idx(0.0);
  constexpr int kB = GridSaturationSummary::kBlock;
  const int bx = cx / kB, by = cy / kB;
  ASSERT_EQ(sum.blocks[static_cast<std::size_t>(bx) + static_cast<std::size_t>(by) * sum.blocks_x],
            GridSaturationSummary::kFull);
  const int hx = bx * kB + kB / 2, hy = by * kB + kB / 2;
  const double wx = fast.idx_to_x(static_cast<std::size_t>(hx));
  const double wy = fast.idx_to_y(static_cast<std::size_t>(hy));
  RangeScan2D hit;
  hit.aperture = 1e-6;
  hit.set_ranges(std::vector<float>{static_cast<float>(std::hypot(wx, wy))});
  const Pose2 origin(0.0, 0.0, std::atan2(wy, wx));
  insert_both(fast, slow, hit, origin, opt);
  ASSERT_LT(fast.cell(hx, hy), LogOddsTraits<std::int8_t>::kMax);
  // Rays through the hit cell free it again, one step per scan.
  for (int k = 0; k < 10; ++k) {
    SCOPED_TRACE(k);
    insert_both(fast, slow, saturating_scan(rng, 0.0f), Pose2(0.0, 0.0, 0.001 * k), opt);
  }
}

// Every other way of writing cells makes the summary stale, so the next
// insertion does not skip the cells that were changed.
TEST(GridInsertionOracle, ExternalWritesInvalidateSummary) {
  GridInsertionOptions opt;
  opt.max_distance_insertion = 3.0f;
  const auto saturated = [&](std::mt19937& rng, OccupancyGrid& fast, OccupancyGrid& slow) {
    fast = OccupancyGrid(-4, 4, -4, 4, 0.05f);
    slow = fast;
    for (int k = 0; k < 40; ++k) insert_both(fast, slow, saturating_scan(rng, 0.0f), near(rng, 0, 0), opt);
    ASSERT_GT(expect_summary_sound(fast), 6400u);
  };
  // Cells 1 m east of the origin (inside saturated blocks).
  const auto write = [](OccupancyGrid& g, int kind) {
    const int cx = g.x_to_idx(1.0), cy = g.y_to_idx(0.0);
    switch (kind) {
      case 0: g.set_cell(cx, cy, 0); break;
      case 1: g.set_free_probability(cx + 1, cy, 0.2f); break;
      case 2: g.update_cell(cx, cy + 1, 0.1f); break;
      case 3: g.mutable_cells()[g.index(cx - 1, cy)] = -20; break;
      case 4: g.fill(0.5f); break;
      case 5:
        g.assign(g.x_min(), g.x_max(), g.y_min(), g.y_max(), g.resolution(), g.size_x(),
                 g.size_y(), std::vector<std::int8_t>(g.cells().size(), 0));
        break;
      default: g.set_size(-4, 4, -4, 4, 0.05f); break;
    }
  };
  for (int kind = 0; kind < 7; ++kind) {
    SCOPED_TRACE(kind);
    std::mt19937 rng(static_cast<unsigned>(100 + kind));
    OccupancyGrid fast, slow;
    saturated(rng, fast, slow);
    write(fast, kind);
    write(slow, kind);
    EXPECT_EQ(expect_summary_sound(fast), 0u);  // stale
    for (int k = 0; k < 3; ++k) {
      insert_both(fast, slow, saturating_scan(rng, 0.0f), Pose2(0.0, 0.0, 0.3 * k), opt);
    }
  }
  // A copy carries the summary with the cells it describes.
  std::mt19937 rng(3);
  OccupancyGrid fast, slow;
  saturated(rng, fast, slow);
  OccupancyGrid copy = fast, copy_slow = slow;
  EXPECT_GT(expect_summary_sound(copy), 100u);
  write(fast, 0);
  write(slow, 0);
  const RangeScan2D scan = saturating_scan(rng, 0.0f);
  insert_both(copy, copy_slow, scan, Pose2(), opt);
  insert_both(fast, slow, scan, Pose2(), opt);
  EXPECT_FALSE(copy == fast);  // the write reached fast only
}

}  // namespace
}  // namespace rove
