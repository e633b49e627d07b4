# `rove kf-slam` end to end (included from apps/CMakeLists.txt).
set(rove_kfs_dir ${CMAKE_CURRENT_BINARY_DIR}/kf_slam_tests)
file(MAKE_DIRECTORY ${rove_kfs_dir})
set(rove_kfs_expect ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)
set(rove_kfs_configs /usr/share/mrpt/config_files/kf-slam)

# MRPT's 6D data-association demo with its config unchanged: JCBB pairs every
# reading right (checked against the ground-truth map), errors against the
# ground truth, and every output; exit 0.
add_test(NAME cli.kf_slam_6d_datassoc COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> kf-slam ${rove_kfs_configs}/EKF-SLAM_6D_test_datassoc.ini --no-progress -o ${rove_kfs_dir}/da"
  -DEXIT=0 "-DREGEX=20 mapped from 1515 readings .*1495 correct, 0 wrong, 0 duplicate.*landmark RMSE: .*path RMSE: .*issues: none"
  -DFILE=${rove_kfs_dir}/da/summary.json
  "-DFILE_REGEX=\"landmark_rmse\": 0\\.[0-9]+,.*\"method\": \"jcbb\",.*\"landmarks\": \\[.*path.tum.*landmarks.csv.*map.png"
  -P ${rove_kfs_expect})

# The 6D demo with its IDs ignored: nearest-neighbour pairing starts a few
# duplicate landmarks, which the run names (warning, exit 3).
add_test(NAME cli.kf_slam_ignore_ids COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> kf-slam ${rove_kfs_configs}/EKF-SLAM_6D_test.ini --ignore-ids --json --no-progress -o ${rove_kfs_dir}/ignore_ids"
  -DEXIT=3 "-DREGEX=\"wrong\": 0,.*\"code\": \"duplicate-landmarks\""
  -P ${rove_kfs_expect})

# A config MRPT's kf-slam would run but rove cannot: a clear error, exit 1.
file(WRITE ${rove_kfs_dir}/ikf.ini "[RangeBearingKFSLAM_KalmanFilter]\nmethod = kfIKFFull\n")
add_test(NAME cli.kf_slam_unsupported_method COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> kf-slam ${rove_kfs_dir}/ikf.ini ${PROJECT_SOURCE_DIR}/data/mrpt/kf-slam_demo.rawlog --no-progress -o ${rove_kfs_dir}/ikf"
  -DEXIT=1 "-DREGEX=rove: error: .*method.*not implemented in rove"
  -P ${rove_kfs_expect})

set_tests_properties(cli.kf_slam_6d_datassoc cli.kf_slam_ignore_ids cli.kf_slam_unsupported_method
  PROPERTIES LABELS cli)
