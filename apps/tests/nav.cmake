# End-to-end tests of `rove nav` (included by apps/CMakeLists.txt), on MRPT's
# own planning example: the Malaga campus map of Debian's mrpt-common, a
# robot of radius 0.30 m from (20, -110) to (90, 40). MRPT 2.5.8's
# PlannerSimple2D finds 194.95 m there (modules/nav/tests,
# grid_planner_datasets_test.cpp); rove's value iteration is within 1 %.
set(rove_nav_dir ${CMAKE_CURRENT_BINARY_DIR}/nav_tests)
file(MAKE_DIRECTORY ${rove_nav_dir})
set(rove_nav_map /usr/share/mrpt/datasets/2006-MalagaCampus.gridmap.gz)
set(rove_nav_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

add_test(NAME cli.nav_plan_value_iteration COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 20,-110 --goal 90,40 --robot-radius 0.3 -o ${rove_nav_dir}/vi.tum"
  -DEXIT=0 "-DREGEX=value-iteration: 19(3\\.[1-9]|4\\.|5\\.|6\\.[0-8])[0-9]* m through [0-9]+ points, minimum clearance 0\\.3[0-9]* m.*wrote [^\n]*vi\\.tum\n  wrote [^\n]*vi\\.png"
  -DFILE=${rove_nav_dir}/vi.tum "-DFILE_REGEX=^# t x y z qx qy qz qw\n0\\.000000 20\\.000000 -110\\.000000 0"
  -P ${rove_nav_expect})
set_tests_properties(cli.nav_plan_value_iteration PROPERTIES LABELS cli)

# A* with its clearance cost, simplified, as JSON: no longer than MRPT's path.
add_test(NAME cli.nav_plan_astar_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 20,-110 --goal 90,40 --robot-radius 0.3 --method astar --simplify --json -o ${rove_nav_dir}/astar.tum --picture ${rove_nav_dir}/astar_picture.png"
  -DEXIT=0 "-DREGEX=\"method\": \"astar\".*\"termination\": \"found\".*\"length_m\": 1(8[0-9]|9[0-4])\\.[0-9]+,.*astar_picture\\.png.*\"issues\": \\[\\]"
  -P ${rove_nav_expect})
set_tests_properties(cli.nav_plan_astar_json PROPERTIES LABELS cli)

# Bad input: each a clear error, nothing written.
add_test(NAME cli.nav_plan_start_in_obstacle COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 35,-60 --goal 90,40 -o ${rove_nav_dir}/bad1.tum"
  -DEXIT=1 "-DREGEX=rove: error: [^\n]*the start \\(35\\.000, -60\\.000\\) is in an obstacle \\(start-blocked\\)"
  -DABSENT=${rove_nav_dir}/bad1.tum -P ${rove_nav_expect})
add_test(NAME cli.nav_plan_goal_outside COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 20,-110 --goal 500,40 -o ${rove_nav_dir}/bad2.tum"
  -DEXIT=1 "-DREGEX=the goal \\(500\\.000, 40\\.000\\) is outside the map \\[-10\\.000, 141\\.040\\] x \\[-127\\.040, 92\\.000\\] m"
  -DABSENT=${rove_nav_dir}/bad2.tum -P ${rove_nav_expect})
add_test(NAME cli.nav_plan_robot_too_large COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 19.5,-103 --goal 90,40 --robot-radius 1.8 -o ${rove_nav_dir}/bad3.tum"
  -DEXIT=1 "-DREGEX=no path from \\(19\\.500, -103\\.000\\) to \\(90\\.000, 40\\.000\\) for a robot of radius 1\\.8 m"
  -DABSENT=${rove_nav_dir}/bad3.tum -P ${rove_nav_expect})
add_test(NAME cli.nav_plan_bad_start COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 1,2,3,4 --goal 90,40 -o ${rove_nav_dir}/bad4.tum"
  -DEXIT=1 "-DREGEX=--start.*expected x,y or x,y,yaw .meters, degrees., got 4 values"
  -DABSENT=${rove_nav_dir}/bad4.tum -P ${rove_nav_expect})
add_test(NAME cli.nav_plan_zero_radius COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 20,-110 --goal 90,40 --robot-radius 0 -o ${rove_nav_dir}/bad5.tum"
  -DEXIT=2 "-DREGEX=--robot-radius: '0' must be a number greater than 0"
  -DABSENT=${rove_nav_dir}/bad5.tum -P ${rove_nav_expect})
add_test(NAME cli.nav_plan_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav plan ${rove_nav_map} --start 20,-110 --goal 90,40 -o ${rove_nav_map}"
  -DEXIT=1 "-DREGEX=rove: error:" -DKEEP=${rove_nav_map} -DREF=${rove_nav_map} -P ${rove_nav_expect})
set_tests_properties(cli.nav_plan_start_in_obstacle cli.nav_plan_goal_outside cli.nav_plan_robot_too_large
  cli.nav_plan_bad_start cli.nav_plan_zero_radius cli.nav_plan_output_is_input PROPERTIES LABELS cli)

# `rove nav run`: 30 m along a corridor of the campus with the TEB; the goal
# is reached and every output is written; the log reads back.
add_test(NAME cli.nav_run_teb COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 20,-110,90 --goal 20,-80 -o ${rove_nav_dir}/run"
  -DEXIT=0 "-DREGEX=teb \\(goal-reached\\): goal reached in [0-9.]+ s.*minimum clearance 0\\.[0-9]+ m.*wrote [^\n]*run\\.rawlog.*wrote [^\n]*frames\\.png"
  -DFILE=${rove_nav_dir}/run/driven.tum "-DFILE_REGEX=^# t x y z qx qy qz qw\n0\\.000000 20\\.000000 -110\\.000000 0"
  -P ${rove_nav_expect})
set_tests_properties(cli.nav_run_teb PROPERTIES LABELS cli FIXTURES_SETUP nav_run)
add_test(NAME cli.nav_run_log_reads_back COMMAND rove rawlog info ${rove_nav_dir}/run/run.rawlog)
set_tests_properties(cli.nav_run_log_reads_back PROPERTIES LABELS cli FIXTURES_REQUIRED nav_run
  PASS_REGULAR_EXPRESSION "format: rove.*[0-9]+  RangeScan2D \\[LIDAR\\].*[0-9]+  RobotMovement2D")

# Bad input: a goal in a wall (no path, nothing written), a robot that does
# not fit where it starts, an unknown TEB key, a zero speed.
add_test(NAME cli.nav_run_goal_in_obstacle COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 20,-110,90 --goal 35,-60 -o ${rove_nav_dir}/run_bad1"
  -DEXIT=1 "-DREGEX=the goal \\(35\\.000, -60\\.000\\) is in an obstacle \\(no-path\\)"
  -DABSENT=${rove_nav_dir}/run_bad1/run.rawlog -P ${rove_nav_expect})
add_test(NAME cli.nav_run_start_overlaps COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 35,-60,0 --goal 20,-80 -o ${rove_nav_dir}/run_bad2"
  -DEXIT=1 "-DREGEX=the robot \\(radius 0\\.3 m\\) at \\(35\\.000, -60\\.000\\) overlaps an obstacle"
  -DABSENT=${rove_nav_dir}/run_bad2/run.rawlog -P ${rove_nav_expect})
file(WRITE ${rove_nav_dir}/typo.ini "[TEB]\nmax_vel_x = 0.5\nweight_obstacles = 10\n")
add_test(NAME cli.nav_run_unknown_teb_key COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 20,-110,90 --goal 20,-80 --config ${rove_nav_dir}/typo.ini -o ${rove_nav_dir}/run_bad3"
  -DEXIT=1 "-DREGEX=\\[TEB\\] weight_obstacles"
  -DABSENT=${rove_nav_dir}/run_bad3/run.rawlog -P ${rove_nav_expect})
add_test(NAME cli.nav_run_zero_speed COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 20,-110,90 --goal 20,-80 --max-v 0 -o ${rove_nav_dir}/run_bad4"
  -DEXIT=2 "-DREGEX=--max-v: '0' must be a number greater than 0" -P ${rove_nav_expect})
set_tests_properties(cli.nav_run_goal_in_obstacle cli.nav_run_start_overlaps cli.nav_run_unknown_teb_key
  cli.nav_run_zero_speed PROPERTIES LABELS cli)

# The reactive navigator reads MRPT's reactive2d_config.ini unchanged (its
# FullEval method and three PTGs) and drives the same corridor; the keys rove
# does not use are listed.
add_test(NAME cli.nav_run_reactive_mrpt_config COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 20,-110,90 --goal 20,-80 --planner reactive --config /usr/share/mrpt/config_files/navigation-ptgs/reactive2d_config.ini -o ${rove_nav_dir}/reactive"
  -DEXIT=0 "-DREGEX=\\[CPointCloudFilterByDistance\\] min_dist, [^\n]*without effect.*reactive \\(goal-reached\\): goal reached.*holonomic method: CHolonomicFullEval.*wrote [^\n]*frames\\.png"
  -P ${rove_nav_expect})
# ...and refuses a scoring it does not evaluate, naming the key.
file(WRITE ${rove_nav_dir}/other_score.ini
  "[CMultiObjMotionOpt_Scalarization]\nscalar_score_formula = 2*target_distance\n")
add_test(NAME cli.nav_run_reactive_other_scoring COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> nav run ${rove_nav_map} --start 20,-110,90 --goal 20,-80 --planner reactive --config ${rove_nav_dir}/other_score.ini -o ${rove_nav_dir}/reactive_bad"
  -DEXIT=1 "-DREGEX=scalar_score_formula.*default scalarization only"
  -DABSENT=${rove_nav_dir}/reactive_bad/run.rawlog -P ${rove_nav_expect})
set_tests_properties(cli.nav_run_reactive_mrpt_config cli.nav_run_reactive_other_scoring PROPERTIES LABELS cli)
