# The split between the tests every clone runs and those that need the large
# shared datasets (ROVE_DATASETS_DIR; README, "Quick start").
#
# The label: the suites named *Datasets and the command-line tests passed to
# rove_dataset_tests() carry `datasets`, and the others do not.
add_test(NAME tests.datasets_label COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${CMAKE_BINARY_DIR} -N -L datasets)
set_tests_properties(tests.datasets_label PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "CarmenDatasets\\.IntelImportsEveryScanAndOdometryLine.*cli\\.align_gicp_small_gicp"
  FAIL_REGULAR_EXPRESSION "PclReference\\.LoadFilterAndSearchAgreeWithPcl|cli\\.align_ndt_room")
# No test builds a path into the shared folder by hand: they go through
# rove/test_data.h (shared_dataset) or ROVE_DATASETS_DIR, so the folder can be
# moved and the label stays true.
add_test(NAME tests.datasets_paths_through_the_helper
  COMMAND sh -c "! grep -rn -e '\\.\\./shared' --include=*.cpp --include=*.h modules/*/tests apps/tests/*.cmake apps/tests/*.sh"
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(tests.datasets_paths_through_the_helper PROPERTIES LABELS cli)
