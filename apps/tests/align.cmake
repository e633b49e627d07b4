# rove align end to end: the small_gicp pair from the shared datasets
# (ROVE_DATASETS_DIR, label `datasets`), the PCL tutorial pair and the bunny
# bundled in data/pointcloud.
set(rove_align_data ${ROVE_DATASETS_DIR}/pointcloud)
set(rove_align_bundled ${PROJECT_SOURCE_DIR}/data/pointcloud)

# GICP on the small_gicp pair recovers the published transform (translation
# row 0.4889 0.1212 -0.0253 to the printed precision band).
add_test(NAME cli.align_gicp_small_gicp COMMAND rove align --method gicp --voxel 0.5 --threads 2
  ${rove_align_data}/small_gicp_source.ply ${rove_align_data}/small_gicp_target.ply)
set_tests_properties(cli.align_gicp_small_gicp PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "T_target_source:\n[^\n]* 0\\.4[89][0-9]*\n[^\n]* 0\\.1[0-3][0-9]*\n.*termination: Converged")
rove_dataset_tests(cli.align_gicp_small_gicp)

# NDT with the PCL tutorial's guess, writing the aligned cloud.
add_test(NAME cli.align_ndt_room COMMAND rove align --method ndt --voxel 0.2
  --init 1.79387,0.720047,0,0,0,0.6931 -o ${CMAKE_CURRENT_BINARY_DIR}/room_aligned.pcd
  ${rove_align_bundled}/room_scan2.pcd ${rove_align_bundled}/room_scan1.pcd)
set_tests_properties(cli.align_ndt_room PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "termination: Converged.*aligned source written")

# Bad input: a malformed --init is an error, not a run from garbage.
add_test(NAME cli.align_bad_init COMMAND rove align --init 1,2,three,0,0,0
  ${rove_align_bundled}/bunny.pcd ${rove_align_bundled}/bunny.pcd)
set_tests_properties(cli.align_bad_init PROPERTIES LABELS cli WILL_FAIL TRUE)

# A single plane is degenerate: exit status 3, reported in the output.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/align_plane.pcd
  "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 400\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 400\nDATA ascii\n")
foreach(i RANGE 0 19)
  foreach(j RANGE 0 19)
    file(APPEND ${CMAKE_CURRENT_BINARY_DIR}/align_plane.pcd "${i}.0 ${j}.0 0\n")
  endforeach()
endforeach()
add_test(NAME cli.align_plane_degenerate COMMAND rove align --method point-to-plane
  --init 0.2,0.1,0.05,0,0,0.02
  ${CMAKE_CURRENT_BINARY_DIR}/align_plane.pcd ${CMAKE_CURRENT_BINARY_DIR}/align_plane.pcd)
set_tests_properties(cli.align_plane_degenerate PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "termination: Degenerate")
