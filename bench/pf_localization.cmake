# Monte-Carlo localization against MRPT 2.5.8: one weighting step of 40,000
# particles on MRPT's localization demo grid (bench_pf_localization_vs_mrpt).
# bench/run_pf_localization_vs_mrpt.sh runs it after the whole-process,
# global-localization and range-only comparisons.
# Built only when MRPT is found.
find_package(MRPT 2.5 QUIET COMPONENTS maps obs poses io serialization config)
if(MRPT_FOUND)
  rove_add_bench(bench_pf_localization_vs_mrpt
                 SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/pf_localization_vs_mrpt.cpp
                 LIBS rove::slam mrpt::maps mrpt::obs mrpt::poses mrpt::io mrpt::serialization
                      mrpt::config)
  target_compile_definitions(bench_pf_localization_vs_mrpt PRIVATE
    ROVE_SOURCE_DATA_DIR="${PROJECT_SOURCE_DIR}/data")
else()
  message(STATUS "rove bench: MRPT 2.5 not found, bench_pf_localization_vs_mrpt is skipped")
endif()
