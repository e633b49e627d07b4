# End-to-end tests of `rove rawlog ...` (included by apps/CMakeLists.txt).
# They check values: entry counts, kept/dropped classes, and lines of the
# text exports against MRPT rawlog-edit's output for the same file.

set(rove_rawlog_dir ${CMAKE_CURRENT_BINARY_DIR}/rawlog_tests)
file(MAKE_DIRECTORY ${rove_rawlog_dir})
set(rove_rawlog_sena
  ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog)
set(rove_rawlog_data ${PROJECT_SOURCE_DIR}/modules/io/tests/data)

# check_line: line LINE of FILE must equal line REF_LINE of REF (1-based).
file(WRITE ${rove_rawlog_dir}/check_line.cmake [=[
file(STRINGS "${FILE}" got)
file(STRINGS "${REF}" want)
math(EXPR i "${LINE} - 1")
math(EXPR j "${REF_LINE} - 1")
list(LENGTH got n)
if(i GREATER_EQUAL n)
  message(FATAL_ERROR "${FILE} has ${n} lines, no line ${LINE}")
endif()
list(GET got ${i} a)
list(GET want ${j} b)
if(NOT a STREQUAL b)
  message(FATAL_ERROR "line ${LINE} of ${FILE}:\n${a}\ndiffers from line ${REF_LINE} of ${REF}:\n${b}")
endif()
]=])

# expect_failure: COMMAND must exit non-zero and print REGEX on stderr.
file(WRITE ${rove_rawlog_dir}/expect_failure.cmake [=[
separate_arguments(cmd UNIX_COMMAND "${COMMAND}")
execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a failure, got exit code 0:\n${out}${err}")
endif()
if(NOT err MATCHES "${REGEX}")
  message(FATAL_ERROR "stderr does not match '${REGEX}':\n${err}")
endif()
]=])

# Counts as MRPT's rawlog-edit --info reports them for the bundled log.
add_test(NAME cli.rawlog_info COMMAND rove rawlog info --no-progress ${rove_rawlog_sena})
set_tests_properties(cli.rawlog_info PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "format: MRPT.*entries: 449 \\(224 action collections, 225 sensory frames, 0 bare observations\\).*uncompressed bytes: 498881")

add_test(NAME cli.rawlog_info_carmen COMMAND rove rawlog info --no-progress
  ${rove_rawlog_data}/carmen_intel_head.clf)
set_tests_properties(cli.rawlog_info_carmen PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "format: CARMEN.*entries: 47 \\(23 action collections, 24 sensory frames, 0 bare observations\\)")

# MRPT → rove keeps every entry; the result reads back with the same counts.
add_test(NAME cli.rawlog_convert_mrpt COMMAND rove rawlog convert --no-progress
  ${rove_rawlog_sena} ${rove_rawlog_dir}/sena.rawlog)
set_tests_properties(cli.rawlog_convert_mrpt PROPERTIES LABELS cli FIXTURES_SETUP rove_rawlog_sena
  PASS_REGULAR_EXPRESSION "entries: 449 read, 449 written.*225  RangeScan2D.*224  RobotMovement2D.*dropped: none")
add_test(NAME cli.rawlog_info_rove COMMAND rove rawlog info --no-progress ${rove_rawlog_dir}/sena.rawlog)
set_tests_properties(cli.rawlog_info_rove PROPERTIES LABELS cli FIXTURES_REQUIRED rove_rawlog_sena
  PASS_REGULAR_EXPRESSION "format: rove.*entries: 449 \\(224 action collections, 225 sensory frames, 0 bare observations\\)")

# CARMEN → layout #2: one odometry + one scan per FLASER line, ODOM lines too.
add_test(NAME cli.rawlog_convert_carmen COMMAND rove rawlog convert --no-progress --layout 2
  ${rove_rawlog_data}/carmen_intel_head.clf ${rove_rawlog_dir}/intel_head.rawlog)
set_tests_properties(cli.rawlog_convert_carmen PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "\\(CARMEN\\).*entries: 93 read, 93 written.*69  OdometryObservation.*24  RangeScan2D.*dropped:.*2  CARMEN PARAM/SYNC/other line")

add_test(NAME cli.rawlog_convert_carmen_layout1 COMMAND rove rawlog convert --no-progress --no-gzip
  ${rove_rawlog_data}/carmen_intel_head.clf ${rove_rawlog_dir}/intel_head_1.rawlog)
set_tests_properties(cli.rawlog_convert_carmen_layout1 PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "entries: 47 read, 47 written.*23  RobotMovement2D.*45  CARMEN ODOM line \\(odometry taken from laser lines\\)")

# Exports: the first scan row rawlog-edit writes for the Telecom log
# (it skips the frame before the first action, rove exports it as row 2).
add_test(NAME cli.rawlog_export_scans COMMAND rove rawlog export-scans --no-progress
  ${rove_rawlog_sena} ${rove_rawlog_dir}/sena_scans.txt)
set_tests_properties(cli.rawlog_export_scans PROPERTIES LABELS cli FIXTURES_SETUP rove_rawlog_scans
  PASS_REGULAR_EXPRESSION "sena_scans.txt \\(225 rows\\)")
add_test(NAME cli.rawlog_export_scans_line COMMAND ${CMAKE_COMMAND}
  -DFILE=${rove_rawlog_dir}/sena_scans.txt -DLINE=3
  -DREF=${rove_rawlog_data}/mrpt_sena_export_2d_scans.txt -DREF_LINE=4
  -P ${rove_rawlog_dir}/check_line.cmake)
set_tests_properties(cli.rawlog_export_scans_line PROPERTIES LABELS cli
  FIXTURES_REQUIRED rove_rawlog_scans)

add_test(NAME cli.rawlog_export_odometry COMMAND rove rawlog export-odometry --no-progress
  ${rove_rawlog_data}/mrpt_carmen2rawlog_intel_head.rawlog ${rove_rawlog_dir}/intel_odo.txt)
set_tests_properties(cli.rawlog_export_odometry PROPERTIES LABELS cli FIXTURES_SETUP rove_rawlog_odo
  PASS_REGULAR_EXPRESSION "intel_odo.txt \\(24 rows\\)")
add_test(NAME cli.rawlog_export_odometry_line COMMAND ${CMAKE_COMMAND}
  -DFILE=${rove_rawlog_dir}/intel_odo.txt -DLINE=9
  -DREF=${rove_rawlog_data}/mrpt_carmen2rawlog_intel_head_ODOMETRY.txt -DREF_LINE=9
  -P ${rove_rawlog_dir}/check_line.cmake)
set_tests_properties(cli.rawlog_export_odometry_line PROPERTIES LABELS cli
  FIXTURES_REQUIRED rove_rawlog_odo)

add_test(NAME cli.rawlog_cut COMMAND rove rawlog cut --no-progress --from 10 --to 19
  ${rove_rawlog_sena} ${rove_rawlog_dir}/cut.rawlog)
set_tests_properties(cli.rawlog_cut PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "entries: 20 read, 10 written.*5  RobotMovement2D")

add_test(NAME cli.rawlog_decimate COMMAND rove rawlog decimate --no-progress --every 3
  ${rove_rawlog_sena} ${rove_rawlog_dir}/decimated.rawlog)
set_tests_properties(cli.rawlog_decimate PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "entries: 449 read, 149 written.*75  RangeScan2D.*74  RobotMovement2D")

# Bad input fails with the file, the offset or line, and the field.
add_test(NAME cli.rawlog_missing_file COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog convert ${rove_rawlog_dir}/no_such_file.rawlog ${rove_rawlog_dir}/x.rawlog"
  "-DREGEX=no_such_file.rawlog" -P ${rove_rawlog_dir}/expect_failure.cmake)
set_tests_properties(cli.rawlog_missing_file PROPERTIES LABELS cli)
file(WRITE ${rove_rawlog_dir}/bad_version.rawlog "ROVERAWLxx")
add_test(NAME cli.rawlog_corrupt_rove COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog info --no-progress ${rove_rawlog_dir}/bad_version.rawlog"
  "-DREGEX=bad_version.rawlog \\(byte offset 8\\) \\[format version\\]"
  -P ${rove_rawlog_dir}/expect_failure.cmake)
set_tests_properties(cli.rawlog_corrupt_rove PROPERTIES LABELS cli)
file(WRITE ${rove_rawlog_dir}/bad.clf "FLASER 3 1.0 2.0 abc 0 0 0 0 0 0 1.0 host 1.0\n")
add_test(NAME cli.rawlog_corrupt_carmen COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog export-scans --no-progress ${rove_rawlog_dir}/bad.clf ${rove_rawlog_dir}/bad.txt"
  "-DREGEX=bad.clf:1" -P ${rove_rawlog_dir}/expect_failure.cmake)
set_tests_properties(cli.rawlog_corrupt_carmen PROPERTIES LABELS cli)

# --- Honest input and outputs (issue 18: items 6, 7, 8) ---------------------

# tests/scripts/expect_exit.cmake: exit code, output, files kept or absent.

# Text that is not a robot log (a greeting, a pose graph) is refused by name,
# never read as an empty CARMEN log.
file(WRITE ${rove_rawlog_dir}/hello.txt "hello world\n")
file(WRITE ${rove_rawlog_dir}/graph.g2o "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n")
add_test(NAME cli.rawlog_text_is_not_a_log COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog info --no-progress ${rove_rawlog_dir}/hello.txt" -DEXIT=1
  "-DREGEX=hello.txt.*not a rove rawlog, MRPT rawlog or CARMEN log"
  -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
add_test(NAME cli.rawlog_g2o_is_not_a_log COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog convert --no-progress ${rove_rawlog_dir}/graph.g2o ${rove_rawlog_dir}/graph.rawlog"
  -DEXIT=1 "-DREGEX=graph.g2o.*not a rove rawlog, MRPT rawlog or CARMEN log"
  -DABSENT=${rove_rawlog_dir}/graph.rawlog -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
# A CARMEN log with PARAM lines only has no record: an error, not an empty log.
file(WRITE ${rove_rawlog_dir}/params_only.clf "# CARMEN Logfile\nPARAM robot_use_laser on nohost 0\n")
add_test(NAME cli.rawlog_carmen_without_records COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog info --no-progress ${rove_rawlog_dir}/params_only.clf" -DEXIT=1
  "-DREGEX=params_only.clf:2 \\[records\\]: no CARMEN record" -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
# Devices are refused at once (reading /dev/zero never ends).
add_test(NAME cli.rawlog_info_dev_zero COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog info --no-progress /dev/zero" -DEXIT=1
  "-DREGEX=/dev/zero.*not a regular file" -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set_tests_properties(cli.rawlog_info_dev_zero PROPERTIES TIMEOUT 20)

# An output that is the input is refused and the input stays intact.
configure_file(${rove_rawlog_sena} ${rove_rawlog_dir}/same.rawlog COPYONLY)
foreach(job "cut --from 3" "decimate --every 2" "convert")
  string(REGEX REPLACE " .*" "" name "${job}")
  add_test(NAME cli.rawlog_${name}_output_is_input COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:rove> rawlog ${job} --no-progress ${rove_rawlog_dir}/same.rawlog ${rove_rawlog_dir}/./same.rawlog"
    -DEXIT=1 "-DREGEX=refusing to write over the input" -DKEEP=${rove_rawlog_dir}/same.rawlog
    -DREF=${rove_rawlog_sena} -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
endforeach()
add_test(NAME cli.rawlog_export_scans_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog export-scans --no-progress ${rove_rawlog_dir}/same.rawlog ${rove_rawlog_dir}/same.rawlog"
  -DEXIT=1 "-DREGEX=refusing to write over the input" -DKEEP=${rove_rawlog_dir}/same.rawlog
  -DREF=${rove_rawlog_sena} -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# Selections that find nothing name the flag and what the log holds.
add_test(NAME cli.rawlog_cut_outside_the_log COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog cut --no-progress --from 100000 ${rove_rawlog_sena} ${rove_rawlog_dir}/outside.rawlog"
  -DEXIT=1 "-DREGEX=--from: --from 100000 selects no entry: .*449 entries \\(indices 0..448\\)"
  -DABSENT=${rove_rawlog_dir}/outside.rawlog -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
add_test(NAME cli.rawlog_cut_outside_the_log_time COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog cut --no-progress --to-time 10 ${rove_rawlog_sena} ${rove_rawlog_dir}/outside_t.rawlog"
  -DEXIT=1 "-DREGEX=--to-time: --to-time 10.000000 selects no entry: .*times 1137834225.71"
  -DABSENT=${rove_rawlog_dir}/outside_t.rawlog -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
add_test(NAME cli.rawlog_export_scans_unknown_label COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog export-scans --no-progress --label NOPE ${rove_rawlog_data}/carmen_intel_head.clf ${rove_rawlog_dir}/nope.txt"
  -DEXIT=1 "-DREGEX=--label: no 2D scan has label 'NOPE' .*labels are 'LASER' \\(24\\)"
  -DABSENT=${rove_rawlog_dir}/nope.txt -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# CARMEN maximum range: readings at it are "no return" (invalid, 0 in the
# validity columns of the export).
file(WRITE ${rove_rawlog_dir}/range50.clf
  "FLASER 4 1.00 50.00 49.99 60.00 0 0 0 0 0 0 1.0 host 1.0\n")
add_test(NAME cli.rawlog_carmen_max_range COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rawlog export-scans --no-progress --max-range 50 ${rove_rawlog_dir}/range50.clf ${rove_rawlog_dir}/range50.txt"
  -DEXIT=0 "-DREGEX=range50.txt \\(1 rows\\)" -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
add_test(NAME cli.rawlog_carmen_max_range_row COMMAND ${CMAKE_COMMAND}
  -DFILE=${rove_rawlog_dir}/range50.txt -DLINE=2 -DREF=${rove_rawlog_dir}/range50_ref.txt -DREF_LINE=1
  -P ${rove_rawlog_dir}/check_line.cmake)
file(WRITE ${rove_rawlog_dir}/range50_ref.txt
  "        1.000000 1.000 50.000 49.990 60.000     1 0 1 0     \n")
set_tests_properties(cli.rawlog_carmen_max_range_row PROPERTIES DEPENDS cli.rawlog_carmen_max_range)

# --json stays valid JSON for a file name that is not UTF-8 (U+FFFD in its place).
add_test(NAME cli.rawlog_info_json_non_utf8 COMMAND sh
  ${CMAKE_CURRENT_SOURCE_DIR}/tests/rawlog_json_non_utf8.sh $<TARGET_FILE:rove>
  ${rove_rawlog_data}/carmen_intel_head.clf ${rove_rawlog_dir})

set_tests_properties(cli.rawlog_text_is_not_a_log cli.rawlog_g2o_is_not_a_log
  cli.rawlog_carmen_without_records cli.rawlog_info_dev_zero cli.rawlog_cut_output_is_input
  cli.rawlog_decimate_output_is_input cli.rawlog_convert_output_is_input
  cli.rawlog_export_scans_output_is_input cli.rawlog_cut_outside_the_log
  cli.rawlog_cut_outside_the_log_time cli.rawlog_export_scans_unknown_label
  cli.rawlog_carmen_max_range cli.rawlog_carmen_max_range_row cli.rawlog_info_json_non_utf8
  PROPERTIES LABELS cli)
