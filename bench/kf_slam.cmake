# EKF-SLAM against MRPT 2.5.8's CRangeBearingKFSLAM(2D) on MRPT's kf-slam
# configs (bench_kf_slam_vs_mrpt), and the cost of one step against the
# number of landmarks (bench_kf_slam_scaling, Google Benchmark, rove and
# MRPT). bench/run_kf_slam_vs_mrpt.sh runs both. Built only when MRPT is found.
find_package(MRPT 2.5 QUIET COMPONENTS slam maps obs poses io serialization config)
if(MRPT_FOUND)
  rove_add_bench(bench_kf_slam_vs_mrpt SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/kf_slam_vs_mrpt.cpp
                 LIBS rove::slam mrpt::slam mrpt::maps mrpt::obs mrpt::poses mrpt::io
                      mrpt::serialization mrpt::config)
  rove_add_bench(bench_kf_slam_scaling SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/kf_slam_scaling.cpp
                 LIBS rove::slam mrpt::slam mrpt::maps mrpt::obs mrpt::poses)
else()
  message(STATUS "rove bench: MRPT 2.5 not found, the kf-slam benchmarks are skipped")
endif()
