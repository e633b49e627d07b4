# `rove rgbd-slam` end to end (included from apps/CMakeLists.txt; only when
# rove::vision is built): TUM fr1/rpy and the Kinect frames of the shared
# datasets (label `datasets`), a tutorial parameters.txt, and bad input.
if(TARGET rove::vision)
set(rove_rg_dir ${CMAKE_CURRENT_BINARY_DIR}/rgbd_slam_tests)
file(MAKE_DIRECTORY ${rove_rg_dir})
set(rove_rg_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set(rove_rg_fr1 ${ROVE_DATASETS_DIR}/rgbd/tum_fr1_rpy)

# 60 frames of fr1/rpy: every file, the ATE against groundtruth.txt.
add_test(NAME cli.rgbd_slam_fr1 COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --max-frames 60 ${rove_rg_fr1} -o ${rove_rg_dir}/fr1"
  -DEXIT=0 "-DREGEX=rgbd-slam: 60 frames .*tum, camera tum-fr1.*60 tracked, 0 lost.*octree: 0\\.05 m cells, [1-9][0-9]+ nodes \\([1-9][0-9]+ leaves, [1-9][0-9]+ occupied\\).*ATE .*RMSE 0\\.0[0-3][0-9]* m.*wrote 7 files"
  -DFILE=${rove_rg_dir}/fr1/summary.json
  "-DFILE_REGEX=\"frames\": 60,.*\"frames_per_second\": [0-9.]+,.*\"rmse_m\": 0\\.0[0-3].*\"octree\": {[^}]*\"file\": \"map.bt\",[^}]*\"resolution\": 0.05,.*\"issues\": \\[\\]"
  -P ${rove_rg_expect})
# --json, the tutorial's preset.
add_test(NAME cli.rgbd_slam_tutorial_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --json --preset tutorial --max-frames 20 ${rove_rg_fr1} -o ${rove_rg_dir}/tutorial"
  -DEXIT=0
  "-DREGEX=\"preset\": \"tutorial\",.*\"frames\": 20,.*\"files\": \\[.*trajectory.tum.*keyframes.tum.*loops.csv.*map.ply.*graph.g2o.*map.bt"
  -P ${rove_rg_expect})
# octree_resolution = 0: no octree map; a bad --threads is refused.
file(WRITE ${rove_rg_dir}/nooctree.ini "[rgbd-slam]\noctree_resolution = 0\n")
add_test(NAME cli.rgbd_slam_no_octree COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --config ${rove_rg_dir}/nooctree.ini --max-frames 10 ${rove_rg_fr1} -o ${rove_rg_dir}/nooctree"
  -DEXIT=0 "-DREGEX=10 tracked.*wrote 6 files" -DABSENT=${rove_rg_dir}/nooctree/map.bt
  -DFILE=${rove_rg_dir}/nooctree/summary.json "-DFILE_REGEX=\"octree\": null"
  -P ${rove_rg_expect})
add_test(NAME cli.rgbd_slam_bad_threads COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --threads 100000 ${rove_rg_fr1} -o ${rove_rg_dir}/badthreads"
  -DEXIT=1 "-DREGEX=--threads" -DABSENT=${rove_rg_dir}/badthreads/summary.json -P ${rove_rg_expect})
# MRPT's tests_rgbd.rawlog (one CObservation3DRangeScan): one pose, the
# intensity camera; a rawlog without 3D range scans is an error naming it.
add_test(NAME cli.rgbd_slam_mrpt_rawlog COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress ${ROVE_DATASETS_DIR}/mrpt/tests_rgbd.rawlog -o ${rove_rg_dir}/rawlog"
  -DEXIT=0 "-DREGEX=rgbd-slam: 1 frames of .*tests_rgbd.rawlog' \\(rawlog, camera rawlog \\('OPENNI2' intensity camera\\), global shutter\\).*1 tracked, 0 lost.*1 keyframes.*octree: .*wrote 7 files"
  -DFILE=${rove_rg_dir}/rawlog/trajectory.tum "-DFILE_REGEX=1462879443\\.617[0-9]+ 0\\.000000 0\\.000000 0\\.000000 0\\.000000000 0\\.000000000 0\\.000000000 1\\.000000000"
  -P ${rove_rg_expect})
add_test(NAME cli.rgbd_slam_rawlog_without_scans COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress ${PROJECT_SOURCE_DIR}/data/mrpt/RO-SLAM_demo.rawlog -o ${rove_rg_dir}/noscans"
  -DEXIT=1 "-DREGEX=RO-SLAM_demo.rawlog.*no 3D range scan \\(CObservation3DRangeScan\\)"
  -DABSENT=${rove_rg_dir}/noscans/summary.json -P ${rove_rg_expect})
# Numbered Kinect frames far apart: some are not tracked; the run says so
# and exits 3 with its files written.
add_test(NAME cli.rgbd_slam_kinect5_lost COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --camera kinect ${ROVE_DATASETS_DIR}/rgbd/kinect5 -o ${rove_rg_dir}/kinect5"
  -DEXIT=3 "-DREGEX=numbered-frames, camera kinect.*rove: warning: lost-tracking: [1-4] of 5 frames"
  -DFILE=${rove_rg_dir}/kinect5/trajectory.tum "-DFILE_REGEX=1\\.000000 [-0-9]"
  -P ${rove_rg_expect})

# Bad input: not a sequence, a color image without depth, no camera, a
# misspelt key in the tutorial's parameters.txt.
file(MAKE_DIRECTORY ${rove_rg_dir}/empty)
add_test(NAME cli.rgbd_slam_not_a_sequence COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress ${rove_rg_dir}/empty -o ${rove_rg_dir}/empty_out"
  -DEXIT=1 "-DREGEX=empty.*not an RGB-D sequence" -DABSENT=${rove_rg_dir}/empty_out/summary.json
  -P ${rove_rg_expect})
file(WRITE ${rove_rg_dir}/nodepth/color/1.png "x")
file(MAKE_DIRECTORY ${rove_rg_dir}/nodepth/depth)
add_test(NAME cli.rgbd_slam_missing_depth COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress ${rove_rg_dir}/nodepth -o ${rove_rg_dir}/nodepth_out"
  -DEXIT=1 "-DREGEX=1.png.*no depth image numbered 1" -P ${rove_rg_expect})
file(WRITE ${rove_rg_dir}/nocam/color/1.png "x")
file(WRITE ${rove_rg_dir}/nocam/depth/1.png "x")
add_test(NAME cli.rgbd_slam_no_camera COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress ${rove_rg_dir}/nocam -o ${rove_rg_dir}/nocam_out"
  -DEXIT=1 "-DREGEX=nocam.*needs a camera" -P ${rove_rg_expect})
add_test(NAME cli.rgbd_slam_bad_frame COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --camera kinect ${rove_rg_dir}/nocam -o ${rove_rg_dir}/badframe_out"
  -DEXIT=1 "-DREGEX=nocam/color/1.png" -DABSENT=${rove_rg_dir}/badframe_out/summary.json -P ${rove_rg_expect})
file(WRITE ${rove_rg_dir}/params.txt "detector=ORB\ngood_match_treshold=10\ncamera.fx=518.0;\n")
add_test(NAME cli.rgbd_slam_misspelt_key COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> rgbd-slam --no-progress --camera kinect --config ${rove_rg_dir}/params.txt ${rove_rg_dir}/nocam -o ${rove_rg_dir}/misspelt_out"
  -DEXIT=1 "-DREGEX=params.txt.*good_match_treshold" -P ${rove_rg_expect})
set_tests_properties(cli.rgbd_slam_fr1 cli.rgbd_slam_tutorial_json cli.rgbd_slam_kinect5_lost
  cli.rgbd_slam_no_octree cli.rgbd_slam_bad_threads cli.rgbd_slam_mrpt_rawlog
  cli.rgbd_slam_rawlog_without_scans
  cli.rgbd_slam_not_a_sequence cli.rgbd_slam_missing_depth cli.rgbd_slam_no_camera
  cli.rgbd_slam_bad_frame cli.rgbd_slam_misspelt_key PROPERTIES LABELS cli)
rove_dataset_tests(cli.rgbd_slam_fr1 cli.rgbd_slam_tutorial_json cli.rgbd_slam_kinect5_lost
  cli.rgbd_slam_no_octree cli.rgbd_slam_bad_threads cli.rgbd_slam_mrpt_rawlog)
endif()
