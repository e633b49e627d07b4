# End-to-end tests of `rove graph-slam` (included by apps/CMakeLists.txt).
# They check values: the χ² the optimizer reaches on the bundled-size
# datasets, what --info counts, and the errors bad files give.

set(rove_graph_dir ${CMAKE_CURRENT_BINARY_DIR}/graph_tests)
file(MAKE_DIRECTORY ${rove_graph_dir})
set(rove_graph_data ${ROVE_DATASETS_DIR}/posegraph)
set(rove_graph_bundled ${PROJECT_SOURCE_DIR}/data/posegraph)

# Circle from the stored poses: the optimum χ² (also Ceres') and a TORO
# output that reads back.
add_test(NAME cli.graph_slam_circle COMMAND rove graph-slam --init as-is
  -i ${rove_graph_bundled}/graph_2d_circle_50nodes.graph -o ${rove_graph_dir}/circle_out.graph
  --plot ${rove_graph_dir}/circle.png)
set_tests_properties(cli.graph_slam_circle PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "chi2 +124\\.2323834[0-9]* -> 0\\.00871210[0-9]*.*termination +converged")
add_test(NAME cli.graph_slam_reread COMMAND rove graph-slam --info
  -i ${rove_graph_dir}/circle_out.graph)
set_tests_properties(cli.graph_slam_reread PROPERTIES LABELS cli DEPENDS cli.graph_slam_circle
  PASS_REGULAR_EXPRESSION "vertices +50 .*edges +101 .*chi2 +0\\.00871210")

# The default start (auto) takes the chordal guess where it is better, and
# says so: torus3D from its stored poses stops at the iteration limit with
# χ² 19,972; from the chordal guess it converges to 14,574.7.
add_test(NAME cli.graph_slam_auto_init_circle COMMAND rove graph-slam
  -i ${rove_graph_bundled}/graph_2d_circle_50nodes.graph)
set_tests_properties(cli.graph_slam_auto_init_circle PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "initial guess +chordal \\(auto: .*chi2 +0\\.012220903 -> 0\\.00871210[0-9]*.*termination +converged")
add_test(NAME cli.graph_slam_auto_init_torus COMMAND rove graph-slam --json
  -i ${rove_graph_data}/torus3D.g2o)
set_tests_properties(cli.graph_slam_auto_init_torus PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "\"init\": \"chordal\".*\"final_chi2\": 14574\\.746[0-9]*.*\"termination\": \"converged\"")
rove_dataset_tests(cli.graph_slam_auto_init_torus)

# Careless and hostile input (apps/tests/graph_safety.sh): --level 99, outputs
# over inputs, devices, thread counts, max-iterations as exit 3, edges-only
# files, information repair, non-UTF-8 paths in JSON, atomic outputs.
add_test(NAME cli.graph_slam_safety COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/tests/graph_safety.sh
  $<TARGET_FILE:rove> ${rove_graph_data} ${rove_graph_dir}/safety)
set_tests_properties(cli.graph_slam_safety PROPERTIES LABELS cli)
rove_dataset_tests(cli.graph_slam_safety)  # reads intel.g2o

# intel with Levenberg–Marquardt (the default is the dog-leg), JSON summary.
add_test(NAME cli.graph_slam_intel_lm COMMAND rove graph-slam --json --solver lm
  -i ${rove_graph_data}/intel.g2o)
set_tests_properties(cli.graph_slam_intel_lm PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "\"final_chi2\": 45\\.0046958[0-9]*.*\"termination\": \"converged\"")
rove_dataset_tests(cli.graph_slam_intel_lm)

# --info on w100 (EQUIV merges 20 vertices away).
add_test(NAME cli.graph_slam_info_w100 COMMAND rove graph-slam --info
  -i ${rove_graph_bundled}/w100.graph)
set_tests_properties(cli.graph_slam_info_w100 PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "connectivity +1 connected component")

# Bad input: file and line named.
file(WRITE ${rove_graph_dir}/bad.graph
  "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nEDGE2 0 1 1 0 0 1 0 1 -1 0 0\n")
add_test(NAME cli.graph_slam_bad_information COMMAND rove graph-slam
  -i ${rove_graph_dir}/bad.graph)
set_tests_properties(cli.graph_slam_bad_information PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "bad\\.graph:3.*positive definite")
file(WRITE ${rove_graph_dir}/disconnected.graph
  "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nVERTEX2 5 0 0 0\nVERTEX2 6 1 0 0\nEDGE2 0 1 1 0 0 1 0 1 1 0 0\nEDGE2 5 6 1 0 0 1 0 1 1 0 0\nFIX 0\n")
add_test(NAME cli.graph_slam_disconnected COMMAND rove graph-slam
  -i ${rove_graph_dir}/disconnected.graph)
set_tests_properties(cli.graph_slam_disconnected PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "not connected to an anchored vertex.*5, 6")
