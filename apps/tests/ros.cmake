# `rove rawlog convert` to and from ROS bags, and a SLAM command reading a
# bag (included from apps/CMakeLists.txt; only with the rove::ros adapter).
if(NOT TARGET rove::ros)
  return()
endif()
set(rove_ros_dir ${CMAKE_CURRENT_BINARY_DIR}/ros_tests)
file(MAKE_DIRECTORY ${rove_ros_dir})
set(rove_ros_telecom
  ${PROJECT_SOURCE_DIR}/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog)

# MRPT rawlog → bag: a scan and an odometry message per frame, the laser's
# pose on /tf_static.
add_test(NAME cli.ros_convert_to_bag COMMAND rove rawlog convert --no-progress
  ${rove_ros_telecom} ${rove_ros_dir}/telecom.bag)
set_tests_properties(cli.ros_convert_to_bag PROPERTIES LABELS cli FIXTURES_SETUP rove_ros_bag
  PASS_REGULAR_EXPRESSION "entries: 449 read, 451 messages written.*225  messages on /odom.*225  messages on /scan.*1  messages on /tf_static.*dropped: none")
# The bag reads back as the rawlog's layout, with nothing skipped.
add_test(NAME cli.ros_info_bag COMMAND rove rawlog info --no-progress ${rove_ros_dir}/telecom.bag)
set_tests_properties(cli.ros_info_bag PROPERTIES LABELS cli FIXTURES_REQUIRED rove_ros_bag
  PASS_REGULAR_EXPRESSION "format: ROS bag.*entries: 449 \\(224 action collections, 225 sensory frames, 0 bare observations\\).*225  RangeScan2D \\[scan\\].*224  RobotMovement2D.*skipped: nothing")
# bag → rove rawlog with a topic selection: scans only, the odometry skipped.
add_test(NAME cli.ros_convert_from_bag_topics COMMAND rove rawlog convert --no-progress
  --topics /scan --layout 2 ${rove_ros_dir}/telecom.bag ${rove_ros_dir}/scans.rawlog)
set_tests_properties(cli.ros_convert_from_bag_topics PROPERTIES LABELS cli FIXTURES_REQUIRED rove_ros_bag
  PASS_REGULAR_EXPRESSION "\\(ROS bag\\).*entries: 225 read, 225 written.*225  RangeScan2D.*225 messages on /odom \\(nav_msgs/Odometry\\): not among --topics")

# icp-slam on the bag writes the very path it writes from the rawlog (the
# scans come back bit for bit, the odometry increments to 1e-15 m, which
# leaves every printed digit of the path unchanged).
add_test(NAME cli.ros_icp_slam_rawlog COMMAND rove icp-slam --no-progress
  ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini ${rove_ros_telecom} -o ${rove_ros_dir}/icp_rawlog)
set_tests_properties(cli.ros_icp_slam_rawlog PROPERTIES LABELS cli FIXTURES_SETUP rove_ros_icp_rawlog)
add_test(NAME cli.ros_icp_slam_bag COMMAND rove icp-slam --no-progress
  ${PROJECT_SOURCE_DIR}/data/mrpt/icp-slam_demo_classic.ini ${rove_ros_dir}/telecom.bag -o ${rove_ros_dir}/icp_bag)
set_tests_properties(cli.ros_icp_slam_bag PROPERTIES LABELS cli FIXTURES_REQUIRED rove_ros_bag
  FIXTURES_SETUP rove_ros_icp_bag
  PASS_REGULAR_EXPRESSION "224 steps from .*\\(ROS bag\\).*ICP: 182 runs, 182 accepted")
add_test(NAME cli.ros_icp_slam_same_path COMMAND ${CMAKE_COMMAND} -E compare_files
  ${rove_ros_dir}/icp_rawlog/path.tum ${rove_ros_dir}/icp_bag/path.tum)
set_tests_properties(cli.ros_icp_slam_same_path PROPERTIES LABELS cli
  FIXTURES_REQUIRED "rove_ros_icp_rawlog;rove_ros_icp_bag")

# docs/ros.md's example runs as written.
add_test(NAME cli.ros_docs_example COMMAND ${CMAKE_COMMAND} -DDOC=${PROJECT_SOURCE_DIR}/docs/ros.md
  -DWORK=${rove_ros_dir}/docs_example -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DROVE=$<TARGET_FILE:rove>
  -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/run_doc_sh.cmake)
set_tests_properties(cli.ros_docs_example PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "format: ROS bag.*225  RangeScan2D \\[scan\\].*skipped: nothing.*icp-slam: 224 steps from telecom.bag \\(ROS bag\\).*entries: 225 read, 225 written")
