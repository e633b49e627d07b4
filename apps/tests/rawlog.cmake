# End-to-end tests of `rove rawlog ...` (included by apps/CMakeLists.txt).
# They check values: entry counts, kept/dropped classes, and lines of the
# text exports against MRPT rawlog-edit's output for the same file.

set(rove_rawlog_dir ${CMAKE_CURRENT_BINARY_DIR}/rawlog_tests)
file(MAKE_DIRECTORY ${rove_rawlog_dir})
set(rove_rawlog_sena
  ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog)
set(rove_rawlog_data ${PROJECT_SOURCE_DIR}/modules/obs/tests/data)

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
