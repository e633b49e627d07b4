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
