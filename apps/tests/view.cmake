# `rove view` end to end (included by apps/CMakeLists.txt): scenes from the
# bundled clouds and graphs written as glTF and as one page, bad inputs, and
# (label `browser`) a screenshot through headless Chromium and the served
# page stopped with Ctrl-C.
set(rove_view_dir ${CMAKE_CURRENT_BINARY_DIR}/view_tests)
file(MAKE_DIRECTORY ${rove_view_dir})
set(rove_view_expect -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set(rove_view_pc ${PROJECT_SOURCE_DIR}/data/pointcloud)
set(rove_view_graph ${PROJECT_SOURCE_DIR}/data/posegraph/w100.graph)

# A cloud and a pose graph: one scene, as glTF and as a page.
add_test(NAME cli.view_export COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_pc}/bunny.pcd ${rove_view_graph} --export ${rove_view_dir}/scene.glb --html ${rove_view_dir}/scene.html"
  -DEXIT=0
  "-DREGEX=bunny\\.pcd: PCD point cloud, 397 points\n[^\n]*w100\\.graph: pose graph, 2D, 60 vertices, 240 edges \\(12 loop closures by 28 edges\\)\nscene: 4 layers, 597 vertices.*wrote [^\n]*scene\\.glb\nwrote [^\n]*scene\\.html"
  -DFILE=${rove_view_dir}/scene.html "-DFILE_REGEX=<title>rove view: loading</title>.*GLTFLoader.*roveView\\({base64: "
  ${rove_view_expect})
set_tests_properties(cli.view_export PROPERTIES LABELS cli)

# An unknown file is named and skipped (exit 3, the rest is written); with
# nothing else, nothing is written (exit 1).
file(WRITE ${rove_view_dir}/notes.xyz "not a scene\n")
add_test(NAME cli.view_skips_unknown COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/notes.xyz ${rove_view_pc}/bunny.pcd --export ${rove_view_dir}/skip.glb"
  -DEXIT=3 "-DREGEX=rove: warning: skipped-input: [^\n]*notes\\.xyz \\[format\\]: a file rove cannot show"
  ${rove_view_expect})
set_tests_properties(cli.view_skips_unknown PROPERTIES LABELS cli)
add_test(NAME cli.view_nothing_readable COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/notes.xyz ${rove_view_dir}/missing.pcd --export ${rove_view_dir}/none.glb"
  -DEXIT=1 "-DREGEX=notes\\.xyz.*missing\\.pcd.*rove: error: nothing to show: none of the 2 inputs could be read"
  -DABSENT=${rove_view_dir}/none.glb ${rove_view_expect})
set_tests_properties(cli.view_nothing_readable PROPERTIES LABELS cli)

# An empty cloud, a cloud without a finite point, NaN points (left out and
# counted), a corrupt graph.
file(WRITE ${rove_view_dir}/empty.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n")
file(WRITE ${rove_view_dir}/all_nan.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\nnan nan nan\nnan 0 0\n")
file(WRITE ${rove_view_dir}/some_nan.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 0 0\nnan nan nan\n0 1 0\n")
file(WRITE ${rove_view_dir}/broken.g2o "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 7 1 0 0 1 0 0 1 0 1\n")
add_test(NAME cli.view_empty_cloud COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/empty.pcd --export ${rove_view_dir}/empty.glb"
  -DEXIT=1 "-DREGEX=empty\\.pcd[^\n]*the cloud has no point.*nothing to show" -DABSENT=${rove_view_dir}/empty.glb
  ${rove_view_expect})
add_test(NAME cli.view_all_nan_cloud COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/all_nan.pcd --export ${rove_view_dir}/all_nan.glb"
  -DEXIT=1 "-DREGEX=all_nan\\.pcd[^\n]*none of its 2 points is finite" -DABSENT=${rove_view_dir}/all_nan.glb
  ${rove_view_expect})
add_test(NAME cli.view_nan_points COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/some_nan.pcd --export ${rove_view_dir}/some_nan.glb"
  -DEXIT=3 "-DREGEX=2 points, 1 not finite left out.*rove: warning: skipped-points: 1 points"
  ${rove_view_expect})
add_test(NAME cli.view_corrupt_graph COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/broken.g2o ${rove_view_pc}/bunny.pcd --export ${rove_view_dir}/broken.glb"
  -DEXIT=3 "-DREGEX=rove: warning: skipped-input: [^\n]*broken\\.g2o" ${rove_view_expect})
set_tests_properties(cli.view_empty_cloud cli.view_all_nan_cloud cli.view_nan_points cli.view_corrupt_graph
  PROPERTIES LABELS cli)

# Never over an input.
add_test(NAME cli.view_output_is_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_dir}/some_nan.pcd --html ${rove_view_dir}/some_nan.pcd"
  -DEXIT=1 "-DREGEX=some_nan\\.pcd" ${rove_view_expect})
set_tests_properties(cli.view_output_is_input PROPERTIES LABELS cli)

# A picture through headless Chromium, and the served page (label browser).
add_test(NAME cli.view_screenshot COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_view_pc}/room_scan1.pcd --screenshot ${rove_view_dir}/room.png --size 320x200"
  -DEXIT=0 "-DREGEX=wrote [^\n]*room\\.png" -DFILE=${rove_view_dir}/room.png "-DFILE_REGEX=^.PNG"
  ${rove_view_expect})
add_test(NAME cli.view_serve_interrupt COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/tests/view_serve.sh
  $<TARGET_FILE:rove> ${PROJECT_SOURCE_DIR} ${rove_view_dir}/serve)
set_tests_properties(cli.view_screenshot cli.view_serve_interrupt PROPERTIES LABELS "cli;browser" TIMEOUT 120)

# The output folders of rove kf-slam and rove rbpf-slam, as their tests
# leave them: landmarks with their ellipsoids; the map with the path.
add_test(NAME cli.view_kf_slam_folder COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_kfs_dir}/da --export ${rove_view_dir}/kf_slam.glb"
  -DEXIT=0 "-DREGEX=da: rove kf-slam output, [0-9]+ poses \\(path\\.tum\\); 20 3D landmarks with their 3-sigma ellipsoids"
  ${rove_view_expect})
set_tests_properties(cli.kf_slam_6d_datassoc PROPERTIES FIXTURES_SETUP rove_kf_slam_out)
add_test(NAME cli.view_rbpf_slam_folder COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_rbpf_dir}/telecom --export ${rove_view_dir}/rbpf_slam.glb"
  -DEXIT=0 "-DREGEX=telecom: rove rbpf-slam output, map [0-9]+ x [0-9]+ cells of 0\\.07 m; [0-9]+ poses \\(path\\.tum\\), odometry\\.tum"
  ${rove_view_expect})
set_tests_properties(cli.rbpf_slam_telecom PROPERTIES FIXTURES_SETUP rove_rbpf_slam_out)
set_tests_properties(cli.view_kf_slam_folder PROPERTIES LABELS cli FIXTURES_REQUIRED rove_kf_slam_out)
set_tests_properties(cli.view_rbpf_slam_folder PROPERTIES LABELS cli FIXTURES_REQUIRED rove_rbpf_slam_out)

# The output folder of rove rgbd-slam, as its test on 60 frames of TUM
# fr1/rpy leaves it: the coloured map, the pose graph with each loop once,
# the trajectory, the keyframes and the loop checks (label datasets).
if(TARGET rove::vision)
  add_test(NAME cli.view_rgbd_slam_folder COMMAND ${CMAKE_COMMAND}
    "-DCOMMAND=$<TARGET_FILE:rove> view ${rove_rg_dir}/fr1 --export ${rove_view_dir}/rgbd_slam.glb"
    -DEXIT=0
    "-DREGEX=fr1: rove rgbd-slam output, map [1-9][0-9]+ points; octree [1-9][0-9]* leaves, resolution 0.05 m \\(hidden at first\\); graph 3D, [1-9][0-9]* vertices, [1-9][0-9]* edges \\([1-9][0-9]* loop closures by [1-9][0-9]* edges\\); 60 poses \\(trajectory\\.tum\\); [1-9][0-9]* keyframes; loops\\.csv: [1-9][0-9]* of [1-9][0-9]* loop checks accepted \\((appearance [0-9]+, )?nearby [0-9]+.*wrote [^\n]*rgbd_slam\\.glb"
    ${rove_view_expect})
  set_tests_properties(cli.rgbd_slam_fr1 PROPERTIES FIXTURES_SETUP rove_rgbd_slam_out)
  set_tests_properties(cli.view_rgbd_slam_folder PROPERTIES LABELS cli FIXTURES_REQUIRED rove_rgbd_slam_out)
  rove_dataset_tests(cli.view_rgbd_slam_folder)
endif()
