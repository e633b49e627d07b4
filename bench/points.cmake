# Point clouds against PCL 1.13: voxel grid, KD-tree build + kNN, PCD load.
# Built only when PCL is found (it is a peer, never a requirement). The data
# comes from ../shared/datasets/pointcloud (see bench/RESULTS.md).
# Debian's VTK (pulled in by PCLConfig) refers to MPI::MPI_C: find MPI first.
# Without an MPI development package, an empty stand-in target lets VTK's
# config load (PCL's common/io/filters/kdtree never link VTK::mpi).
find_package(MPI QUIET COMPONENTS C)
if(NOT TARGET MPI::MPI_C)
  add_library(MPI::MPI_C INTERFACE IMPORTED)
endif()
find_package(PCL 1.13 QUIET COMPONENTS common io filters kdtree)
if(PCL_FOUND)
  rove_add_bench(bench_points_vs_pcl SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/points_vs_pcl.cpp
                 LIBS rove::io ${PCL_LIBRARIES})
  target_include_directories(bench_points_vs_pcl SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
  target_compile_definitions(bench_points_vs_pcl PRIVATE ${PCL_DEFINITIONS}
    ROVE_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/datasets/pointcloud")
else()
  message(STATUS "rove bench: PCL 1.13 not found, bench_points_vs_pcl is skipped")
endif()
