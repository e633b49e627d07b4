// OctoMap's .bt and .ot files: round trips, OctoMap's own files byte for
// byte, bad input.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "rove/octree_reference_files.h"
#include "rove/octree_test_support.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/octree_files.h"
#include "rove/test_data.h"

namespace rove {
namespace {

using octree_test::expect_same_tree;

std::string ref_bytes(const std::string& name) {
  const octree_test::RefReader r(name);
  return std::string(r.bytes().begin(), r.bytes().end());
}

OccupancyOctree random_tree(OctreeChannels channels = OctreeChannels::None, std::uint64_t seed = 5) {
  OccupancyOctree t(0.05, {}, channels);
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 3000; ++i) {
    const OctreeKey k{static_cast<std::uint16_t>(32750 + rng() % 40), static_cast<std::uint16_t>(32750 + rng() % 40),
                      static_cast<std::uint16_t>(32760 + rng() % 8)};
    t.update_node(k, rng() % 3 == 0);
    if (has_channels(channels, OctreeChannels::Color)) {
      t.update_color(k, Rgb8{static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()), 7},
                     OctreeColorUpdate::Average);
    }
  }
  return t;
}

TEST(OctreeFiles, FullFilesRoundTripExactly) {
  for (const auto ch : {OctreeChannels::None, OctreeChannels::Color}) {
    const OccupancyOctree t = random_tree(ch);
    const std::string bytes = octree_full_bytes(t);
    const OccupancyOctree u = parse_octree(bytes, "<test>");
    expect_same_tree(t, u);
    EXPECT_EQ(octree_full_bytes(u), bytes);
    EXPECT_EQ(u.resolution(), 0.05);
  }
}

TEST(OctreeFiles, BinaryFilesKeepOccupancyAndStructure) {
  const OccupancyOctree t = random_tree();
  const std::string bytes = octree_binary_bytes(t);
  const OccupancyOctree u = parse_octree(bytes, "<test>");
  EXPECT_EQ(u.num_nodes(), t.num_nodes());
  std::size_t leaves = 0;
  t.for_each_leaf([&](const OctreeLeaf& l) {
    ++leaves;
    const auto n = u.search(l.key, l.depth);
    ASSERT_TRUE(n.has_value());
    EXPECT_EQ(n->depth, l.depth);
    EXPECT_EQ(n->log_odds, t.is_occupied(l.log_odds) ? u.clamp_max_log_odds() : u.clamp_min_log_odds());
  });
  EXPECT_EQ(u.num_leaves(), leaves);
  EXPECT_EQ(octree_binary_bytes(u), bytes);
  // The maximum-likelihood file: pruned further, same occupancy.
  const std::string ml = octree_binary_bytes(t, OctreeBinaryContent::MaxLikelihood);
  EXPECT_LE(ml.size(), bytes.size());
  const OccupancyOctree v = parse_octree(ml, "<test>");
  t.for_each_leaf([&](const OctreeLeaf& l) {
    EXPECT_EQ(v.is_occupied(v.search(l.key)->log_odds), t.is_occupied(l.log_odds));
  });
  EXPECT_EQ(octree_binary_bytes(v, OctreeBinaryContent::MaxLikelihood), ml);
}

// Found by rove_octree_fuzz: a ColorOcTree's .bt read back as a plain tree
// and wrote back with another id.
TEST(OctreeFiles, ColorTreeBinaryFileKeepsItsType) {
  const OccupancyOctree t = random_tree(OctreeChannels::Color, 3);
  const std::string bytes = octree_binary_bytes(t);
  ASSERT_NE(bytes.find("id ColorOcTree\n"), std::string::npos);
  const OccupancyOctree u = parse_octree(bytes, "<test>");
  EXPECT_EQ(u.channels(), OctreeChannels::Color);
  EXPECT_EQ(octree_binary_bytes(u), bytes);
  u.for_each_leaf([&](const OctreeLeaf& l) { EXPECT_EQ(u.color_at(l.key), (Rgb8{255, 255, 255})); });
}

TEST(OctreeFiles, HeaderIsOctoMaps) {
  OccupancyOctree t(0.123456789);
  EXPECT_EQ(octree_binary_bytes(t),
            "# Octomap OcTree binary file\n# (feel free to add / change comments, but leave the first line as it "
            "is!)\n#\nid OcTree\nsize 0\nres 0.123457\ndata\n");
  EXPECT_EQ(parse_octree(octree_full_bytes(OccupancyOctree(1e-5)), "<t>").resolution(), 1e-5);
  EXPECT_NE(octree_full_bytes(OccupancyOctree(0.05, {}, OctreeChannels::Color)).find("id ColorOcTree\n"),
            std::string::npos);
  // A header as OctoMap accepts it: comments, unknown words, the old id.
  const std::string h = "# Octomap OcTree file\n# x\nfoo bar\nid 1\n  size 1 res 0.5\n# c\ndata   \n";
  std::string one = h;
  const float v = 0.5f;
  one.append(reinterpret_cast<const char*>(&v), 4);
  one.push_back('\0');
  const OccupancyOctree u = parse_octree(one, "<t>");
  EXPECT_EQ(u.num_nodes(), 1u);
  EXPECT_EQ(u.search(OctreeKey{1, 2, 3})->log_odds, 0.5f);
  EXPECT_EQ(parse_octree_header(one, "<t>").id, "OcTree");
}

TEST(OctreeFiles, LegacyBinaryHeaderIsRead) {
  const OccupancyOctree t = random_tree();
  const std::string modern = octree_binary_bytes(t);
  const std::size_t data = parse_octree_header(modern, "<t>").data_offset;
  std::string legacy(16, '\0');
  const std::int32_t type = 3;
  const double res = 0.05;
  const auto size = static_cast<std::uint32_t>(t.num_nodes());
  std::memcpy(legacy.data(), &type, 4);
  std::memcpy(legacy.data() + 4, &res, 8);
  std::memcpy(legacy.data() + 12, &size, 4);
  legacy += modern.substr(data);
  const OccupancyOctree u = parse_octree(legacy, "<legacy>");
  EXPECT_TRUE(parse_octree_header(legacy, "<legacy>").legacy);
  EXPECT_EQ(octree_binary_bytes(u), modern);
}

void expect_parse_error(const std::string& bytes, const std::string& field) {
  try {
    parse_octree(bytes, "bad.bt");
    ADD_FAILURE() << "no error for field " << field;
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, field) << e.what();
    EXPECT_EQ(e.location().source, "bad.bt");
    EXPECT_TRUE(e.location().offset.has_value());
  }
}

TEST(OctreeFiles, MalformedFilesAreParseErrors) {
  const std::string head = "# Octomap OcTree binary file\nid OcTree\n";
  expect_parse_error("", "header");
  expect_parse_error("hello\n", "header");
  expect_parse_error(head + "size 0\nres 0.1\n", "data");
  expect_parse_error("# Octomap OcTree binary file\nsize 0\nres 0.1\ndata\n", "id");
  expect_parse_error(head + "size 0\nres 0\ndata\n", "res");
  expect_parse_error(head + "size 0\nres -0.1\ndata\n", "res");
  expect_parse_error(head + "size 0\nres nan\ndata\n", "res");
  expect_parse_error(head + "size 0\nres 0.1x\ndata\n", "res");
  expect_parse_error(head + "size 0\nres 1e-320\ndata\n", "res");  // subnormal: its inverse overflows
  expect_parse_error(head + "size 0\nres 1e305\ndata\n", "res");   // the tree's extent overflows
  expect_parse_error(head + "size 0\ndata\n", "res");
  expect_parse_error(head + "size -1\nres 0.1\ndata\n", "size");
  expect_parse_error(head + "size\n", "size");
  expect_parse_error(head + "size 1\nres 0.1\ndata\n", "node");            // no data for 1 node
  expect_parse_error(head + "size 2\nres 0.1\ndata\n\x01", "node");        // truncated record
  expect_parse_error(head + "size 9\nres 0.1\ndata\n\x01", "size");        // 9 nodes cannot fit in a byte
  expect_parse_error(head + "size 2\nres 0.1\ndata\n\x00\x00", "size");    // only 1 node
  expect_parse_error(head + "size 0\nres 0.1\ndata\nXY", "data");          // bytes after the tree
  expect_parse_error(head + "size 18446744073709551615\nres 0.1\ndata\n\x03\x00", "size");
  // An inner node (code 11) whose record lists no child.
  expect_parse_error(head + "size 2\nres 0.1\ndata\n" + std::string("\x03\x00\x00\x00", 4), "node");
  // A chain of inner nodes deeper than 16 levels.
  std::string deep = head + "size 20\nres 0.1\ndata\n";
  for (int i = 0; i < 18; ++i) deep += std::string("\x03\x00", 2);
  expect_parse_error(deep, "node");
  // .ot: a NaN log-odds, an unknown tree type, truncated.
  std::string ot = "# Octomap OcTree file\nid OcTree\nsize 1\nres 0.1\ndata\n";
  const float nan = std::nanf("");
  std::string bad = ot;
  bad.append(reinterpret_cast<const char*>(&nan), 4);
  bad.push_back('\0');
  expect_parse_error(bad, "log-odds");
  expect_parse_error("# Octomap OcTree file\nid CountingOcTree\nsize 0\nres 0.1\ndata\n", "id");
  expect_parse_error(ot + "\x01\x02", "size");  // a node takes 5 bytes
  expect_parse_error(ot + std::string("\x00\x00\x80\x3f\x00\x07", 6), "data");  // a byte after the tree
}

TEST(OctreeFiles, EveryTruncationAndCorruptionIsHandled) {
  const OccupancyOctree t = random_tree(OctreeChannels::Color, 9);
  for (const std::string& bytes : {octree_binary_bytes(t), octree_full_bytes(t)}) {
    // Every prefix is refused (the last byte completes the tree).
    for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 64) {
      EXPECT_THROW(parse_octree(bytes.substr(0, n), "<cut>"), ParseError) << n;
    }
    // Flipped bytes: a clear error or a valid tree, never a crash.
    std::mt19937_64 rng(1);
    for (int i = 0; i < 300; ++i) {
      std::string c = bytes;
      c[rng() % c.size()] = static_cast<char>(rng());
      try {
        const OccupancyOctree u = parse_octree(c, "<flip>");
        EXPECT_EQ(parse_octree(octree_full_bytes(u), "<again>").num_nodes(), u.num_nodes());
      } catch (const ParseError&) {
      } catch (const ResourceError&) {
      }
    }
  }
}

TEST(OctreeFiles, WritesAtomically) {
  const OccupancyOctree t = random_tree();
  const std::string path = ::testing::TempDir() + "/rove_octree_test.bt";
  write_octree(path, t, OctreeFileFormat::Binary);
  const OccupancyOctree u = read_octree(path);
  EXPECT_EQ(u.num_nodes(), t.num_nodes());
  write_octree(path, t, OctreeFileFormat::Full);
  expect_same_tree(read_octree(path), t);
  EXPECT_THROW(read_octree(path + ".missing"), IoError);
}

// OctoMap's own files of the scan, written by rove byte for byte.
TEST(OctreeFilesDatasets, OctoMapsScanFilesAreReproducedByteForByte) {
  const auto pts = octree_test::read_scan_dat(test_data::shared_dataset("octree/scan.dat.bz2"));
  OctreeInsertOptions opt;
  opt.arithmetic = OctreeRayArithmetic::OctoMap;
  OccupancyOctree t(0.2);
  t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), opt);
  const std::string ot = ref_bytes("octomap_scan_0.2.ot.gz");
  EXPECT_EQ(octree_full_bytes(t), ot);
  expect_same_tree(parse_octree(ot, "octomap_scan_0.2.ot"), t);
  EXPECT_EQ(octree_binary_bytes(t), ref_bytes("octomap_scan_0.2.bt.gz"));
  // The coloured tree: insertion, then OctoMap's integrateNodeColor per point.
  OccupancyOctree c(0.2, {}, OctreeChannels::Color);
  std::vector<Rgb8> colors;
  for (const auto& p : pts) {
    colors.push_back(Rgb8{static_cast<std::uint8_t>(static_cast<int>(std::floor(std::fabs(p.x()) * 37.0f)) % 256),
                          static_cast<std::uint8_t>(static_cast<int>(std::floor(std::fabs(p.y()) * 53.0f)) % 256),
                          static_cast<std::uint8_t>(static_cast<int>(std::floor(std::fabs(p.z()) * 71.0f)) % 256)});
  }
  c.insert_point_cloud(pts, colors, Eigen::Vector3d::Zero(), opt, OctreeColorUpdate::Integrate);
  EXPECT_EQ(octree_full_bytes(c), ref_bytes("octomap_scan_color_0.2.ot.gz"));
}

TEST(OctreeFilesDatasets, Geb079ReadsWritesBackAndAnswersAsOctoMap) {
  const std::string path = test_data::shared_dataset("octree/geb079.bt");
  const std::string bytes = read_input_file(path, 1u << 30);
  const OccupancyOctree t = read_octree(path);
  EXPECT_EQ(t.num_nodes(), 532566u);
  EXPECT_EQ(t.num_leaves(), 428144u);
  EXPECT_EQ(t.resolution(), 0.08);
  EXPECT_EQ(octree_binary_bytes(t), bytes);
  EXPECT_EQ(octree_binary_bytes(t, OctreeBinaryContent::MaxLikelihood), bytes);
  // search() at 100,000 random points, as OctoMap answered.
  octree_test::RefReader r("octomap_geb079_queries.bin.gz");
  r.expect_magic("OCTQUER1");
  const auto cases = octree_test::read_cases_header(r);
  std::vector<float> palette(r.get<std::uint32_t>());
  for (float& v : palette) v = r.get<float>();
  octree_reference::SplitMix64 g{cases.seed};
  std::size_t bad = 0, known = 0;
  for (std::uint64_t i = 0; i < cases.n; ++i) {
    float p[3];
    octree_reference::random_point(g, cases.box, p);
    const auto code = r.get<std::uint16_t>();
    const auto n = t.search(Eigen::Vector3d(p[0], p[1], p[2]));
    known += code != 0 ? 1 : 0;
    if ((code == 0) != !n.has_value() || (n && n->log_odds != palette.at(code - 1u))) ++bad;
  }
  EXPECT_EQ(cases.n, 100000u);
  EXPECT_EQ(bad, 0u);
  EXPECT_GT(known, 10000u);
  EXPECT_TRUE(r.at_end());
  EXPECT_EQ(octree_test::expect_rays_match(t, "octomap_geb079_castray.bin.gz"), 10000u);
}

}  // namespace
}  // namespace rove
