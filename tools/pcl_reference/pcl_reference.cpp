// Writes PCL 1.13's view of the shared point clouds as text, one record per
// line:
//   cloud <name> <points>
//   point <name> <index> <x> <y> <z>            (%.9g: exact floats)
//   voxel <name> <leaf> <voxels>
//   centroid <name> <leaf> <rank> <x> <y> <z>   (ranks 0, 1, mid, last)
//   knn <name> <qx> <qy> <qz> <k> <index> <sq_distance> ...
#include <cstdio>
#include <string>
#include <vector>

#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <pointcloud dataset dir> <output file>\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  std::FILE* out = std::fopen(argv[2], "w");
  if (!out) return 1;
  struct Input {
    std::string name;
    bool ply;
  };
  for (const Input& in : {Input{"room_scan1.pcd", false}, Input{"room_scan2.pcd", false}, Input{"bunny.pcd", false},
                          Input{"small_gicp_source.ply", true}}) {
    pcl::PointCloud<pcl::PointXYZ>::Ptr c(new pcl::PointCloud<pcl::PointXYZ>);
    const int rc = in.ply ? pcl::io::loadPLYFile(dir + "/" + in.name, *c) : pcl::io::loadPCDFile(dir + "/" + in.name, *c);
    if (rc != 0) {
      std::fprintf(stderr, "cannot load %s\n", in.name.c_str());
      return 1;
    }
    const std::size_t n = c->size();
    std::fprintf(out, "cloud %s %zu\n", in.name.c_str(), n);
    for (std::size_t i : {std::size_t{0}, std::size_t{1}, n / 2, n - 1})
      std::fprintf(out, "point %s %zu %.9g %.9g %.9g\n", in.name.c_str(), i, (*c)[i].x, (*c)[i].y, (*c)[i].z);
    const float leaf = in.name == "bunny.pcd" ? 0.01f : 0.1f;
    pcl::VoxelGrid<pcl::PointXYZ> vg;
    vg.setInputCloud(c);
    vg.setLeafSize(leaf, leaf, leaf);
    pcl::PointCloud<pcl::PointXYZ> v;
    vg.filter(v);
    std::fprintf(out, "voxel %s %.9g %zu\n", in.name.c_str(), leaf, v.size());
    for (std::size_t r : {std::size_t{0}, std::size_t{1}, v.size() / 2, v.size() - 1})
      std::fprintf(out, "centroid %s %.9g %zu %.9g %.9g %.9g\n", in.name.c_str(), leaf, r, v[r].x, v[r].y, v[r].z);
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    tree.setInputCloud(c);
    for (std::size_t qi : {n / 3, n / 5}) {
      pcl::PointXYZ q((*c)[qi].x + 0.013f, (*c)[qi].y - 0.007f, (*c)[qi].z + 0.005f);
      std::vector<int> idx(5);
      std::vector<float> d(5);
      tree.nearestKSearch(q, 5, idx, d);
      std::fprintf(out, "knn %s %.9g %.9g %.9g 5", in.name.c_str(), q.x, q.y, q.z);
      for (int k = 0; k < 5; ++k) std::fprintf(out, " %d %.9g", idx[static_cast<std::size_t>(k)], d[static_cast<std::size_t>(k)]);
      std::fprintf(out, "\n");
    }
  }
  std::fclose(out);
  return 0;
}
