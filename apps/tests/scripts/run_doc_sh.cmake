# Runs the ```sh blocks of DOC (a docs/*.md page) with bash, in the empty
# folder WORK where `data` links to the repository's data/, with the folder
# of ROVE (the rove program) first on PATH; prints their output (the test's
# PASS_REGULAR_EXPRESSION checks it) and fails when a command fails.
file(READ "${DOC}" text)
string(REGEX MATCHALL "```sh\n[^`]*```" blocks "${text}")
if(NOT blocks)
  message(FATAL_ERROR "${DOC} has no sh block")
endif()
set(script "set -euo pipefail\n")
foreach(b IN LISTS blocks)
  string(REGEX REPLACE "^```sh\n" "" b "${b}")
  string(REGEX REPLACE "```$" "" b "${b}")
  string(APPEND script "${b}")
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
file(CREATE_LINK "${SOURCE_DIR}/data" "${WORK}/data" SYMBOLIC)
file(WRITE "${WORK}/doc.sh" "${script}")
get_filename_component(bin "${ROVE}" DIRECTORY)
execute_process(COMMAND ${CMAKE_COMMAND} -E env "PATH=${bin}:$ENV{PATH}" bash "${WORK}/doc.sh"
  WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${DOC}'s example failed (exit ${rc}):\n${err}")
endif()
