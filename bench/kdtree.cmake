# rove's KD-tree against nanoflann used directly (build, kNN, radius) on the
# room scans from ../shared/datasets/pointcloud (see bench/RESULTS.md).
rove_add_bench(bench_kdtree_vs_nanoflann SOURCES ${CMAKE_CURRENT_LIST_DIR}/kdtree_vs_nanoflann.cpp
               LIBS rove::io nanoflann::nanoflann)
target_compile_definitions(bench_kdtree_vs_nanoflann PRIVATE
  ROVE_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/datasets/pointcloud")
