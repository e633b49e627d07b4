# Navigation against MRPT 2.5.8: grid path planning on MRPT's planning
# example (Malaga campus map, radius 0.30 m, (20, -110) -> (90, 40)):
# PlannerSimple2D beside rove's value iteration and A*; the reactive
# navigator's cycle beside CReactiveNavigationSystem. Built only when MRPT
# (with its nav library) is found.
find_package(MRPT 2.5 QUIET COMPONENTS maps nav poses io serialization)
if(MRPT_FOUND)
  rove_add_bench(bench_nav_vs_mrpt SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/nav_vs_mrpt.cpp
                 LIBS rove::nav mrpt::maps mrpt::nav mrpt::poses mrpt::io mrpt::serialization)
  target_compile_definitions(bench_nav_vs_mrpt PRIVATE
    ROVE_DATA_DIR="${ROVE_DATASETS_DIR}/mrpt")
  # The reactive navigator's cycle beside CReactiveNavigationSystem.
  rove_add_bench(bench_reactive_vs_mrpt SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/reactive_vs_mrpt.cpp
                 LIBS rove::nav mrpt::nav mrpt::maps mrpt::poses)
  target_compile_definitions(bench_reactive_vs_mrpt PRIVATE
    ROVE_DATA_DIR="${ROVE_DATASETS_DIR}/mrpt")
else()
  message(STATUS "rove bench: MRPT 2.5 (nav) not found, bench_nav_vs_mrpt is skipped")
endif()

# Closed-loop navigation in rove's simulator (no peer): bench/run_nav_closed_loop.sh.
add_executable(bench_nav_closed_loop ${CMAKE_CURRENT_SOURCE_DIR}/nav_closed_loop.cpp)
target_link_libraries(bench_nav_closed_loop PRIVATE rove::nav)
rove_target_defaults(bench_nav_closed_loop)
