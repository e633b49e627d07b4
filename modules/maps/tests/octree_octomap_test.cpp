// OccupancyOctree against OctoMap 1.9.7 on scan.dat (the 3D scan of
// OctoMap's own tests, datasets/octree in the shared datasets): the reference files under
// data/reference/octomap/ were written by tools/octomap_reference.
#include <map>

#include <gtest/gtest.h>

#include "rove/octree_reference_files.h"
#include "rove/maps/occupancy_octree.h"
#include "rove/test_data.h"

namespace rove {
namespace {

using octree_test::expect_rays_match;
using octree_test::expect_tree_matches;
using octree_test::read_ref_tree;

const std::vector<Eigen::Vector3f>& scan() {
  static const std::vector<Eigen::Vector3f> pts =
      octree_test::read_scan_dat(test_data::shared_dataset("octree/scan.dat.bz2"));
  return pts;
}

OccupancyOctree insert_scan(double res, OctreeInsertOptions opt) {
  OccupancyOctree t(res);
  const auto r = t.insert_point_cloud(scan(), Eigen::Vector3d::Zero(), opt);
  EXPECT_TRUE(r.ok()) << r.message;
  return t;
}

TEST(OctreeOctoMapDatasets, ScanHas88206Points) { EXPECT_EQ(scan().size(), 88206u); }

// The acceptance test: every node's log-odds equals OctoMap's, after
// pruning the same nodes, at 0.2, 0.1 and 0.05 m.
TEST(OctreeOctoMapDatasets, ScanTreesEqualOctoMapsAtThreeResolutions) {
  for (const char* res : {"0.2", "0.1", "0.05"}) {
    SCOPED_TRACE(res);
    const auto ref = read_ref_tree(std::string("octomap_scan_tree_") + res + ".bin.gz");
    for (int threads : {1, 2}) {
      SCOPED_TRACE(threads);
      OctreeInsertOptions opt;
      opt.arithmetic = OctreeRayArithmetic::OctoMap;
      opt.num_threads = threads;
      expect_tree_matches(insert_scan(std::stod(res), opt), ref, 0.0f);
    }
  }
}

// Double arithmetic differs from OctoMap's float only for rays through cell
// borders: a handful of cells.
TEST(OctreeOctoMapDatasets, DoubleArithmeticAgreesOnAlmostEveryCell) {
  const auto ref = read_ref_tree("octomap_scan_tree_0.1.bin.gz");
  OccupancyOctree octomap(0.1);
  {
    std::vector<OctreeNodeRecord> nodes(ref.nodes);
    for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i].log_odds = ref.log_odds[i], nodes[i].child_mask = ref.masks[i];
    octomap.assign_preorder(nodes);
  }
  const OccupancyOctree mine = insert_scan(0.1, {});
  std::size_t differ = 0, cells = 0;
  octomap.for_each_leaf([&](const OctreeLeaf& l) {
    ++cells;
    const auto n = mine.search(l.key);
    if (!n || n->log_odds != l.log_odds) ++differ;
  });
  RecordProperty("leaves_differing", static_cast<int>(differ));
  EXPECT_LT(static_cast<double>(differ), 1e-3 * static_cast<double>(cells)) << differ << " of " << cells;
  EXPECT_NEAR(static_cast<double>(mine.num_nodes()), static_cast<double>(ref.nodes), 1e-3 * static_cast<double>(ref.nodes));
}

TEST(OctreeOctoMapDatasets, InsertionModesEqualOctoMaps) {
  struct Case {
    const char* file;
    OctreeUpdateMode mode;
    double max_range;
  };
  for (const Case& c : {Case{"octomap_scan_discrete_0.2.bin.gz", OctreeUpdateMode::Discretized, -1.0},
                        Case{"octomap_scan_maxrange5_0.2.bin.gz", OctreeUpdateMode::OncePerScan, 5.0},
                        Case{"octomap_scan_rays_0.2.bin.gz", OctreeUpdateMode::EveryRay, -1.0}}) {
    SCOPED_TRACE(c.file);
    for (int threads : {1, 2}) {
      OctreeInsertOptions opt;
      opt.arithmetic = OctreeRayArithmetic::OctoMap;
      opt.mode = c.mode;
      opt.max_range = c.max_range;
      opt.num_threads = threads;
      expect_tree_matches(insert_scan(0.2, opt), read_ref_tree(c.file), 0.0f);
    }
  }
}

TEST(OctreeOctoMapDatasets, MovingScansAndChangeDetectionEqualOctoMaps) {
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    OccupancyOctree t(0.2);
    OctreeInsertOptions opt;
    opt.arithmetic = OctreeRayArithmetic::OctoMap;
    opt.num_threads = threads;
    t.enable_change_detection(true);
    t.insert_point_cloud(scan(), Eigen::Vector3d::Zero(), opt);
    t.reset_changes();
    t.insert_point_cloud(scan(), Eigen::Vector3d(0.3f, -0.2f, 0.1f), opt);
    octree_test::RefReader r("octomap_scan_multi_changes_0.2.bin.gz");
    r.expect_magic("OCTCHNG1");
    const auto n = r.get<std::uint64_t>();
    const auto changes = t.changes();
    ASSERT_EQ(changes.size(), n);
    for (const auto& c : changes) {
      OctreeKey k;
      k.x = r.get<std::uint16_t>(), k.y = r.get<std::uint16_t>(), k.z = r.get<std::uint16_t>();
      EXPECT_EQ(c.key, k);
      EXPECT_EQ(c.created, r.get<std::uint8_t>() != 0);
    }
    t.insert_point_cloud(scan(), Eigen::Vector3d(-0.5f, 0.4f, 0.25f), opt);
    t.insert_point_cloud(scan(), Eigen::Vector3d::Zero(), opt);
    expect_tree_matches(t, read_ref_tree("octomap_scan_multi_0.2.bin.gz"), 0.0f);
  }
}

TEST(OctreeOctoMapDatasets, CastRayEqualsOctoMapsOnRandomRays) {
  OctreeInsertOptions opt;
  opt.arithmetic = OctreeRayArithmetic::OctoMap;
  const OccupancyOctree t = insert_scan(0.1, opt);
  EXPECT_EQ(expect_rays_match(t, "octomap_scan_castray_0.1.bin.gz"), 10000u);
}

}  // namespace
}  // namespace rove
