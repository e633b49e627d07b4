# Pose-graph optimization against Ceres and MRPT (whole process, side by
# side): `cmake --build <dir> --target bench_graph_vs_peers` runs
# bench/run_graph_vs_peers.sh on this build (needs -DROVE_BUILD_PEER_TOOLS=ON
# for the Ceres reference, mrpt-apps for MRPT's graph-slam).
# (tools/ is configured after bench/, so the script builds the Ceres tool
# itself when it is missing.)
if(TARGET rove)
  add_custom_target(bench_graph_vs_peers
    COMMAND ${PROJECT_SOURCE_DIR}/bench/run_graph_vs_peers.sh ${CMAKE_BINARY_DIR}
    DEPENDS rove
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} USES_TERMINAL)
endif()
