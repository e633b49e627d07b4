# Occupancy grid against MRPT 2.5.8's COccupancyGridMap2D: scan insertion and
# likelihood-field (Thrun) evaluation on the Telecom Faculty rawlog, 5 cm
# grid, same scans and poses in one run. Built only when MRPT is found.
find_package(MRPT 2.5 QUIET COMPONENTS maps obs poses io serialization)
if(MRPT_FOUND)
  rove_add_bench(bench_grid_vs_mrpt SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/grid_vs_mrpt.cpp
                 LIBS rove::io mrpt::maps mrpt::obs mrpt::poses mrpt::io mrpt::serialization)
  target_compile_definitions(bench_grid_vs_mrpt PRIVATE
    ROVE_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/datasets/mrpt")
else()
  message(STATUS "rove bench: MRPT 2.5 not found, bench_grid_vs_mrpt is skipped")
endif()
