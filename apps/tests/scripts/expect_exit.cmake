# Run by the command-line tests as `cmake -DCOMMAND=... -DEXIT=N -DREGEX=... -P`:
# COMMAND must exit with EXIT and print REGEX on stdout+stderr. Optional:
#   FILE + FILE_REGEX  the content of FILE must match FILE_REGEX;
#   KEEP + REF         KEEP must still equal REF (an input left intact);
#   ABSENT             this file must not have been written.
separate_arguments(cmd UNIX_COMMAND "${COMMAND}")
execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL "${EXIT}")
  message(FATAL_ERROR "expected exit code ${EXIT}, got ${rc}:\n${out}${err}")
endif()
if(NOT "${out}${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "output does not match '${REGEX}':\n${out}${err}")
endif()
if(DEFINED FILE)
  file(READ "${FILE}" text)
  if(NOT text MATCHES "${FILE_REGEX}")
    message(FATAL_ERROR "${FILE} does not match '${FILE_REGEX}':\n${text}")
  endif()
endif()
if(DEFINED KEEP)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${KEEP}" "${REF}" RESULT_VARIABLE diff)
  if(NOT diff EQUAL 0)
    message(FATAL_ERROR "${KEEP} was changed")
  endif()
endif()
if(DEFINED ABSENT AND EXISTS "${ABSENT}")
  message(FATAL_ERROR "${ABSENT} was written")
endif()
