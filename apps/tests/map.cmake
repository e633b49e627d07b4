# End-to-end tests of `rove map build` (included by apps/CMakeLists.txt).
# They check values against MRPT 2.5.8 on the same input: the point count
# and grid size MRPT's CMultiMetricMap produces from localization_demo's
# simplemap with MRPT's own config files (modules/slam/tests/data/).

set(rove_map_dir ${CMAKE_CURRENT_BINARY_DIR}/map_tests)
file(MAKE_DIRECTORY ${rove_map_dir})
set(rove_map_datasets ${PROJECT_SOURCE_DIR}/data/mrpt)
set(rove_mrpt_package /usr/share/mrpt/datasets)
set(rove_map_configs /usr/share/mrpt/config_files)

# Points: MRPT's icp-slam map section on the localization simplemap gives
# exactly 11937 points; the PLY and PCD files are written.
add_test(NAME cli.map_build_points COMMAND rove map build
  ${rove_map_configs}/icp-slam/icp-slam_demo_classic.ini
  ${rove_map_datasets}/localization_demo.simplemap.gz -o ${rove_map_dir}/points)
set_tests_properties(cli.map_build_points PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "map 0 pointsMap: 11937 points.*wrote [^\n]*map_00_pointsMap\\.ply")

# Grid: MRPT's pf-localization map section; MRPT's grid is 1250 x 517 cells.
add_test(NAME cli.map_build_grid COMMAND rove map build --section MetricMap
  ${rove_map_configs}/pf-localization/localization_demo.ini
  ${rove_map_datasets}/localization_demo.simplemap.gz -o ${rove_map_dir}/grid)
set_tests_properties(cli.map_build_grid PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "map 0 occupancyGrid: [0-9]+ cells of 646250 cells.*wrote [^\n]*map_00_occupancyGrid\\.png\n  wrote [^\n]*map_00_occupancyGrid\\.yaml")
# ...and the ROS map it wrote loads back (map.yaml + PNG -> .rovegrid).
add_test(NAME cli.map_build_grid_ros_map_loads COMMAND rove map convert
  ${rove_map_dir}/grid/map_00_occupancyGrid.yaml ${rove_map_dir}/grid/back.rovegrid)
set_tests_properties(cli.map_build_grid_ros_map_loads PROPERTIES LABELS cli DEPENDS cli.map_build_grid
  PASS_REGULAR_EXPRESSION "ROS map [^\n]*: 1250 x 517 cells of 0\\.06 m")

# Beacons from a rawlog (layout #1, poses from odometry), JSON summary.
add_test(NAME cli.map_build_beacons_json COMMAND rove map build --json
  ${rove_map_configs}/rbpf-slam/RO-SLAM_simulatedData_SOG.ini
  ${rove_map_datasets}/RO-SLAM_demo.rawlog -o ${rove_map_dir}/beacons)
set_tests_properties(cli.map_build_beacons_json PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "\"input_kind\": \"rawlog\",\n  \"keyframes\": 100,\n  \"odometry_steps\": 100,.*\"kind\": \"beaconMap\",[^}]*\"beacons\": 1[0-9],[^}]*\"observations_inserted\": 100,.*\"issues\": \\[\\]")

# A misspelled key is reported by name, with its section.
file(WRITE ${rove_map_dir}/typo.ini
  "[M]\nbeaconMap_count=1\n[M_beaconMap_00_likelihoodOpts]\nrangeStdd=0.1\n")
add_test(NAME cli.map_build_unknown_key COMMAND rove map build ${rove_map_dir}/typo.ini
  ${rove_map_datasets}/RO-SLAM_demo.rawlog -o ${rove_map_dir}/typo)
set_tests_properties(cli.map_build_unknown_key PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "M_beaconMap_00_likelihoodOpts\\] rangeStdd: unknown key")
# ...and the command fails.
add_test(NAME cli.map_build_unknown_key_fails COMMAND rove map build ${rove_map_dir}/typo.ini
  ${rove_map_datasets}/RO-SLAM_demo.rawlog -o ${rove_map_dir}/typo)
set_tests_properties(cli.map_build_unknown_key_fails PROPERTIES LABELS cli WILL_FAIL TRUE)

# Gas grids are not implemented: a clear error naming the key.
add_test(NAME cli.map_build_gas_grid COMMAND rove map build
  ${rove_map_configs}/icp-slam/icp-gas-mapping.ini
  ${rove_map_datasets}/localization_demo.simplemap.gz -o ${rove_map_dir}/gas)
set_tests_properties(cli.map_build_gas_grid PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "gasGrid_count: 1 map requested, but map kind 'gasGrid' is not implemented")

# `rove map convert`: MRPT .gridmap -> ROS map (PNG + yaml) -> .rovegrid ->
# ROS map again; both trinary PNGs must be byte-identical.
file(MAKE_DIRECTORY ${rove_map_dir}/convert)
add_test(NAME cli.map_convert_gridmap COMMAND rove map convert
  ${rove_mrpt_package}/2006-MalagaCampus.gridmap.gz ${rove_map_dir}/convert/malaga.yaml)
set_tests_properties(cli.map_convert_gridmap PROPERTIES LABELS cli FIXTURES_SETUP map_convert_1
  PASS_REGULAR_EXPRESSION "MRPT gridmap [^\n]*: [0-9]+ x [0-9]+ cells.*wrote [^\n]*malaga\\.png\n  wrote [^\n]*malaga\\.yaml")
add_test(NAME cli.map_convert_yaml_to_rovegrid COMMAND rove map convert
  ${rove_map_dir}/convert/malaga.yaml ${rove_map_dir}/convert/malaga.rovegrid.gz)
set_tests_properties(cli.map_convert_yaml_to_rovegrid PROPERTIES LABELS cli
  FIXTURES_REQUIRED map_convert_1 FIXTURES_SETUP map_convert_2
  PASS_REGULAR_EXPRESSION "ROS map .*wrote [^\n]*malaga\\.rovegrid\\.gz")
add_test(NAME cli.map_convert_rovegrid_to_yaml COMMAND rove map convert
  ${rove_map_dir}/convert/malaga.rovegrid.gz ${rove_map_dir}/convert/again.yaml)
set_tests_properties(cli.map_convert_rovegrid_to_yaml PROPERTIES LABELS cli
  FIXTURES_REQUIRED map_convert_2 FIXTURES_SETUP map_convert_3
  PASS_REGULAR_EXPRESSION "rove grid .*wrote [^\n]*again\\.png")
add_test(NAME cli.map_convert_same_png COMMAND ${CMAKE_COMMAND} -E compare_files
  ${rove_map_dir}/convert/malaga.png ${rove_map_dir}/convert/again.png)
set_tests_properties(cli.map_convert_same_png PROPERTIES LABELS cli FIXTURES_REQUIRED map_convert_3)
# A yaml with a yaw is refused, naming the file and the key.
file(WRITE ${rove_map_dir}/convert/yaw.yaml "image: malaga.png\nresolution: 0.2\norigin: [0, 0, 0.5]\n")
add_test(NAME cli.map_convert_yaw_rejected COMMAND rove map convert
  ${rove_map_dir}/convert/yaw.yaml ${rove_map_dir}/convert/yaw.rovegrid)
set_tests_properties(cli.map_convert_yaw_rejected PROPERTIES LABELS cli FIXTURES_REQUIRED map_convert_1
  PASS_REGULAR_EXPRESSION "yaw\\.yaml.*origin.*yaw 0\\.5")

# Entropy and information of a grid (grid_entropy.h): MRPT's uwb demo map
# has 455,000 cells of which 354,316 are unknown (p = 0.5), so 100,684 are
# mapped (GridEntropy.MatchesMrptComputeEntropyOnMrptGrids ties these
# numbers to MRPT's computeEntropy).
add_test(NAME cli.map_convert_prints_entropy COMMAND rove map convert
  ${PROJECT_SOURCE_DIR}/modules/io/tests/data/grid_uwb_demo.gridmap.gz ${rove_map_dir}/uwb.rovegrid)
set_tests_properties(cli.map_convert_prints_entropy PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "700 x 650 cells of 0\\.04 m[^\n]*\n    entropy [0-9.]+ nats, information [0-9.]+ \\(100684 mapped cells, 161\\.09 m2")

# Voronoi diagram of MRPT's uwb demo map (4 cm cells): with a 0.2 m robot
# no diagram cell has less than 0.2 m of clearance (the nearest possible is
# √26 cells = 0.204 m), and the image is written.
add_test(NAME cli.map_voronoi COMMAND rove map voronoi --robot-size 0.2
  ${PROJECT_SOURCE_DIR}/modules/io/tests/data/grid_uwb_demo.gridmap.gz -o ${rove_map_dir}/uwb_voronoi.png)
set_tests_properties(cli.map_voronoi PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "voronoi diagram: [1-9][0-9]* cells \\([0-9.]+ m\\), clearance 0\\.(20[4-9]|2[1-9][0-9]|[3-9][0-9][0-9]) to [0-9.]+ m\n  wrote [^\n]*uwb_voronoi\\.png")
# ...an unknown image kind is refused before any work.
add_test(NAME cli.map_voronoi_bad_output COMMAND rove map voronoi
  ${PROJECT_SOURCE_DIR}/modules/io/tests/data/grid_uwb_demo.gridmap.gz -o ${rove_map_dir}/uwb_voronoi.jpg)
set_tests_properties(cli.map_voronoi_bad_output PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "uwb_voronoi\\.jpg: expected a \\.png or \\.pgm image")

# Careless input (apps/tests/map_safety.sh): outputs over inputs are refused
# with inputs intact, sizes beyond the memory budget are refused naming the
# file or the config key, `config check --for` rejects what the commands
# reject and warns on repeated keys.
add_test(NAME cli.map_safety
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/tests/map_safety.sh $<TARGET_FILE:rove>
          ${PROJECT_SOURCE_DIR} ${rove_map_dir}/safety)
set_tests_properties(cli.map_safety PROPERTIES LABELS cli TIMEOUT 300
  PASS_REGULAR_EXPRESSION "[0-9]+ passed, 0 failed")

# `rove map check`: a simplemap's 2D scans against each other. MRPT's own
# maps of the Malaga faculty and the localization demo agree with
# themselves; ICP-SLAM's map of the Intel log's first 3,000 steps (written
# by cli.icp_slam_contradicted_map) does not: exit 3. Not a simplemap: exit 1.
set(rove_map_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
add_test(NAME cli.map_check_malaga COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map check ${ROVE_DATASETS_DIR}/mrpt/malaga-cs-fac-building.simplemap.gz"
  -DEXIT=0 "-DREGEX=99 keyframes, 99 2D scans.*0 of 98 with more than 20 % of the rays through walls"
  -P ${rove_map_expect})
add_test(NAME cli.map_check_localization_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map check --json ${rove_map_datasets}/localization_demo.simplemap.gz"
  -DEXIT=0 "-DREGEX=\"keyframes\": 72,.*\"checked\": 71,.*\"contradicted\": 0,.*\"issues\": \\[\\]"
  -P ${rove_map_expect})
add_test(NAME cli.map_check_contradicted COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map check ${CMAKE_CURRENT_BINARY_DIR}/icp_slam_tests/contradicted/map.simplemap"
  -DEXIT=3 "-DREGEX=scan [0-9]+ at \\(.*\\) m: [0-9]+ % of its rays through walls.*rove: warning: map-contradicts-scans: [0-9]+ of [0-9]+ scans saw more than 20 %"
  -P ${rove_map_expect})
add_test(NAME cli.map_check_not_a_simplemap COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map check ${rove_map_configs}/icp-slam/icp-slam_demo_classic.ini"
  -DEXIT=1 "-DREGEX=icp-slam_demo_classic.ini" -P ${rove_map_expect})
set_tests_properties(cli.map_check_malaga cli.map_check_localization_json cli.map_check_contradicted
  cli.map_check_not_a_simplemap PROPERTIES LABELS cli)
set_tests_properties(cli.map_check_contradicted PROPERTIES DEPENDS cli.icp_slam_contradicted_map)
rove_dataset_tests(cli.map_check_malaga cli.map_check_contradicted)
