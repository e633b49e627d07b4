# `rove octomap build` end to end (included by apps/CMakeLists.txt): clouds
# bundled in data/pointcloud, OctoMap's test scan from the shared datasets.
set(rove_octomap_dir ${CMAKE_CURRENT_BINARY_DIR}/octomap_tests)
file(MAKE_DIRECTORY ${rove_octomap_dir})
set(rove_octomap_pc ${PROJECT_SOURCE_DIR}/data/pointcloud)
set(rove_octomap_expect -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# A room scan (its VIEWPOINT is the sensor origin) into a .bt, with the
# occupied cells as PLY and a slice as a ROS map; the .bt reads back.
add_test(NAME cli.octomap_build_room COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_pc}/room_scan1.pcd -o ${rove_octomap_dir}/room.bt --res 0.1 --ply ${rove_octomap_dir}/room_occupied.ply --slice ${rove_octomap_dir}/room_slice --slice-z 0.5 --threads 2"
  -DEXIT=0
  "-DREGEX=octree: 1 clouds, 112586 points \\(0 skipped\\), resolution 0\\.1 m.*nodes: [0-9]+ \\([0-9]+ leaves, [0-9]+ occupied\\).*wrote [^\n]*room\\.bt.*wrote [^\n]*room_occupied\\.ply.*wrote [^\n]*room_slice\\.png.*room_slice\\.yaml.*issues: none"
  -DFILE=${rove_octomap_dir}/room.bt "-DFILE_REGEX=^# Octomap OcTree binary file\n.*\nid OcTree\nsize [0-9]+\nres 0\\.1\ndata\n"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_room PROPERTIES LABELS cli)

# The same cloud twice from given origins into a full .ot, JSON summary.
add_test(NAME cli.octomap_build_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --json --origin 0.5,0.2,0.3 --max-range 4 ${rove_octomap_pc}/bunny.pcd ${rove_octomap_pc}/bunny.pcd -o ${rove_octomap_dir}/bunny.ot --res 0.005"
  -DEXIT=0
  "-DREGEX=\"command\": \"octomap build\",.*\"resolution\": 0\\.005,.*\"points\": 794,\n  \"skipped_points\": 0,.*\"outputs\": \\[\n    \"[^\"]*bunny\\.ot\"\n  \\],\n  \"issues\": \\[\\]"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_json PROPERTIES LABELS cli)

# Points that are not finite are skipped and reported: exit status 3.
file(WRITE ${rove_octomap_dir}/nan.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 0 0\nnan nan nan\n0 1 0\n")
add_test(NAME cli.octomap_build_skipped_points COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/nan.bt"
  -DEXIT=3 "-DREGEX=rove: warning: skipped-points: 1 of 3 points"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_skipped_points PROPERTIES LABELS cli)

# Poses place clouds given in the sensor frame: one pose per cloud.
file(WRITE ${rove_octomap_dir}/two_poses.txt "# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0.7071068 0.7071068\n")
file(WRITE ${rove_octomap_dir}/one_pose.txt "0 0 0 0 0 0 0 1\n")
add_test(NAME cli.octomap_build_poses COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --poses ${rove_octomap_dir}/two_poses.txt ${rove_octomap_dir}/nan.pcd ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/posed.ot --res 0.05"
  -DEXIT=3 "-DREGEX=octree: 2 clouds, 6 points \\(2 skipped\\)" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_poses PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_pose_count COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --poses ${rove_octomap_dir}/one_pose.txt ${rove_octomap_dir}/nan.pcd ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/count.bt"
  -DEXIT=1 "-DREGEX=1 poses for 2 clouds" -DABSENT=${rove_octomap_dir}/count.bt ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_pose_count PROPERTIES LABELS cli)

# Never over an input (the input is left as it was, no output is written);
# unknown formats, missing or corrupt inputs and bad numbers are errors.
file(WRITE ${rove_octomap_dir}/kept.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 0 0\n")
file(WRITE ${rove_octomap_dir}/kept_ref.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 0 0\n")
add_test(NAME cli.octomap_build_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/kept.pcd -o ${rove_octomap_dir}/kept.bt --pcd ${rove_octomap_dir}/kept.pcd"
  -DEXIT=1 "-DREGEX=kept\\.pcd" -DKEEP=${rove_octomap_dir}/kept.pcd -DREF=${rove_octomap_dir}/kept_ref.pcd
  -DABSENT=${rove_octomap_dir}/kept.bt ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_output_is_input PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_missing_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/no_such.pcd -o ${rove_octomap_dir}/missing.bt"
  -DEXIT=1 "-DREGEX=no_such\\.pcd" -DABSENT=${rove_octomap_dir}/missing.bt ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_missing_input PROPERTIES LABELS cli)
file(WRITE ${rove_octomap_dir}/corrupt.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n1 0 0\n0 1\n")
add_test(NAME cli.octomap_build_corrupt_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/corrupt.pcd -o ${rove_octomap_dir}/corrupt.bt"
  -DEXIT=1 "-DREGEX=corrupt\\.pcd" -DABSENT=${rove_octomap_dir}/corrupt.bt ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_corrupt_input PROPERTIES LABELS cli)
file(WRITE ${rove_octomap_dir}/bad_pose.txt "0 0 0 0 0 0 0 1\n1 1 0 zero 0 0 0 1\n")
add_test(NAME cli.octomap_build_bad_trajectory COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --poses ${rove_octomap_dir}/bad_pose.txt ${rove_octomap_dir}/nan.pcd ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/bad_pose.bt"
  -DEXIT=1 "-DREGEX=bad_pose\\.txt.*2.*z.*'zero' is not a finite number" -DABSENT=${rove_octomap_dir}/bad_pose.bt
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_bad_trajectory PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_origin_and_poses COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --poses ${rove_octomap_dir}/two_poses.txt --origin 0,0,0 ${rove_octomap_dir}/nan.pcd ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/op.bt"
  -DEXIT=2 "-DREGEX=--origin excludes --poses" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_origin_and_poses PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_nan_max_range COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/mr.bt --max-range nan"
  -DEXIT=2 "-DREGEX=--max-range: 'nan' is not a finite number" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_nan_max_range PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_slice_outside COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/sz.bt --slice ${rove_octomap_dir}/sz --slice-z 5000"
  -DEXIT=1 "-DREGEX=--slice-z = 5000: outside the octree, which spans ±3276\\.8 m" -DABSENT=${rove_octomap_dir}/sz.bt
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_slice_outside PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_bad_output COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/x.png"
  -DEXIT=1 "-DREGEX=expected \\.bt or \\.ot" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_bad_output PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_bad_origin COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/o.bt --origin 1,2"
  -DEXIT=1 "-DREGEX=--origin.*not X,Y,Z" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_bad_origin PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_bad_res COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/nan.pcd -o ${rove_octomap_dir}/r.bt --res 0"
  -DEXIT=2 "-DREGEX=--res" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_bad_res PROPERTIES LABELS cli)

# Coloured clouds make OctoMap's ColorOcTree: each leaf the mean colour of
# its points by default (two points share a cell here), OctoMap's rules on
# request; a cloud without colours before them is converted; a .bt keeps no
# colours, which is reported.
file(WRITE ${rove_octomap_dir}/colored.ply
  "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n1.01 0.01 0.01 10 20 30\n1.09 0.02 0.03 31 40 50\n0.01 1.01 0.01 200 0 0\n0.01 0.01 1.01 0 0 255\n")
add_test(NAME cli.octomap_build_colour_mean COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/colored.ply -o ${rove_octomap_dir}/colored.ot --res 0.1"
  -DEXIT=0 "-DREGEX=colours: mean \\(1 clouds, 4 points, 3 leaves\\).*issues: none"
  -DFILE=${rove_octomap_dir}/colored.ot "-DFILE_REGEX=^# Octomap OcTree file\n.*id ColorOcTree\nsize [0-9]+\nres 0\\.1\ndata\n"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_colour_mean PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_colour_after_plain COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --json --color average ${rove_octomap_dir}/kept.pcd ${rove_octomap_dir}/colored.ply -o ${rove_octomap_dir}/mixed.ot --res 0.1"
  -DEXIT=0 "-DREGEX=\"colors\": {\n    \"rule\": \"average\",\n    \"clouds\": 1,\n    \"points\": 4,"
  -DFILE=${rove_octomap_dir}/mixed.ot "-DFILE_REGEX=\nid ColorOcTree\n"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_colour_after_plain PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_colour_into_bt COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build ${rove_octomap_dir}/colored.ply -o ${rove_octomap_dir}/colored.bt"
  -DEXIT=3 "-DREGEX=rove: warning: colors-not-written: [^\n]*colored\\.bt holds no colours" ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_colour_into_bt PROPERTIES LABELS cli)
add_test(NAME cli.octomap_build_colour_none COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --color none ${rove_octomap_dir}/colored.ply -o ${rove_octomap_dir}/plain.ot"
  -DEXIT=0 "-DREGEX=issues: none" -DFILE=${rove_octomap_dir}/plain.ot "-DFILE_REGEX=\nid OcTree\n"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_build_colour_none PROPERTIES LABELS cli)

# Every default is visible in --help.
add_test(NAME cli.octomap_help_shows_defaults COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> octomap build --help" -DEXIT=0
  "-DREGEX=--res[^\n]*=0\\.1.*--origin.*default: a PCD.*--poses.*default none.*--max-range[^\n]*=-1.*--mode[^\n]*=once.*--arithmetic[^\n]*=double.*--threads[^\n]*=1.*--color[^\n]*=mean.*--ply[^\n]*default none"
  ${rove_octomap_expect})
set_tests_properties(cli.octomap_help_shows_defaults PROPERTIES LABELS cli)

# `rove map build` fills MRPT's octoMap from a rawlog with a 3D range scan
# (MRPT's tests_rgbd.rawlog: one RGB-D frame) and writes it as .bt.
file(WRITE ${rove_octomap_dir}/octomap.ini
  "[MappingApplication]\noctoMap_count=1\ncolourOctoMap_count=1\n[MappingApplication_octoMap_00_creationOpts]\nresolution=0.05\n[MappingApplication_colourOctoMap_00_creationOpts]\nresolution=0.05\n")
add_test(NAME cli.map_build_octomap_rgbd COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map build ${rove_octomap_dir}/octomap.ini ${ROVE_DATASETS_DIR}/mrpt/tests_rgbd.rawlog -o ${rove_octomap_dir}/rgbd"
  -DEXIT=0 "-DREGEX=map 0 colourOctoMap: 3333 occupied voxels of 9362 cells.*map 1 octoMap: 3333 occupied voxels of 9362 cells.*wrote [^\n]*map_00_colourOctoMap\\.ot.*wrote [^\n]*map_01_octoMap\\.bt"
  -DFILE=${rove_octomap_dir}/rgbd/map_00_colourOctoMap.ot "-DFILE_REGEX=^# Octomap OcTree file\n.*id ColorOcTree\nsize [0-9]+\nres 0\\.05\ndata\n"
  ${rove_octomap_expect})
set_tests_properties(cli.map_build_octomap_rgbd PROPERTIES LABELS cli)
rove_dataset_tests(cli.map_build_octomap_rgbd)

# Velodyne scans of raw packets are decoded with the calibration they carry
# (MRPT's VLP-16 test scan); a scan without one is reported, not inserted.
file(WRITE ${rove_octomap_dir}/velodyne.ini
  "[MappingApplication]\noctoMap_count=1\n[MappingApplication_octoMap_00_creationOpts]\nresolution=0.2\n")
add_test(NAME cli.map_build_octomap_velodyne COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map build ${rove_octomap_dir}/velodyne.ini ${PROJECT_SOURCE_DIR}/data/mrpt/test_velodyne_VLP16.rawlog -o ${rove_octomap_dir}/velodyne"
  -DEXIT=0 "-DREGEX=map 0 octoMap: [1-9][0-9]+ occupied voxels of [0-9]+ cells[^\n]*, 1 observations inserted"
  ${rove_octomap_expect})
set_tests_properties(cli.map_build_octomap_velodyne PROPERTIES LABELS cli)
add_test(NAME cli.map_build_octomap_velodyne_uncalibrated COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> map build ${rove_octomap_dir}/velodyne.ini ${PROJECT_SOURCE_DIR}/modules/io/tests/data/mrpt_synthetic_velodyne_uncalibrated.rawlog -o ${rove_octomap_dir}/velodyne_uncalibrated"
  -DEXIT=3 "-DREGEX=rove: warning: velodyne-not-decoded: map 0 \\(octoMap\\): 1 Velodyne scan not inserted: the scan holds 2 raw packets but no per-laser calibration"
  ${rove_octomap_expect})
set_tests_properties(cli.map_build_octomap_velodyne_uncalibrated PROPERTIES LABELS cli)
