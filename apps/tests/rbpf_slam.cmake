# `rove rbpf-slam` end to end (included from apps/CMakeLists.txt).
set(rove_rbpf_dir ${CMAKE_CURRENT_BINARY_DIR}/rbpf_slam_tests)
file(MAKE_DIRECTORY ${rove_rbpf_dir})
set(rove_rbpf_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set(rove_rbpf_ini ${PROJECT_SOURCE_DIR}/data/mrpt/gridmapping_optimal_sampling.ini)
set(rove_rbpf_rawlog ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog)

# MRPT's gridmapping_optimal_sampling.ini on the Telecom loop (fewer
# particles to keep the test short): map, path, ESS, picture and summary.
add_test(NAME cli.rbpf_slam_telecom COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${rove_rbpf_ini} ${rove_rbpf_rawlog} --particles 4 --seed 2 -o ${rove_rbpf_dir}/telecom"
  -DEXIT=0 "-DREGEX=rbpf-slam: 224 steps \\(224 scans\\).*4 particles, pfAuxiliaryPFOptimal proposal, 6[0-9] updates.*issues: none"
  -DFILE=${rove_rbpf_dir}/telecom/summary.json
  "-DFILE_REGEX=\"termination\": \"completed\",.*path.tum.*odometry.tum.*ess.csv.*map.png.*map.yaml.*picture.png"
  -P ${rove_rbpf_expect})

# JSON on stdout.
add_test(NAME cli.rbpf_slam_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress --json ${rove_rbpf_ini} ${rove_rbpf_rawlog} --particles 2 --max-steps 40 -o ${rove_rbpf_dir}/json"
  -DEXIT=0 "-DREGEX=\"particles\": 2,.*\"steps\": 40,.*\"issues\": \\[\\]" -P ${rove_rbpf_expect})

# Zero particles, a missing section, an unsupported map selection: clear
# errors naming the key, nothing written.
file(READ ${rove_rbpf_ini} rove_rbpf_text)
string(REPLACE "sampleSize=25" "sampleSize=0" rove_rbpf_zero "${rove_rbpf_text}")
file(WRITE ${rove_rbpf_dir}/zero.ini "${rove_rbpf_zero}")
add_test(NAME cli.rbpf_slam_zero_particles COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${rove_rbpf_dir}/zero.ini ${rove_rbpf_rawlog} -o ${rove_rbpf_dir}/zero"
  -DEXIT=1 "-DREGEX=MappingApplication.*sampleSize must be >= 1" -DABSENT=${rove_rbpf_dir}/zero/summary.json
  -P ${rove_rbpf_expect})
string(REPLACE "[MappingApplication]" "[Mapping]" rove_rbpf_nosec "${rove_rbpf_text}")
file(WRITE ${rove_rbpf_dir}/nosection.ini "${rove_rbpf_nosec}")
add_test(NAME cli.rbpf_slam_missing_section COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${rove_rbpf_dir}/nosection.ini ${rove_rbpf_rawlog} -o ${rove_rbpf_dir}/nosection"
  -DEXIT=1 "-DREGEX=no \\[MappingApplication\\] section" -P ${rove_rbpf_expect})
add_test(NAME cli.rbpf_slam_points_map COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/gridmapping_RBPF_ICPbased_intel.ini ${rove_rbpf_rawlog} -o ${rove_rbpf_dir}/points"
  -DEXIT=1 "-DREGEX=pfOptimalProposal_mapSelection.*points map" -P ${rove_rbpf_expect})

# MRPT's ICP-based grid config (PF_algorithm = 2, the grid selected, no
# powFactor): with two particles the untempered weights sit on one particle
# at nearly every update; the run writes its outputs and says so (exit 3).
add_test(NAME cli.rbpf_slam_icp_proposal COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/gridmapping_RBPF_grid_ICPbased_malaga.ini ${rove_rbpf_rawlog} --particles 2 --max-steps 80 -o ${rove_rbpf_dir}/icp"
  -DEXIT=3 "-DREGEX=2 particles, pfOptimalProposal proposal.*ess-collapse: in [0-9]+ of [0-9]+ updates"
  -DFILE=${rove_rbpf_dir}/icp/summary.json "-DFILE_REGEX=\"termination\": \"completed-with-issues\""
  -P ${rove_rbpf_expect})

# Range-only SLAM: MRPT's RO-SLAM configs (beacons as Monte-Carlo samples and
# as sums of Gaussians) on its simulated demo, against its beacon ground truth.
set(rove_ro_rawlog ${PROJECT_SOURCE_DIR}/data/mrpt/RO-SLAM_demo.rawlog)
set(rove_ro_truth ${PROJECT_SOURCE_DIR}/data/mrpt/RO-SLAM_demo_ground_truth.txt)
add_test(NAME cli.rbpf_slam_ro_mc COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/RO-SLAM_simulatedData_MC.ini ${rove_ro_rawlog} --ground-truth ${rove_ro_truth} --seed 1 -o ${rove_rbpf_dir}/ro_mc"
  -DEXIT=0 "-DREGEX=99 steps \\(99 with beacon ranges\\).*10 particles, pfStandardProposal, beacons as Monte-Carlo samples, 98 updates.*15 beacons.*beacon RMSE 0\\.0[01][0-9]* m over 15 beacons \\(0 missing, 0 unknown\\).*issues: none"
  -DFILE=${rove_rbpf_dir}/ro_mc/beacons.csv "-DFILE_REGEX=id,kind,x,y,z,cov_xx.*\n14,gaussian,"
  -P ${rove_rbpf_expect})
add_test(NAME cli.rbpf_slam_ro_sog_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress --json ${PROJECT_SOURCE_DIR}/data/mrpt/RO-SLAM_simulatedData_SOG.ini ${rove_ro_rawlog} --ground-truth ${rove_ro_truth} -o ${rove_rbpf_dir}/ro_sog"
  -DEXIT=0 "-DREGEX=\"map\": \"beacons\",.*\"beacon_init\": \"sog\",.*\"beacons\": \\[.*\"covariance\": \\[.*\"beacon_rmse\": 0\\.0[01].*path.tum.*beacons.csv.*picture.png.*summary.json.*\"issues\": \\[\\]"
  -P ${rove_rbpf_expect})
# A grid's --reference with a beacon map, and a beacon truth with a grid: errors.
add_test(NAME cli.rbpf_slam_ro_reference_refused COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/RO-SLAM_simulatedData_MC.ini ${rove_ro_rawlog} --reference ${rove_rbpf_ini} -o ${rove_rbpf_dir}/ro_ref"
  -DEXIT=1 "-DREGEX=--reference compares occupancy grids" -DABSENT=${rove_rbpf_dir}/ro_ref/summary.json
  -P ${rove_rbpf_expect})
add_test(NAME cli.rbpf_slam_grid_truth_refused COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${rove_rbpf_ini} ${rove_rbpf_rawlog} --ground-truth ${rove_ro_truth} -o ${rove_rbpf_dir}/grid_truth"
  -DEXIT=1 "-DREGEX=--ground-truth takes beacon positions" -P ${rove_rbpf_expect})

# The Telecom config (1 m / 40° between updates, 0.07 m) on the first 4,000
# steps of the Intel log: the first loop closes wrong, the return's scans
# see through the first pass's walls and the run says so (exit 3), with
# its outputs written.
add_test(NAME cli.rbpf_slam_contradicted_map COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rbpf-slam --no-progress ${rove_rbpf_ini} ${ROVE_DATASETS_DIR}/radish/intel.clf.bz2 --max-steps 4000 --seed 1 -o ${rove_rbpf_dir}/contradicted"
  -DEXIT=3 "-DREGEX=scans against the map: [0-9]+ of [0-9]+ updates with more than 20 % of the rays through walls.*map-contradicts-scans: in [0-9]+ of [0-9]+ updates"
  -DFILE=${rove_rbpf_dir}/contradicted/ess.csv "-DFILE_REGEX=^step,time,ess,effective_particles,resampled,inserted,fallbacks,distinct_tiles,fit,through_walls,seconds"
  -P ${rove_rbpf_expect})
set_tests_properties(cli.rbpf_slam_contradicted_map PROPERTIES LABELS cli)
rove_dataset_tests(cli.rbpf_slam_contradicted_map)
