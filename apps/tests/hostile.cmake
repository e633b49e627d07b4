# The hostile user (apps/tests/hostile_user.sh): every subcommand on bad input
# must fail with a message naming the culprit, within a memory limit, leaving
# its inputs intact.
if(ROVE_SANITIZE)
  set(rove_hostile_mode --sanitized)
else()
  set(rove_hostile_mode "")
endif()
add_test(NAME cli.hostile_user
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/tests/hostile_user.sh $<TARGET_FILE:rove>
          ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/hostile_user ${rove_hostile_mode})
set_tests_properties(cli.hostile_user PROPERTIES LABELS cli TIMEOUT 900)
