# Registration against PCL 1.13: GICP and point-to-point ICP on the small_gicp
# pair (voxel 0.25), NDT on the PCL tutorial pair, side by side in one run.
# Built only when PCL is found; the data comes from ../shared/datasets.
find_package(MPI QUIET COMPONENTS C)
if(NOT TARGET MPI::MPI_C)
  add_library(MPI::MPI_C INTERFACE IMPORTED)
endif()
find_package(PCL 1.13 QUIET COMPONENTS common io filters kdtree registration)
if(PCL_FOUND)
  rove_add_bench(bench_registration_vs_pcl
                 SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/registration_vs_pcl.cpp
                 LIBS rove::registration rove::io ${PCL_LIBRARIES})
  target_include_directories(bench_registration_vs_pcl SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
  target_compile_definitions(bench_registration_vs_pcl PRIVATE ${PCL_DEFINITIONS}
    ROVE_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/datasets/pointcloud"
    ROVE_REG_TEST_DATA="${PROJECT_SOURCE_DIR}/modules/registration/tests/data")
else()
  message(STATUS "rove bench: PCL 1.13 not found, bench_registration_vs_pcl is skipped")
endif()
