# `rove lidar-slam` end to end (included from apps/CMakeLists.txt):
# the bundled Telecom rawlog with the defaults, --json, a config file,
# and bad input (tests/scripts/expect_exit.cmake: exit code, output, files).
set(rove_ls_dir ${CMAKE_CURRENT_BINARY_DIR}/lidar_slam_tests)
file(MAKE_DIRECTORY ${rove_ls_dir})
set(rove_ls_telecom
  ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog)
set(rove_ls_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# The defaults on the bundled log write every file and say what they did.
add_test(NAME cli.lidar_slam_telecom COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_telecom} -o ${rove_ls_dir}/telecom"
  -DEXIT=0 "-DREGEX=lidar-slam: 225 scans .*front-end: 224 matched.*loop closure: [0-9]+ searches.*refinement: every scan aligned with the next 2: [1-9][0-9]+ pairs aligned, [0-9]+ not.*on 1 thread.*wrote 9 files.*issues: none"
  -DFILE=${rove_ls_dir}/telecom/summary.json
  "-DFILE_REGEX=\"scans\": 225,.*\"nodes\": [1-9][0-9]*,.*\"refinement\": {[^}]*\"scan_window\": 2,[^}]*\"window_edges\": [1-9][0-9]+,.*\"real_time_factor\": [0-9.]+,.*\"issues\": \\[\\]"
  -P ${rove_ls_expect})
add_test(NAME cli.lidar_slam_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --json --no-progress --max-scans 50 ${rove_ls_telecom} -o ${rove_ls_dir}/json"
  -DEXIT=0 "-DREGEX=\"scans\": 50,.*\"matched\": 49,.*\"files\": \\[.*path.tum.*loop_closures.csv.*map.png.*graph.g2o.*lidar_slam.png"
  -P ${rove_ls_expect})

# A config file: the sections and keys of docs/lidar-slam.md; strict.
file(WRITE ${rove_ls_dir}/small_submaps.ini
  "[frontend]\nmax_range = 25\n[submaps]\nscans_per_submap = 20\n[loop_closure]\nmin_score = 0.6\n[map]\nresolution = 0.1\n")
add_test(NAME cli.lidar_slam_config COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/small_submaps.ini ${rove_ls_telecom} -o ${rove_ls_dir}/config"
  -DEXIT=0 "-DREGEX=config: .*small_submaps.ini.*submaps"
  -DFILE=${rove_ls_dir}/config/summary.json "-DFILE_REGEX=\"submaps\": (1[0-9]|[2-9][0-9]),"
  -P ${rove_ls_expect})
file(WRITE ${rove_ls_dir}/misspelt.ini "[frontend]\nmax_rnage = 25\n")
add_test(NAME cli.lidar_slam_misspelt_key COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/misspelt.ini ${rove_ls_telecom} -o ${rove_ls_dir}/misspelt"
  -DEXIT=1 "-DREGEX=misspelt.ini.*frontend.*max_rnage" -DABSENT=${rove_ls_dir}/misspelt/summary.json
  -P ${rove_ls_expect})
file(WRITE ${rove_ls_dir}/section.ini "[ICP]\nmaxIterations = 10\n")
add_test(NAME cli.lidar_slam_unknown_section COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/section.ini ${rove_ls_telecom} -o ${rove_ls_dir}/section"
  -DEXIT=1 "-DREGEX=section.ini.*ICP.*unknown section" -P ${rove_ls_expect})

# Honest results: a score no pose reaches accepts no loop closure; the
# run writes its files, warns, and exits 3.
file(WRITE ${rove_ls_dir}/strict.ini "[loop_closure]\nmin_score = 0.89\n[submaps]\nscans_per_submap = 20\n")
add_test(NAME cli.lidar_slam_no_loop_closure COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/strict.ini ${rove_ls_telecom} -o ${rove_ls_dir}/strict"
  -DEXIT=3 "-DREGEX=rove: warning: no-loop-closure: none of [0-9]+ loop-closure searches"
  -DFILE=${rove_ls_dir}/strict/summary.json
  "-DFILE_REGEX=\"loops_accepted\": 0,.*\"code\": \"no-loop-closure\""
  -P ${rove_ls_expect})

# Bad input: no scan, one scan, no valid range, not a log.
file(WRITE ${rove_ls_dir}/odom_only.clf "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 0.5 0 0 0 0 0 2.0 host 2.0\n")
add_test(NAME cli.lidar_slam_no_scans COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/odom_only.clf -o ${rove_ls_dir}/odom_only"
  -DEXIT=1 "-DREGEX=odom_only.clf.*no rawlog entry" -DABSENT=${rove_ls_dir}/odom_only/path.tum
  -P ${rove_ls_expect})
string(REPEAT " 3.0" 180 rove_ls_wall)
file(WRITE ${rove_ls_dir}/one_scan.clf "FLASER 180${rove_ls_wall} 0 0 0 0 0 0 1.0 host 1.0\n")
add_test(NAME cli.lidar_slam_one_scan COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/one_scan.clf -o ${rove_ls_dir}/one_scan"
  -DEXIT=1 "-DREGEX=one_scan.clf holds a single 2D scan.*needs at least two" -DABSENT=${rove_ls_dir}/one_scan/path.tum
  -P ${rove_ls_expect})
string(REPEAT " 0.0" 180 rove_ls_blind)
file(WRITE ${rove_ls_dir}/blind.clf
  "FLASER 180${rove_ls_blind} 0 0 0 0 0 0 1.0 host 1.0\nFLASER 180${rove_ls_blind} 0.1 0 0 0.1 0 0 1.2 host 1.2\n")
add_test(NAME cli.lidar_slam_no_valid_range COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/blind.clf -o ${rove_ls_dir}/blind"
  -DEXIT=1 "-DREGEX=none of the 2 scans .* has a valid return within" -DABSENT=${rove_ls_dir}/blind/path.tum
  -P ${rove_ls_expect})
file(WRITE ${rove_ls_dir}/hello.txt "hello world\n")
add_test(NAME cli.lidar_slam_text_is_not_a_log COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/hello.txt -o ${rove_ls_dir}/hello"
  -DEXIT=1 "-DREGEX=hello.txt.*not a rove rawlog, MRPT rawlog or CARMEN log" -P ${rove_ls_expect})
# An output that is an input is refused before the run.
file(MAKE_DIRECTORY ${rove_ls_dir}/same)
configure_file(${rove_ls_telecom} ${rove_ls_dir}/same/path.tum COPYONLY)
add_test(NAME cli.lidar_slam_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress ${rove_ls_dir}/same/path.tum -o ${rove_ls_dir}/same"
  -DEXIT=1 "-DREGEX=refusing to write over the input" -DKEEP=${rove_ls_dir}/same/path.tum
  -DREF=${rove_ls_telecom} -P ${rove_ls_expect})
# --threads: the same path on two threads; a count out of range is refused.
add_test(NAME cli.lidar_slam_threads COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress --threads 2 ${rove_ls_telecom} -o ${rove_ls_dir}/threads"
  -DEXIT=0 "-DREGEX=refinement: every scan aligned with the next 2: .* on 2 threads"
  -DKEEP=${rove_ls_dir}/threads/path.tum -DREF=${rove_ls_dir}/telecom/path.tum -P ${rove_ls_expect})
set_tests_properties(cli.lidar_slam_threads PROPERTIES DEPENDS cli.lidar_slam_telecom)
add_test(NAME cli.lidar_slam_bad_threads COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> lidar-slam --no-progress --threads -2 ${rove_ls_telecom} -o ${rove_ls_dir}/bad_threads"
  -DEXIT=1 "-DREGEX=--threads.*-2" -DABSENT=${rove_ls_dir}/bad_threads/path.tum -P ${rove_ls_expect})
# Usage: no log, three positional arguments.
add_test(NAME cli.lidar_slam_usage COMMAND rove lidar-slam --no-progress)
add_test(NAME cli.lidar_slam_too_many COMMAND rove lidar-slam a.ini b.log c.log)
set_tests_properties(cli.lidar_slam_usage cli.lidar_slam_too_many PROPERTIES WILL_FAIL TRUE)

set_tests_properties(cli.lidar_slam_telecom cli.lidar_slam_json cli.lidar_slam_config
  cli.lidar_slam_misspelt_key cli.lidar_slam_unknown_section cli.lidar_slam_no_loop_closure
  cli.lidar_slam_no_scans cli.lidar_slam_one_scan cli.lidar_slam_no_valid_range
  cli.lidar_slam_text_is_not_a_log cli.lidar_slam_output_is_input cli.lidar_slam_usage
  cli.lidar_slam_too_many cli.lidar_slam_threads cli.lidar_slam_bad_threads PROPERTIES LABELS cli)
