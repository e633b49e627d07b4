// Writes OctoMap 1.9.7's results on the shared octree datasets, for rove's
// octree tests to compare against.
//
// Usage: rove_octomap_reference <scan.dat (plain text)> <geb079.bt> <output dir>
//
// Every output is gzip-compressed little-endian binary (formats in
// data/reference/README.md):
//   octomap_scan_tree_<res>.bin.gz   scan.dat inserted from (0,0,0) at 0.2, 0.1,
//                                      0.05 m with insertPointCloud (defaults)
//   octomap_scan_<mode>_0.2.bin.gz     discrete, maxrange5, rays (insertPointCloudRays),
//                                      multi (four scans from moving origins, with
//                                      change detection over the second)
//   octomap_scan_castray_0.1.bin.gz    castRay on random rays, tree of scan.dat at 0.1 m
//   octomap_geb079_queries.bin.gz      search() at 100,000 random points of geb079.bt
//   octomap_geb079_castray.bin.gz      castRay on random rays in geb079.bt
//   octomap_scan_0.2.ot, octomap_scan_0.2.bt, octomap_scan_color_0.2.ot
//                                      OctoMap's own files of small trees
// and prints whether geb079.bt written back with writeBinaryConst is
// byte-identical to the input.
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <zlib.h>

#include "rove/octree_reference_cases.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace {

namespace ref = rove::octree_reference;

class GzOut {
 public:
  explicit GzOut(const std::string& path) : f_(gzopen(path.c_str(), "wb9")) {
    if (f_ == nullptr) {
      std::fprintf(stderr, "cannot write %s\n", path.c_str());
      std::exit(1);
    }
  }
  ~GzOut() { gzclose(f_); }
  GzOut(const GzOut&) = delete;
  GzOut& operator=(const GzOut&) = delete;
  template <typename T>
  void put(const T& v) {
    gzwrite(f_, &v, sizeof(T));
  }
  void magic(const char (&m)[9]) { gzwrite(f_, m, 8); }
  void bytes(const void* p, std::size_t n) {
    if (n > 0) gzwrite(f_, p, static_cast<unsigned>(n));
  }

 private:
  gzFile f_;
};

octomap::Pointcloud read_scan(const std::string& path) {
  std::ifstream in(path);
  octomap::Pointcloud cloud;
  float x, y, z;
  while (in >> x >> y >> z) cloud.push_back(x, y, z);
  return cloud;
}

// Distinct log-odds values of a tree, in order of first appearance.
class Palette {
 public:
  std::uint16_t index(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof v);
    const auto [it, inserted] = map_.emplace(bits, static_cast<std::uint16_t>(values_.size()));
    if (inserted) {
      if (values_.size() == 65535) {
        std::fprintf(stderr, "more than 65535 distinct log-odds values\n");
        std::exit(1);
      }
      values_.push_back(v);
    }
    return it->second;
  }
  void write(GzOut& f) const {
    f.put(static_cast<std::uint32_t>(values_.size()));
    for (float v : values_) f.put(v);
  }

 private:
  std::map<std::uint32_t, std::uint16_t> map_;
  std::vector<float> values_;
};

void tree_bytes(const octomap::OcTree& t, const octomap::OcTreeNode* n, Palette& pal,
                std::vector<std::uint8_t>& out) {
  std::uint8_t mask = 0;
  for (unsigned i = 0; i < 8; ++i) mask |= t.nodeChildExists(n, i) ? (1u << i) : 0u;
  const std::uint16_t v = pal.index(n->getLogOdds());
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(mask);
  for (unsigned i = 0; i < 8; ++i) {
    if (t.nodeChildExists(n, i)) tree_bytes(t, t.getNodeChild(n, i), pal, out);
  }
}

// "OCTTREE1", f64 resolution, u64 nodes, u64 leaves, u32 palette size, f32
// palette[], then every node in depth-first pre-order (children 0..7): u16
// palette index of its log-odds, u8 mask of existing children.
void write_tree(const std::string& path, const octomap::OcTree& tree) {
  Palette pal;
  std::vector<std::uint8_t> bytes;
  if (tree.getRoot() != nullptr) tree_bytes(tree, tree.getRoot(), pal, bytes);
  GzOut f(path);
  f.magic("OCTTREE1");
  f.put(tree.getResolution());
  f.put(static_cast<std::uint64_t>(tree.size()));
  f.put(static_cast<std::uint64_t>(tree.getNumLeafNodes()));
  pal.write(f);
  f.bytes(bytes.data(), bytes.size());
  std::printf("%s: %zu nodes, %zu leaves\n", path.c_str(), tree.size(), tree.getNumLeafNodes());
}

// "OCTCHNG1", u64 n, then per changed key (sorted): u16 x, y, z, u8 new.
void write_changes(const std::string& path, const octomap::OcTree& tree) {
  std::vector<std::tuple<std::uint16_t, std::uint16_t, std::uint16_t, std::uint8_t>> c;
  for (auto it = tree.changedKeysBegin(); it != tree.changedKeysEnd(); ++it) {
    c.emplace_back(it->first[0], it->first[1], it->first[2], it->second ? 1 : 0);
  }
  std::sort(c.begin(), c.end());
  GzOut f(path);
  f.magic("OCTCHNG1");
  f.put(static_cast<std::uint64_t>(c.size()));
  for (const auto& [x, y, z, n] : c) f.put(x), f.put(y), f.put(z), f.put(n);
  std::printf("%s: %zu changed keys\n", path.c_str(), c.size());
}

void put_cases_header(GzOut& f, std::uint64_t seed, const ref::Box& box, std::size_t n) {
  f.put(ref::kCasesVersion);
  f.put(seed);
  for (float v : box.lo) f.put(v);
  for (float v : box.hi) f.put(v);
  f.put(static_cast<std::uint64_t>(n));
}

// "OCTRAYS1", u32 cases version, u64 seed, f32 box lo[3], hi[3], u64 n, then
// per ray of ref::random_ray: u8 castRay's result, u16 key[3] of its end.
void write_rays(const std::string& path, const octomap::OcTree& tree, const ref::Box& box,
                std::size_t n, std::uint64_t seed) {
  ref::SplitMix64 g{seed};
  GzOut f(path);
  f.magic("OCTRAYS1");
  put_cases_header(f, seed, box, n);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const ref::RayCase c = ref::random_ray(g, box, i);
    const octomap::point3d o(c.origin[0], c.origin[1], c.origin[2]);
    const octomap::point3d d(c.direction[0], c.direction[1], c.direction[2]);
    octomap::point3d end;
    const bool hit = tree.castRay(o, d, end, c.ignore_unknown, c.max_range);
    hits += hit ? 1 : 0;
    const octomap::OcTreeKey k = tree.coordToKey(end);
    f.put(static_cast<std::uint8_t>(hit));
    f.put(k[0]), f.put(k[1]), f.put(k[2]);
  }
  std::printf("%s: %zu rays, %zu hits\n", path.c_str(), n, hits);
}

// "OCTQUER1", u32 cases version, u64 seed, f32 box lo[3], hi[3], u64 n,
// u32 palette size, f32 palette[], then per point of ref::random_point:
// u16 0 when search() found no node, else 1 + palette index of its log-odds.
void write_queries(const std::string& path, const octomap::OcTree& tree, const ref::Box& box,
                   std::size_t n, std::uint64_t seed) {
  ref::SplitMix64 g{seed};
  Palette pal;
  std::vector<std::uint8_t> out;
  std::size_t found = 0;
  for (std::size_t i = 0; i < n; ++i) {
    float p[3];
    ref::random_point(g, box, p);
    const octomap::OcTreeNode* node = tree.search(octomap::point3d(p[0], p[1], p[2]));
    const std::uint16_t v = node == nullptr ? 0 : static_cast<std::uint16_t>(1 + pal.index(node->getLogOdds()));
    out.push_back(static_cast<std::uint8_t>(v & 0xFF));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    found += node != nullptr ? 1 : 0;
  }
  GzOut f(path);
  f.magic("OCTQUER1");
  put_cases_header(f, seed, box, n);
  pal.write(f);
  f.bytes(out.data(), out.size());
  std::printf("%s: %zu points, %zu known\n", path.c_str(), n, found);
}

ref::Box metric_box(const octomap::OcTree& tree, float margin) {
  double x0, y0, z0, x1, y1, z1;
  tree.getMetricMin(x0, y0, z0);
  tree.getMetricMax(x1, y1, z1);
  return ref::Box{{static_cast<float>(x0) - margin, static_cast<float>(y0) - margin,
                   static_cast<float>(z0) - margin},
                  {static_cast<float>(x1) + margin, static_cast<float>(y1) + margin,
                   static_cast<float>(z1) + margin}};
}

// A deterministic colour per point, as rove's test computes it.
void point_color(const octomap::point3d& p, std::uint8_t& r, std::uint8_t& g, std::uint8_t& b) {
  r = static_cast<std::uint8_t>(static_cast<int>(std::floor(std::fabs(p.x()) * 37.0f)) % 256);
  g = static_cast<std::uint8_t>(static_cast<int>(std::floor(std::fabs(p.y()) * 53.0f)) % 256);
  b = static_cast<std::uint8_t>(static_cast<int>(std::floor(std::fabs(p.z()) * 71.0f)) % 256);
}

void scan_modes(const octomap::Pointcloud& cloud, const octomap::point3d& origin, const std::string& dir) {
  {
    octomap::OcTree t(0.2);
    t.insertPointCloud(cloud, origin, -1.0, false, true);
    write_tree(dir + "/octomap_scan_discrete_0.2.bin.gz", t);
  }
  {
    octomap::OcTree t(0.2);
    t.insertPointCloud(cloud, origin, 5.0);
    write_tree(dir + "/octomap_scan_maxrange5_0.2.bin.gz", t);
  }
  {
    octomap::OcTree t(0.2);
    t.insertPointCloudRays(cloud, origin);
    write_tree(dir + "/octomap_scan_rays_0.2.bin.gz", t);
  }
  {
    // Four scans of the same points from moving origins: updates of existing
    // (and pruned) nodes, clamping, change detection over the second scan.
    octomap::OcTree t(0.2);
    t.enableChangeDetection(true);
    t.insertPointCloud(cloud, origin);
    t.resetChangeDetection();
    t.insertPointCloud(cloud, octomap::point3d(0.3f, -0.2f, 0.1f));
    write_changes(dir + "/octomap_scan_multi_changes_0.2.bin.gz", t);
    t.insertPointCloud(cloud, octomap::point3d(-0.5f, 0.4f, 0.25f));
    t.insertPointCloud(cloud, origin);
    write_tree(dir + "/octomap_scan_multi_0.2.bin.gz", t);
  }
}

void small_files(const octomap::Pointcloud& cloud, const octomap::point3d& origin, const std::string& dir) {
  octomap::OcTree t(0.2);
  t.insertPointCloud(cloud, origin);
  t.write(dir + "/octomap_scan_0.2.ot");
  t.writeBinaryConst(dir + "/octomap_scan_0.2.bt");
  octomap::ColorOcTree c(0.2);
  c.insertPointCloud(cloud, origin);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    std::uint8_t r, g, b;
    point_color(cloud[i], r, g, b);
    c.integrateNodeColor(cloud[i].x(), cloud[i].y(), cloud[i].z(), r, g, b);
  }
  c.updateInnerOccupancy();
  c.write(dir + "/octomap_scan_color_0.2.ot");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s <scan.dat> <geb079.bt> <output dir>\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[3];
  const octomap::Pointcloud cloud = read_scan(argv[1]);
  std::printf("scan.dat: %zu points\n", cloud.size());
  const octomap::point3d origin(0.0f, 0.0f, 0.0f);

  for (const char* res : {"0.2", "0.1", "0.05"}) {
    octomap::OcTree t(std::stod(res));
    t.insertPointCloud(cloud, origin);
    write_tree(dir + "/octomap_scan_tree_" + res + ".bin.gz", t);
    if (std::string(res) == "0.1") {
      write_rays(dir + "/octomap_scan_castray_0.1.bin.gz", t,
                 ref::Box{{-2.0f, -2.0f, -0.5f}, {2.0f, 2.0f, 1.5f}}, 10000, 0x5ca11ab1e);
    }
  }
  scan_modes(cloud, origin, dir);
  small_files(cloud, origin, dir);

  std::ifstream in(argv[2], std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream is(bytes);
  octomap::OcTree geb(0.1);
  if (!geb.readBinary(is)) {
    std::fprintf(stderr, "cannot read %s\n", argv[2]);
    return 1;
  }
  std::ostringstream os;
  geb.writeBinaryConst(os);
  std::printf("geb079.bt: %zu nodes, %zu leaves, resolution %g, written back %s\n", geb.size(),
              geb.getNumLeafNodes(), geb.getResolution(),
              os.str() == bytes ? "byte-identical" : "DIFFERENT");
  write_queries(dir + "/octomap_geb079_queries.bin.gz", geb, metric_box(geb, 1.0f), 100000, 0x9eb079);
  write_rays(dir + "/octomap_geb079_castray.bin.gz", geb, metric_box(geb, -0.5f), 10000, 0xca57);
  return 0;
}
