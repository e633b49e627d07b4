# End-to-end tests of `rove eval` (included by apps/CMakeLists.txt): values
# computed by hand on small trajectories, the formats it reads, and what it
# says about poses and relations it cannot use.

set(rove_eval_dir ${CMAKE_CURRENT_BINARY_DIR}/eval_tests)
file(MAKE_DIRECTORY ${rove_eval_dir})
set(rove_eval_expect -P ${CMAKE_CURRENT_SOURCE_DIR}/tests/scripts/expect_exit.cmake)

# A reference square (TUM) and the same square 0.1 m off in y (KITTI rows:
# time = row index, so the reference times are 0..3 too).
file(WRITE ${rove_eval_dir}/gt.tum
  "# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 1 1 0 0 0 0 1\n3 0 1 0 0 0 0 1\n")
file(WRITE ${rove_eval_dir}/est.kitti
  "1 0 0 0 0 1 0 0.1 0 0 1 0\n1 0 0 1 0 1 0 0.1 0 0 1 0\n1 0 0 1 0 1 0 1.1 0 0 1 0\n1 0 0 0 0 1 0 1.1 0 0 1 0\n")
add_test(NAME cli.eval_ate_unaligned COMMAND rove eval ate --align none
  ${rove_eval_dir}/gt.tum ${rove_eval_dir}/est.kitti)
set_tests_properties(cli.eval_ate_unaligned PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "pairs +4 .*translation +rmse 0\\.1 +mean 0\\.1 +median 0\\.1 +std [0-9.e-]+ +min 0\\.1 +max 0\\.1 m")
# Aligned (the default, SE3) the offset is gone; the plot is written.
add_test(NAME cli.eval_ate_aligned_json COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval ate --json --plot ${rove_eval_dir}/ate.png ${rove_eval_dir}/gt.tum ${rove_eval_dir}/est.kitti"
  -DEXIT=0 "-DREGEX=\"method\": \"se3\".*\"translation_m\": {[^}]*\"count\": 4,[^}]*\"rmse\": [0-9.]*e-1[0-9].*\"issues\": \\[\\]"
  -DFILE=${rove_eval_dir}/ate.png "-DFILE_REGEX=^.PNG" ${rove_eval_expect})
set_tests_properties(cli.eval_ate_aligned_json PROPERTIES LABELS cli)
# RPE over one frame: each step of the estimate equals the reference's.
add_test(NAME cli.eval_rpe COMMAND rove eval rpe
  ${rove_eval_dir}/gt.tum ${rove_eval_dir}/est.kitti)
set_tests_properties(cli.eval_rpe PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "3 intervals of 1 frames.*translation +rmse 0 ")

# An estimate pose without a reference pose near its time: evaluated, named,
# exit status 3.
file(WRITE ${rove_eval_dir}/est_extra.tum
  "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 1 1 0 0 0 0 1\n3 0 1 0 0 0 0 1\n7.5 0 1 0 0 0 0 1\n")
add_test(NAME cli.eval_ate_unassociated COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval ate ${rove_eval_dir}/gt.tum ${rove_eval_dir}/est_extra.tum"
  -DEXIT=3 "-DREGEX=rove: warning: unassociated: 1 of 5 estimate poses have no reference pose within the time tolerance: t = 7\\.500000"
  ${rove_eval_expect})
set_tests_properties(cli.eval_ate_unassociated PROPERTIES LABELS cli)
# Nothing associates: an error with both time ranges.
file(WRITE ${rove_eval_dir}/est_later.tum "100 0 0 0 0 0 0 1\n101 1 0 0 0 0 0 1\n")
add_test(NAME cli.eval_ate_nothing_associates COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval ate ${rove_eval_dir}/gt.tum ${rove_eval_dir}/est_later.tum"
  -DEXIT=1 "-DREGEX=no estimate pose is within 0\\.01 s of a reference pose .reference: 4 poses, t 0\\.000000 \\.\\. 3\\.000000 s; estimate: 2 poses, t 100\\.000000"
  ${rove_eval_expect})
set_tests_properties(cli.eval_ate_nothing_associates PROPERTIES LABELS cli)
# Neither TUM nor KITTI: named with the count of fields.
file(WRITE ${rove_eval_dir}/five.txt "1 2 3 4 5\n")
add_test(NAME cli.eval_unknown_format COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval ate ${rove_eval_dir}/gt.tum ${rove_eval_dir}/five.txt"
  -DEXIT=1 "-DREGEX=five\\.txt.*the first row has 5 fields: not a TUM trajectory" ${rove_eval_expect})
set_tests_properties(cli.eval_unknown_format PROPERTIES LABELS cli)
# A bad row names its line and field.
file(WRITE ${rove_eval_dir}/bad.tum "0 0 0 0 0 0 0 1\n1 1 zero 0 0 0 0 1\n")
add_test(NAME cli.eval_bad_row COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval ate ${rove_eval_dir}/gt.tum ${rove_eval_dir}/bad.tum"
  -DEXIT=1 "-DREGEX=bad\\.tum.*2.*y.*'zero' is not a finite number" ${rove_eval_expect})
set_tests_properties(cli.eval_bad_row PROPERTIES LABELS cli)
# The plot may not overwrite an input.
add_test(NAME cli.eval_plot_over_input COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval ate --plot ${rove_eval_dir}/gt.tum ${rove_eval_dir}/gt.tum ${rove_eval_dir}/est.kitti"
  -DEXIT=1 "-DREGEX=gt\\.tum" -DKEEP=${rove_eval_dir}/gt.tum -DREF=${rove_eval_dir}/gt.tum
  ${rove_eval_expect})
set_tests_properties(cli.eval_plot_over_input PROPERTIES LABELS cli)

# Graph vertices as a trajectory (vertex id as time): the circle's ground
# truth against itself is exact.
set(rove_eval_circle ${PROJECT_SOURCE_DIR}/data/posegraph/graph_2d_circle_50nodes_groundtruth.graph)
add_test(NAME cli.eval_ate_graph_vertices COMMAND rove eval ate ${rove_eval_circle} ${rove_eval_circle})
set_tests_properties(cli.eval_ate_graph_vertices PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "graph \\(2D vertices, id as time\\), 50 poses.*pairs +50 .*translation +rmse 0 ")

# Relations: the square's steps, one 0.05 m off and one at a time the
# estimate does not have.
file(WRITE ${rove_eval_dir}/square.relations
  "0 1 1 0 0 0 0 0\n1 2 0 1.05 0 0 0 0\n2 9 0 0 0 0 0 0\n")
add_test(NAME cli.eval_relations COMMAND ${CMAKE_COMMAND}
  "-DCOMMAND=$<TARGET_FILE:rove> eval relations ${rove_eval_dir}/gt.tum ${rove_eval_dir}/square.relations"
  -DEXIT=3 "-DREGEX=relations +2 used of 3.*translation +0\\.0250 ± 0\\.0250 m.*max 0\\.0500 m.*missing-times: 1 of 3 relations left out: the estimate has no pose within 0\\.001 s of t = 9\\.000000"
  ${rove_eval_expect})
set_tests_properties(cli.eval_relations PROPERTIES LABELS cli)
# Freiburg relations name the FLASER lines' ipc timestamps; --log takes them
# to the logger timestamps rove's trajectories carry.
file(WRITE ${rove_eval_dir}/square.clf
  "FLASER 3 1 1 1 0 0 0 0 0 0 500.25 host 0.0\nFLASER 3 1 1 1 1 0 0 1 0 0 501.25 host 1.0\nFLASER 3 1 1 1 1 1 0 1 1 0 502.25 host 2.0\n")
file(WRITE ${rove_eval_dir}/square_ipc.relations "500.25 501.25 1 0 0 0 0 0\n501.25 502.25 0 1 0 0 0 0\n")
add_test(NAME cli.eval_relations_carmen_clock COMMAND rove eval relations --log ${rove_eval_dir}/square.clf
  ${rove_eval_dir}/gt.tum ${rove_eval_dir}/square_ipc.relations)
set_tests_properties(cli.eval_relations_carmen_clock PROPERTIES LABELS cli
  PASS_REGULAR_EXPRESSION "relations +2 used of 2.*translation +0\\.0000 ± 0\\.0000 m")
