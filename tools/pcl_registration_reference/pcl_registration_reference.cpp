// Writes PCL 1.13's NDT result on the PCL tutorial pair, with the tutorial's
// settings, for rove's registration tests.
//
// usage: rove_pcl_registration_reference <datasets/pointcloud> <output dir>
//
// Outputs:
//   room_scan2_approx_voxel_0.2.f32   the source after PCL's
//       ApproximateVoxelGrid (leaf 0.2): N little-endian float32 (x, y, z)
//       triplets, so the test registers exactly the points PCL registered;
//   pcl_ndt_room_reference.txt        settings, the 4×4 T_target_source,
//       iterations, convergence flag, transformation probability.

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include <Eigen/Geometry>
#include <pcl/filters/approximate_voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/registration/ndt.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: " << argv[0] << " <datasets/pointcloud dir> <output dir>\n";
    return 2;
  }
  const std::string in = argv[1], out = argv[2];
  using Cloud = pcl::PointCloud<pcl::PointXYZ>;
  Cloud::Ptr target(new Cloud), source(new Cloud), filtered(new Cloud);
  if (pcl::io::loadPCDFile(in + "/room_scan1.pcd", *target) != 0 ||
      pcl::io::loadPCDFile(in + "/room_scan2.pcd", *source) != 0) {
    std::cerr << "cannot read room_scan1.pcd / room_scan2.pcd in " << in << "\n";
    return 1;
  }
  pcl::ApproximateVoxelGrid<pcl::PointXYZ> approx;
  approx.setLeafSize(0.2f, 0.2f, 0.2f);
  approx.setInputCloud(source);
  approx.filter(*filtered);

  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
  ndt.setTransformationEpsilon(0.01);
  ndt.setStepSize(0.1);
  ndt.setResolution(1.0f);
  ndt.setMaximumIterations(35);
  ndt.setInputSource(filtered);
  ndt.setInputTarget(target);
  const Eigen::AngleAxisf rotation(0.6931f, Eigen::Vector3f::UnitZ());
  const Eigen::Translation3f translation(1.79387f, 0.720047f, 0.0f);
  const Eigen::Matrix4f guess = (translation * rotation).matrix();
  Cloud aligned;
  ndt.align(aligned, guess);
  const Eigen::Matrix4f T = ndt.getFinalTransformation();

  {
    std::ofstream f(out + "/room_scan2_approx_voxel_0.2.f32", std::ios::binary);
    for (const auto& p : filtered->points) {
      const float xyz[3] = {p.x, p.y, p.z};
      f.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
    }
    if (!f) {
      std::cerr << "cannot write the filtered cloud\n";
      return 1;
    }
  }
  std::ofstream r(out + "/pcl_ndt_room_reference.txt");
  r << "# PCL 1.13 NormalDistributionsTransform on room_scan2 (ApproximateVoxelGrid 0.2) onto\n"
       "# room_scan1; epsilon 0.01, step 0.1, resolution 1.0, 35 iterations; guess: 0.6931 rad\n"
       "# about Z, translation (1.79387, 0.720047, 0). Written by tools/pcl_registration_reference.\n";
  r << "source_points " << filtered->size() << "\n";
  r << "target_points " << target->size() << "\n";
  r << "iterations " << ndt.getFinalNumIteration() << "\n";
  r << "converged " << (ndt.hasConverged() ? 1 : 0) << "\n";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", ndt.getTransformationProbability());
  r << "transformation_probability " << buf << "\n";
  r << "T_target_source\n";
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(T(i, j)));
      r << (j ? " " : "") << buf;
    }
    r << "\n";
  }
  if (!r) {
    std::cerr << "cannot write the reference file\n";
    return 1;
  }
  std::cout << "NDT: " << ndt.getFinalNumIteration() << " iterations, converged "
            << ndt.hasConverged() << ", " << filtered->size() << " source points\n"
            << T << "\n";
  return 0;
}
