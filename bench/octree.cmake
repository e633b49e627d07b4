# 3D occupancy octree against OctoMap 1.9.7 (liboctomap-dev): insertion of
# OctoMap's test scan at 0.2, 0.1 and 0.05 m, point queries and ray casts,
# in one run (results in bench/RESULTS.md). Built only when OctoMap is found;
# reads ../shared/datasets/octree/scan.dat.bz2.
find_package(octomap QUIET)
find_package(BZip2 QUIET)
if(octomap_FOUND AND BZip2_FOUND)
  rove_add_bench(bench_octree_vs_octomap SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/octree_vs_octomap.cpp
                 LIBS rove::maps octomap octomath BZip2::BZip2)
  target_include_directories(bench_octree_vs_octomap PRIVATE ${PROJECT_SOURCE_DIR}/modules/maps/tests/support)
  target_compile_definitions(bench_octree_vs_octomap PRIVATE ROVE_DATASETS_DIR="${ROVE_DATASETS_DIR}")
else()
  message(STATUS "rove bench: OctoMap not found, bench_octree_vs_octomap is skipped")
endif()
