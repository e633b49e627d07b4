# rove::vision beside OpenCV 4.6's own calls on TUM fr1/rpy frames: binary
# matching (rove's brute force vs cv::BFMatcher) and PnP with RANSAC (rove's
# AP3P RANSAC + Gauss-Newton vs cv::solvePnPRansac); ORB extraction is
# OpenCV's in both, timed for scale. Built when rove::vision is.
if(TARGET rove::vision)
  find_package(OpenCV 4 REQUIRED COMPONENTS core features2d calib3d)
  rove_add_bench(bench_vision_vs_opencv SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/vision_vs_opencv.cpp
                 LIBS rove::vision opencv_core opencv_features2d opencv_calib3d)
  target_include_directories(bench_vision_vs_opencv SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_compile_definitions(bench_vision_vs_opencv PRIVATE
    ROVE_DATASETS_DIR="${ROVE_DATASETS_DIR}")
endif()
