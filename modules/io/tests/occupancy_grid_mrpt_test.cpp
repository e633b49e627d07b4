// Agreement of rove's occupancy grid with MRPT 2.5.8 (references written by
// tools/mrpt_grid_reference from the MRPT datasets). Insertion and the
// likelihoods that insert run in Arithmetic::Mrpt (parity: suites named
// *MrptCompat, ctest label mrpt_compat); rove's default geometry is checked
// against ground truth in occupancy_grid_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rove/io/mrpt_gridmap.h"
#include "rove/io/mrpt_simplemap.h"
#include "rove/io/rawlog_reader.h"
#include "rove/maps/grid_entropy.h"
#include "rove/maps/grid_insertion.h"
#include "rove/maps/grid_likelihood.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/serialization/input_file.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = ROVE_SOURCE_DIR "/modules/io/tests/data/";
const std::string kDatasets = test_data::bundled_file("mrpt/");

struct RefGrid {
  OccupancyGrid grid;
  std::vector<Pose3> poses;
};

RefGrid read_ref(const std::string& name) {
  auto s = open_input_file(kData + name);
  InArchive ar(*s);
  EXPECT_EQ(ar.read_scalar<std::uint32_t>(), 0x44495247u);
  const float x0 = ar.read_scalar<float>(), x1 = ar.read_scalar<float>();
  const float y0 = ar.read_scalar<float>(), y1 = ar.read_scalar<float>();
  const float res = ar.read_scalar<float>();
  const auto sx = ar.read_scalar<std::uint32_t>(), sy = ar.read_scalar<std::uint32_t>();
  std::vector<std::int8_t> cells;
  ar.append_scalars(cells, std::uint64_t{sx} * sy);
  RefGrid r;
  r.grid.assign(x0, x1, y0, y1, res, sx, sy, std::move(cells));
  const auto n = ar.read_scalar<std::uint32_t>();
  for (std::uint32_t i = 0; i < n; ++i) {
    double v[6];
    for (double& d : v) d = ar.read_scalar<double>();
    r.poses.emplace_back(v[0], v[1], v[2], v[3], v[4], v[5]);
  }
  return r;
}

// Where a .gridmap named in a reference file is: MRPT's uwb demo map is
// kept with the test data, the Malaga campus map (860 kB) is read from
// Debian's mrpt-common.
std::string gridmap_path(const std::string& name) {
  return name.rfind("uwb", 0) == 0 ? kData + "grid_uwb_demo.gridmap.gz" : test_data::mrpt_package_file(name);
}

std::vector<std::shared_ptr<const RangeScan2D>> simplemap_scans(const std::string& file) {
  const SimpleMap sm = load_mrpt_simplemap(kDatasets + file);
  std::vector<std::shared_ptr<const RangeScan2D>> out;
  for (const auto& kf : sm.keyframes) {
    for (const auto& o : kf.frame->observations) {
      if (auto s = std::dynamic_pointer_cast<const RangeScan2D>(o)) out.push_back(s);
    }
  }
  return out;
}

std::vector<std::shared_ptr<const RangeScan2D>> rawlog_scans(const std::string& file) {
  const Rawlog log = load_rawlog(kDatasets + file);
  std::vector<std::shared_ptr<const RangeScan2D>> out;
  // As MRPT's getActionObservationPairOrObservation: sensory frames that
  // follow an action (the log's first frame has none and is skipped).
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

struct Agreement {
  std::size_t total = 0, equal = 0, same_class = 0;
};

int cls(std::int8_t c) { return c < 0 ? -1 : (c > 0 ? 1 : 0); }

Agreement compare(const OccupancyGrid& a, const OccupancyGrid& b) {
  Agreement r;
  EXPECT_EQ(a.size_x(), b.size_x());
  EXPECT_EQ(a.size_y(), b.size_y());
  EXPECT_EQ(a.x_min(), b.x_min());
  EXPECT_EQ(a.y_min(), b.y_min());
  if (a.cells().size() != b.cells().size()) return r;
  for (std::size_t i = 0; i < a.cells().size(); ++i) {
    ++r.total;
    r.equal += a.cells()[i] == b.cells()[i];
    r.same_class += cls(a.cells()[i]) == cls(b.cells()[i]);
  }
  return r;
}

void build_and_compare(const std::string& ref_name,
                       const std::vector<std::shared_ptr<const RangeScan2D>>& scans, float res,
                       const GridInsertionOptions& opt) {
  const RefGrid ref = read_ref(ref_name);
  ASSERT_EQ(scans.size(), ref.poses.size());
  OccupancyGrid g(-10, 10, -10, 10, res);
  GridInsertionOptions mrpt = opt;
  mrpt.arithmetic = Arithmetic::Mrpt;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    ASSERT_TRUE(insert_scan(g, *scans[i], ref.poses[i], mrpt).inserted());
  }
  const Agreement a = compare(g, ref.grid);
  ASSERT_GT(a.total, 0u);
  const double eq = static_cast<double>(a.equal) / a.total;
  const double cl = static_cast<double>(a.same_class) / a.total;
  std::printf("%s: %zu cells, %.6f%% equal, %.6f%% same class\n", ref_name.c_str(), a.total,
              100 * eq, 100 * cl);
  EXPECT_GE(cl, 0.99);
  EXPECT_GE(eq, 0.99);
}

// The same insertion in rove's default arithmetic: the rays at the scan's
// own angles move cells near the edges of the aperture (MRPT spaces the
// rays aperture / N apart), but the map is the same map.
TEST(OccupancyGrid, DefaultArithmeticBuildsTheSameMapAsMrpt) {
  const RefGrid ref = read_ref("grid_telecom_005.bin.gz");
  const auto scans = rawlog_scans("2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog");
  OccupancyGrid g(-10, 10, -10, 10, 0.05f);
  for (std::size_t i = 0; i < scans.size(); ++i)
    ASSERT_TRUE(insert_scan(g, *scans[i], ref.poses[i], {}).inserted());
  const Agreement a = compare(g, ref.grid);
  ASSERT_GT(a.total, 0u);
  const double cl = static_cast<double>(a.same_class) / a.total;
  std::printf("telecom, default arithmetic: %zu cells, %.4f%% same class as MRPT's\n", a.total,
              100 * cl);
  EXPECT_GE(cl, 0.95);
}

TEST(OccupancyGridMrptCompat, MalagaSimplemapMatchesMrpt) {
  build_and_compare("grid_malaga_005.bin.gz", simplemap_scans("malaga-cs-fac-building.simplemap.gz"),
                    0.05f, {});
}

TEST(OccupancyGridMrptCompat, LocalizationDemoWideningBeamsMatchesMrpt) {
  GridInsertionOptions o;
  o.widening_beams_with_distance = true;
  o.decimation = 2;
  o.consider_invalid_ranges_as_free_space = false;
  build_and_compare("grid_locdemo_widening_010.bin.gz",
                    simplemap_scans("localization_demo.simplemap.gz"), 0.10f, o);
}

TEST(OccupancyGridMrptCompat, TelecomRawlogAtOdometryMatchesMrpt) {
  build_and_compare("grid_telecom_005.bin.gz",
                    rawlog_scans("2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"), 0.05f,
                    {});
}

TEST(OccupancyGridMrptCompat, LikelihoodsMatchMrptForEveryMethod) {
  const RefGrid ref = read_ref("grid_telecom_005.bin.gz");
  const auto scans = rawlog_scans("2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog");
  std::ifstream in(kData + "grid_likelihood_reference.txt");
  ASSERT_TRUE(in.good());
  std::string line;
  int compared = 0;
  double worst = 0;
  std::map<int, std::unique_ptr<GridLikelihoodModel<std::int8_t>>> models;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::size_t si;
    double dx, dy, dphi, value;
    int method, alt, sq;
    unsigned dec;
    std::string vs;
    ls >> si >> dx >> dy >> dphi >> method >> dec >> alt >> sq >> vs;
    value = std::strtod(vs.c_str(), nullptr);
    GridLikelihoodOptions o;
    o.arithmetic = Arithmetic::Mrpt;
    o.method = static_cast<GridLikelihoodMethod>(method);
    o.lf_decimation = dec;
    o.lf_alternate_average_method = alt != 0;
    o.lf_use_square_dist = sq != 0;
    const Pose3 pose = ref.poses[si] + Pose3(dx, dy, 0, dphi, 0, 0);
    // One model per option set: the per-grid setup is done once.
    const int key = method * 1000 + static_cast<int>(dec) * 10 + alt * 2 + sq;
    auto& model = models[key];
    if (!model) model = std::make_unique<GridLikelihoodModel<std::int8_t>>(ref.grid, o);
    const double mine = model->log_likelihood(*scans[si], pose);
    SCOPED_TRACE(line);
    if (o.method == GridLikelihoodMethod::MeanInformation) {
      // MRPT 2.5.8 returns −inf (its fast cell updates never count).
      EXPECT_TRUE(std::isinf(value) && value < 0);
      EXPECT_TRUE(std::isfinite(mine));
      continue;
    }
    if (o.method == GridLikelihoodMethod::ConsensusOWA) {
      // MRPT 2.5.8 returns 1e-3 for every 2D scan.
      EXPECT_EQ(value, 1e-3);
      EXPECT_TRUE(std::isfinite(mine));
      continue;
    }
    if (std::isinf(value)) {
      EXPECT_EQ(mine, value);
      continue;
    }
    const double rel = std::fabs(mine - value) / std::max(1e-12, std::fabs(value));
    worst = std::max(worst, rel);
    EXPECT_LE(rel, 1e-3) << "mrpt " << value << " rove " << mine;
    ++compared;
  }
  std::printf("likelihoods compared: %d, worst relative difference %.3g\n", compared, worst);
  EXPECT_GT(compared, 100);
}

TEST(OccupancyGridMrpt, GridmapFilesMatchMrptCells) {
  std::ifstream in(kData + "grid_gridmap_digest.txt");
  ASSERT_TRUE(in.good());
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string name, hash;
    unsigned sx, sy;
    float x0, x1, y0, y1, res;
    std::size_t occ, fr;
    ls >> name >> sx >> sy >> x0 >> x1 >> y0 >> y1 >> res >> hash >> occ >> fr;
    const MrptGridmap g = load_mrpt_gridmap(gridmap_path(name));
    EXPECT_EQ(g.grid.size_x(), sx);
    EXPECT_EQ(g.grid.size_y(), sy);
    EXPECT_FLOAT_EQ(g.grid.x_min(), x0);
    EXPECT_FLOAT_EQ(g.grid.y_max(), y1);
    EXPECT_FLOAT_EQ(g.grid.resolution(), res);
    std::uint64_t h = 1469598103934665603ull;
    std::size_t o = 0, f = 0;
    for (const std::int8_t c : g.grid.cells()) {
      h ^= static_cast<std::uint8_t>(c);
      h *= 1099511628211ull;
      o += c < 0;
      f += c > 0;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    EXPECT_EQ(std::string(buf), hash) << name;
    EXPECT_EQ(o, occ);
    EXPECT_EQ(f, fr);
    ++n;
  }
  EXPECT_EQ(n, 2);
}

}  // namespace
}  // namespace rove

namespace rove {
namespace {

// MRPT's computeEntropy on its own grids (tools/mrpt_grid_reference):
// EntropyTable::Mrpt reproduces every number; kExact differs only by the
// unknown cells (value 0) and cells at −1, which MRPT's table zeroes.
TEST(GridEntropyMrptCompat, MatchesMrptComputeEntropyOnMrptGrids) {
  std::ifstream in(kData + "grid_entropy_reference.txt");
  ASSERT_TRUE(in.good());
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string name;
    double H, I, mean_H, mean_I, area;
    std::uint64_t cells;
    ls >> name >> H >> I >> mean_H >> mean_I >> area >> cells;
    ASSERT_FALSE(ls.fail()) << line;
    OccupancyGrid grid;
    if (name.find(".gridmap") != std::string::npos) {
      grid = load_mrpt_gridmap(gridmap_path(name)).grid;
    } else {
      grid = read_ref(name + ".bin.gz").grid;
    }
    const GridEntropy m = grid_entropy(grid, EntropyTable::Mrpt);
    // Same float table, same double sums in the same order: equal to the
    // last digit printed (17 significant).
    EXPECT_DOUBLE_EQ(m.entropy, H) << name;
    EXPECT_DOUBLE_EQ(m.information, I) << name;
    EXPECT_DOUBLE_EQ(m.mean_entropy, mean_H) << name;
    EXPECT_DOUBLE_EQ(m.mean_information, mean_I) << name;
    EXPECT_DOUBLE_EQ(m.mapped_area, area) << name;
    EXPECT_EQ(m.mapped_cells, cells) << name;

    // The exact table: the same sum plus the true entropy of the cells at
    // 0 (ln 2: unknown, not mapped) and −1, which MRPT's table zeroes.
    std::uint64_t at_zero = 0, at_minus_one = 0;
    for (const std::int8_t c : grid.cells()) {
      at_zero += c == 0;
      at_minus_one += c == -1;
    }
    const float p = LogOddsLut<std::int8_t>::instance().l2p(-1);
    const double h_minus_one = -p * std::log(p) - (1 - p) * std::log(1 - p);
    const GridEntropy e = grid_entropy(grid);
    EXPECT_NEAR(e.entropy, H + at_zero * std::log(2.0) + at_minus_one * h_minus_one, 1e-6 * H)
        << name;
    EXPECT_EQ(e.mapped_cells, cells - at_zero) << name;
    EXPECT_GT(at_zero, 0u) << name;
    // Information of the mapped cells lies in [0, 1] each.
    EXPECT_GE(e.information, 0.0);
    EXPECT_LE(e.information, static_cast<double>(e.mapped_cells));
    EXPECT_NEAR(e.mapped_area, static_cast<double>(e.mapped_cells) * grid.resolution() * grid.resolution(),
                1e-6 * e.mapped_area + 1e-9);
    ++n;
  }
  EXPECT_EQ(n, 5);
}

}  // namespace
}  // namespace rove
