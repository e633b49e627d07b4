# `rove pf-localization` end to end (included from apps/CMakeLists.txt).
set(rove_pfl_dir ${CMAKE_CURRENT_BINARY_DIR}/pf_localization_tests)
file(MAKE_DIRECTORY ${rove_pfl_dir})
set(rove_pfl_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set(rove_pfl_demo_ini ${PROJECT_SOURCE_DIR}/data/mrpt/localization_demo.ini)
set(rove_pfl_map ${PROJECT_SOURCE_DIR}/data/mrpt/localization_demo.simplemap.gz)
set(rove_pfl_rawlog ${PROJECT_SOURCE_DIR}/data/mrpt/localization_demo.rawlog)

# Without arguments: the bundled demo (MRPT's localization_demo.ini, its map
# and log) converges and writes path, odometry, steps, particle snapshots,
# picture and summary; exit 0.
add_test(NAME cli.pf_localization_demo COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress -o ${rove_pfl_dir}/demo"
  -DEXIT=0 "-DREGEX=pf-localization: 37 steps from .*result: converged at step [0-9]+ .*issues: none"
  -DFILE=${rove_pfl_dir}/demo/summary.json
  "-DFILE_REGEX=\"peak_particles\": 40000,.*\"termination\": \"converged\",.*particles_initial.txt.*map.png"
  -P ${rove_pfl_expect})

# MRPT's installed config, unchanged (its relative paths resolve beside it),
# JSON on stdout, two threads.
add_test(NAME cli.pf_localization_mrpt_config_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization /usr/share/mrpt/config_files/pf-localization/localization_demo.ini --json --no-progress --seed 3 --threads 2 -o ${rove_pfl_dir}/mrpt_config"
  -DEXIT=0 "-DREGEX=\"steps\": 37,.*\"converged\": true,.*\"issues\": \\[\\]"
  -P ${rove_pfl_expect})

# A map from another building: the run ends, writes its files and says it
# did not converge (warning, summary, exit 3).
add_test(NAME cli.pf_localization_wrong_map COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_demo_ini} ${rove_pfl_rawlog} --map ${PROJECT_SOURCE_DIR}/data/mrpt/malaga-cs-fac-building.simplemap.gz --global --particles 20000 -o ${rove_pfl_dir}/wrong_map"
  -DEXIT=3 "-DREGEX=rove: warning: (not-converged|lost): "
  -DFILE=${rove_pfl_dir}/wrong_map/summary.json
  "-DFILE_REGEX=\"converged\": false,.*\"issues\": \\[[^]]*\"code\": \"(not-converged|lost)\""
  -P ${rove_pfl_expect})

# Particles around a pose (the command line's pose convention) with their
# spread; --init-std alone is refused.
add_test(NAME cli.pf_localization_init_pose COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress --init-pose 1,-10.5,-15 --init-std 1,30 --particles 5000 -o ${rove_pfl_dir}/init_pose"
  -DEXIT=0 "-DREGEX=particles: 5000 initial.*result: converged at step" -P ${rove_pfl_expect})
add_test(NAME cli.pf_localization_init_std_alone COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress --init-std 1,30 -o ${rove_pfl_dir}/init_std"
  -DEXIT=1 "-DREGEX=--init-std needs --init-pose" -DABSENT=${rove_pfl_dir}/init_std/summary.json
  -P ${rove_pfl_expect})

# A config naming a map that does not exist: a clear error naming the key.
file(READ ${rove_pfl_demo_ini} rove_pfl_demo_text)
string(REPLACE "map_file=../../datasets/localization_demo.simplemap.gz" "map_file=no-such-map.simplemap.gz"
  rove_pfl_missing "${rove_pfl_demo_text}")
file(WRITE ${rove_pfl_dir}/missing_map.ini "${rove_pfl_missing}")
add_test(NAME cli.pf_localization_missing_map COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_dir}/missing_map.ini ${rove_pfl_rawlog} -o ${rove_pfl_dir}/missing_map"
  -DEXIT=1 "-DREGEX=map_file.*no-such-map.simplemap.gz' does not exist"
  -DABSENT=${rove_pfl_dir}/missing_map/summary.json -P ${rove_pfl_expect})

# A misspelt key is named, with its section.
string(REPLACE "particles_count=40000" "partcles_count=40000" rove_pfl_typo "${rove_pfl_demo_text}")
file(WRITE ${rove_pfl_dir}/typo.ini "${rove_pfl_typo}")
add_test(NAME cli.pf_localization_bad_key COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_dir}/typo.ini ${rove_pfl_rawlog} --map ${rove_pfl_map} -o ${rove_pfl_dir}/typo"
  -DEXIT=1 "-DREGEX=LocalizationExperiment.*partcles_count" -P ${rove_pfl_expect})

# Zero or absurd particle counts are refused before anything runs.
add_test(NAME cli.pf_localization_zero_particles COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress --particles 0 -o ${rove_pfl_dir}/zero"
  -DEXIT=2 "-DREGEX=--particles" -P ${rove_pfl_expect})
string(REPLACE "particles_count=40000" "particles_count=4000000000" rove_pfl_absurd "${rove_pfl_demo_text}")
file(WRITE ${rove_pfl_dir}/absurd.ini "${rove_pfl_absurd}")
add_test(NAME cli.pf_localization_absurd_particles COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_dir}/absurd.ini ${rove_pfl_rawlog} --map ${rove_pfl_map} -o ${rove_pfl_dir}/absurd"
  -DEXIT=1 "-DREGEX=particles_count=4000000000" -P ${rove_pfl_expect})

# A misspelt key of the filter's sections is named with its section too.
string(REPLACE "resamplingMethod=0" "resamplingMethd=0" rove_pfl_pf_typo "${rove_pfl_demo_text}")
file(WRITE ${rove_pfl_dir}/pf_typo.ini "${rove_pfl_pf_typo}")
add_test(NAME cli.pf_localization_bad_pf_key COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_dir}/pf_typo.ini ${rove_pfl_rawlog} --map ${rove_pfl_map} -o ${rove_pfl_dir}/pf_typo"
  -DEXIT=1 "-DREGEX=PF_options.*resamplingMethd" -DABSENT=${rove_pfl_dir}/pf_typo/summary.json
  -P ${rove_pfl_expect})

# An empty rawlog, and a rawlog without a single step (its first entry, an
# action collection, cut out by `rove rawlog cut`): errors, nothing written.
file(WRITE ${rove_pfl_dir}/empty.rawlog "")
add_test(NAME cli.pf_localization_empty_rawlog COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_demo_ini} ${rove_pfl_dir}/empty.rawlog --map ${rove_pfl_map} -o ${rove_pfl_dir}/empty"
  -DEXIT=1 "-DREGEX=empty.rawlog.*empty file" -DABSENT=${rove_pfl_dir}/empty/summary.json
  -P ${rove_pfl_expect})
add_test(NAME cli.pf_localization_no_steps_setup COMMAND rove rawlog cut --no-progress --from 0
  --to 0 ${rove_pfl_rawlog} ${rove_pfl_dir}/one_action.rrlog)
add_test(NAME cli.pf_localization_no_steps COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_demo_ini} ${rove_pfl_dir}/one_action.rrlog --map ${rove_pfl_map} -o ${rove_pfl_dir}/no_steps"
  -DEXIT=1 "-DREGEX=one_action.rrlog holds no step" -DABSENT=${rove_pfl_dir}/no_steps/summary.json
  -P ${rove_pfl_expect})
set_tests_properties(cli.pf_localization_no_steps_setup PROPERTIES FIXTURES_SETUP pfl_one_action)
set_tests_properties(cli.pf_localization_no_steps PROPERTIES FIXTURES_REQUIRED pfl_one_action)

# MRPT's range-only config, unchanged (beacons declared in [MetricMap], its
# RO-SLAM log): the particles collapse, but the ranges stay many standard
# deviations from the declared beacons, and the run says it did not
# converge, naming the range check (exit 3, outputs written).
add_test(NAME cli.pf_localization_mrpt_ro_config COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization /usr/share/mrpt/config_files/pf-localization/ro-localization-demo.ini --no-progress -o ${rove_pfl_dir}/ro"
  -DEXIT=3 "-DREGEX=99 steps.*map: config.*rove: warning: not-converged: .*range residual <= 3 sigma"
  -DFILE=${rove_pfl_dir}/ro/summary.json "-DFILE_REGEX=\"converged\": false,.*steps.txt\""
  -P ${rove_pfl_expect})

# An output that is an input is refused before the run.
file(MAKE_DIRECTORY ${rove_pfl_dir}/same)
configure_file(${rove_pfl_demo_ini} ${rove_pfl_dir}/same/summary.json COPYONLY)
add_test(NAME cli.pf_localization_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> pf-localization --no-progress ${rove_pfl_dir}/same/summary.json ${rove_pfl_rawlog} --map ${rove_pfl_map} -o ${rove_pfl_dir}/same"
  -DEXIT=1 "-DREGEX=refusing to write over the input" -DKEEP=${rove_pfl_dir}/same/summary.json
  -DREF=${rove_pfl_demo_ini} -P ${rove_pfl_expect})

# --help shows the defaults.
add_test(NAME cli.pf_localization_help COMMAND rove pf-localization --help)
set_tests_properties(cli.pf_localization_help PROPERTIES
  PASS_REGULAR_EXPRESSION "pf-localization-out.*--seed UINT=0.*--threads INT=1")

set_tests_properties(cli.pf_localization_demo cli.pf_localization_mrpt_config_json
  cli.pf_localization_wrong_map cli.pf_localization_missing_map cli.pf_localization_bad_key
  cli.pf_localization_zero_particles cli.pf_localization_absurd_particles
  cli.pf_localization_output_is_input cli.pf_localization_help cli.pf_localization_bad_pf_key
  cli.pf_localization_empty_rawlog cli.pf_localization_no_steps_setup cli.pf_localization_no_steps
  cli.pf_localization_mrpt_ro_config cli.pf_localization_init_pose
  cli.pf_localization_init_std_alone PROPERTIES LABELS cli)
