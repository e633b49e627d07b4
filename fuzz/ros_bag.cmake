# ROS 1 bags through rove's own bag reader (rove::ros), when the adapter is built.
if(TARGET rove::ros)
  rove_add_fuzzer(rove_ros_bag_fuzz ${CMAKE_CURRENT_LIST_DIR}/ros_bag_fuzz.cpp LIBS rove::ros rove::io)
endif()
