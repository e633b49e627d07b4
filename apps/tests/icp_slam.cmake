# `rove icp-slam` end to end (included from apps/CMakeLists.txt).
# Without arguments: the bundled demo (Telecom Faculty loop, MRPT's classic
# config) writes the path, odometry, keyframes, point map, picture,
# simplemap and summary.
add_test(NAME cli.icp_slam_demo
  COMMAND rove icp-slam --no-progress -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_demo)
set_tests_properties(cli.icp_slam_demo PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "icp-slam: 224 steps from .*map: [0-9]+ keyframes, [0-9]+ points.*wrote 7 files")
add_test(NAME cli.icp_slam_json
  COMMAND rove icp-slam --json --no-progress
    ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_LM.ini
    ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog
    -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_lm --max-steps 40)
set_tests_properties(cli.icp_slam_json PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "\"steps\": 40,.*\"icp_runs\": [1-9][0-9]*,.*\"files\": \\[")
# A config whose rawlog_file does not exist and no rawlog given: a clear error
# naming the key.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_norawlog.ini
  "[MappingApplication]\nrawlog_file=does-not-exist.rawlog\npointsMap_count=1\n")
add_test(NAME cli.icp_slam_missing_rawlog
  COMMAND rove icp-slam --no-progress ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_norawlog.ini
    -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_norawlog)
set_tests_properties(cli.icp_slam_missing_rawlog PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "rawlog_file.*does not exist")
