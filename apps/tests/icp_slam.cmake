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
# The arithmetic is rove's double unless chosen, and the report says which:
# --arithmetic mrpt reproduces MRPT's icp-slam to the bit.
add_test(NAME cli.icp_slam_arithmetic_default
  COMMAND rove icp-slam --no-progress --max-steps 30 -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_double)
set_tests_properties(cli.icp_slam_arithmetic_default PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "arithmetic: double \\(default; rove's double precision\\)")
add_test(NAME cli.icp_slam_arithmetic_mrpt
  COMMAND rove icp-slam --json --no-progress --max-steps 30 --arithmetic mrpt
    -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_mrpt)
set_tests_properties(cli.icp_slam_arithmetic_mrpt PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "\"arithmetic\": \"mrpt\",.*\"arithmetic_source\": \"--arithmetic\"")
add_test(NAME cli.icp_slam_arithmetic_unknown
  COMMAND rove icp-slam --no-progress --arithmetic single -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_single)
set_tests_properties(cli.icp_slam_arithmetic_unknown PROPERTIES LABELS cli WILL_FAIL TRUE)

# A config whose rawlog_file does not exist and no rawlog given: a clear error
# naming the key.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_norawlog.ini
  "[MappingApplication]\nrawlog_file=does-not-exist.rawlog\npointsMap_count=1\n")
add_test(NAME cli.icp_slam_missing_rawlog
  COMMAND rove icp-slam --no-progress ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_norawlog.ini
    -o ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_norawlog)
set_tests_properties(cli.icp_slam_missing_rawlog PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "rawlog_file.*does not exist")

# --- Honest results and safe outputs (issue 18: items 3, 6, 7, 8) ----------
set(rove_icp_dir ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_tests)
file(MAKE_DIRECTORY ${rove_icp_dir})
set(rove_icp_telecom
  ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog)
# tests/scripts/expect_exit.cmake: exit code, output, files kept or absent.

# Stand-in for Freiburg's clinic log (0 of 6,915 ICP results accepted): the
# Telecom log with a goodness threshold no result can pass. The run ends,
# writes its files, and says so: warning, summary issue, exit 3.
file(READ ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini rove_icp_classic)
string(REGEX REPLACE "minICPgoodnessToAccept[ \t]*=[ \t]*[0-9.]+" "minICPgoodnessToAccept = 1.0"
  rove_icp_impossible "${rove_icp_classic}")
file(WRITE ${rove_icp_dir}/impossible_goodness.ini "${rove_icp_impossible}")
add_test(NAME cli.icp_slam_no_icp_accepted COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> icp-slam --no-progress ${rove_icp_dir}/impossible_goodness.ini ${rove_icp_telecom} -o ${rove_icp_dir}/impossible"
  -DEXIT=3 "-DREGEX=ICP: [0-9]+ runs, 0 accepted.*rove: warning: no-icp-accepted: none of [0-9]+ ICP results"
  -DFILE=${rove_icp_dir}/impossible/summary.json
  "-DFILE_REGEX=\"icp_accepted\": 0,.*\"issues\": \\[[^]]*\"code\": \"no-icp-accepted\""
  -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
# The demo accepts most of its ICP results: no issue, exit 0.
add_test(NAME cli.icp_slam_demo_no_issues COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> icp-slam --no-progress --max-steps 60 -o ${rove_icp_dir}/demo"
  -DEXIT=0 "-DREGEX=issues: none" -DFILE=${rove_icp_dir}/demo/summary.json
  "-DFILE_REGEX=\"issues\": \\[\\]" -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# A text file is not a log; a log without scans has nothing to map.
file(WRITE ${rove_icp_dir}/hello.txt "hello world\n")
add_test(NAME cli.icp_slam_text_is_not_a_log COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> icp-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini ${rove_icp_dir}/hello.txt -o ${rove_icp_dir}/hello"
  -DEXIT=1 "-DREGEX=hello.txt.*not a rove rawlog, MRPT rawlog or CARMEN log"
  -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
file(WRITE ${rove_icp_dir}/odom_only.clf
  "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 0.5 0 0 0 0 0 2.0 host 2.0\n")
add_test(NAME cli.icp_slam_log_without_scans COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> icp-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini ${rove_icp_dir}/odom_only.clf -o ${rove_icp_dir}/odom_only"
  -DEXIT=1 "-DREGEX=odom_only.clf.*no rawlog entry from its 2 CARMEN records" -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# An output in -o that is one of the inputs is refused before the run.
file(MAKE_DIRECTORY ${rove_icp_dir}/same)
configure_file(${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini
  ${rove_icp_dir}/same/summary.json COPYONLY)
add_test(NAME cli.icp_slam_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> icp-slam --no-progress ${rove_icp_dir}/same/summary.json ${rove_icp_telecom} -o ${rove_icp_dir}/same"
  -DEXIT=1 "-DREGEX=refusing to write over the input" -DKEEP=${rove_icp_dir}/same/summary.json
  -DREF=${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

set_tests_properties(cli.icp_slam_no_icp_accepted cli.icp_slam_demo_no_issues
  cli.icp_slam_text_is_not_a_log cli.icp_slam_log_without_scans cli.icp_slam_output_is_input
  PROPERTIES LABELS cli)

# --json and summary.json stay valid JSON for a file name that is not UTF-8.
add_test(NAME cli.icp_slam_json_non_utf8 COMMAND sh
  ${CMAKE_CURRENT_SOURCE_DIR}/tests/icp_slam_json_non_utf8.sh $<TARGET_FILE:rove>
  ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini ${rove_icp_telecom}
  ${rove_icp_dir}/non_utf8)
set_tests_properties(cli.icp_slam_json_non_utf8 PROPERTIES LABELS cli)

# Ctrl-C stops a long run cleanly (exit 130, nothing written, says so).
add_test(NAME cli.icp_slam_interrupt COMMAND sh
  ${CMAKE_CURRENT_SOURCE_DIR}/tests/icp_slam_interrupt.sh $<TARGET_FILE:rove> ${PROJECT_SOURCE_DIR}
  ${rove_icp_dir}/interrupt ${ROVE_DATASETS_DIR})
set_tests_properties(cli.icp_slam_interrupt PROPERTIES LABELS cli SKIP_RETURN_CODE 77 TIMEOUT 60)
rove_dataset_tests(cli.icp_slam_interrupt)

# ICP-SLAM closes no loop: on the first 3,000 steps of the Intel log the
# path has drifted when the robot comes back, the later keyframes see
# through the walls of the earlier ones, and the run says so (exit 3, its
# files written).
add_test(NAME cli.icp_slam_contradicted_map COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> icp-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini ${ROVE_DATASETS_DIR}/radish/intel.clf.bz2 --max-steps 3000 -o ${rove_icp_dir}/contradicted"
  -DEXIT=3 "-DREGEX=keyframes against each other: [0-9]+ of [0-9]+ with more than 20 % of the rays through walls.*rove: warning: map-contradicts-scans: [0-9]+ of [0-9]+ keyframes"
  -DFILE=${rove_icp_dir}/contradicted/summary.json
  "-DFILE_REGEX=\"keyframes_checked\": [0-9]+,.*\"keyframes_contradicted\": [0-9]+,.*\"code\": \"map-contradicts-scans\""
  -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set_tests_properties(cli.icp_slam_contradicted_map PROPERTIES LABELS cli)
rove_dataset_tests(cli.icp_slam_contradicted_map)
