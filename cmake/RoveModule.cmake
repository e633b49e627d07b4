# Helpers that give every rove module the same shape:
#   modules/<name>/{include/rove/<name>/, src/, tests/, bench/}
#
# rove_add_module(<name> [DEPS rove::a rove::b ...] [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
#   Builds rove_<name> (alias rove::<name>) from src/*.cpp, installs it and its
#   headers, and, when tests are enabled, builds tests/*.cpp into one GoogleTest
#   executable registered with CTest. A DEPS entry must name a module that comes
#   earlier in ROVE_MODULE_ORDER: dependencies only point down the stack.

set(ROVE_MODULE_ORDER core serialization math poses obs maps io registration bayes graph
    vision slam nav viz ros)

# Tests that read the large shared datasets (not part of a clone): GoogleTest
# suites whose name ends in "Datasets", and the command-line tests passed to
# rove_dataset_tests(). ctest labels them `datasets`. When the folder is
# absent they are registered disabled (ctest lists them as "Disabled"), unless
# the environment sets ROVE_REQUIRE_DATASETS=1 at configure time, as CI does:
# then they run and fail loudly, naming the missing file.
set(ROVE_DATASETS_DIR "${PROJECT_SOURCE_DIR}/../shared/datasets" CACHE PATH
    "Folder of the large shared datasets read by the tests labelled 'datasets'")
get_filename_component(ROVE_DATASETS_DIR "${ROVE_DATASETS_DIR}" ABSOLUTE)
set(ROVE_DATASETS_DISABLED FALSE)
if(NOT IS_DIRECTORY "${ROVE_DATASETS_DIR}" AND NOT "$ENV{ROVE_REQUIRE_DATASETS}" STREQUAL "1")
  set(ROVE_DATASETS_DISABLED TRUE)
  if(ROVE_BUILD_TESTS)
    message(STATUS "rove: ${ROVE_DATASETS_DIR} is absent: the tests labelled 'datasets' are disabled")
  endif()
endif()

# rove_dataset_tests(<test>...): marks command-line tests that read
# ROVE_DATASETS_DIR (label `datasets`, disabled when the folder is absent).
function(rove_dataset_tests)
  foreach(t IN LISTS ARGN)
    set_property(TEST ${t} APPEND PROPERTY LABELS datasets)
    if(ROVE_DATASETS_DISABLED)
      set_property(TEST ${t} PROPERTY DISABLED TRUE)
    endif()
  endforeach()
endfunction()

function(rove_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(ROVE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(ROVE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=${ROVE_SANITIZE}
      -fno-omit-frame-pointer -fno-sanitize-recover=all)
    target_link_options(${target} PRIVATE -fsanitize=${ROVE_SANITIZE})
  endif()
endfunction()

# rove_exact_float_sources(<source>...): the sources that reproduce a peer's
# floating-point arithmetic bit for bit (Arithmetic::Mrpt, NdtCompat::Pcl;
# docs/conventions.md, "MRPT and PCL compatibility") are compiled with
# -ffp-contract=off: no fused multiply-add the source does not spell out,
# whatever -march a user adds, so that their sums round as MRPT's and PCL's
# builds round them. Every other source lets the compiler fuse (the default
# paths need no bit-exact agreement with anything). rove_add_module applies
# it to the files named *_mrpt.cpp / *_pcl.cpp (library) and
# *_mrpt_test.cpp / *_pcl_test.cpp (their parity tests), and to the shared
# sources a module names with EXACT_FLOAT (code both paths run whose float
# results the strategy needs to the bit, such as the float KD-tree search).
function(rove_exact_float_sources)
  foreach(src IN LISTS ARGN)
    if(src MATCHES "_(mrpt|pcl)(_test)?\\.cpp$")
      set_source_files_properties(${src} PROPERTIES COMPILE_OPTIONS -ffp-contract=off)
    endif()
  endforeach()
endfunction()

function(rove_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPS;PUBLIC_LIBS;PRIVATE_LIBS;EXACT_FLOAT" ${ARGN})
  list(FIND ROVE_MODULE_ORDER ${name} self_index)
  if(self_index EQUAL -1)
    message(FATAL_ERROR "rove module '${name}' is not listed in ROVE_MODULE_ORDER")
  endif()
  foreach(dep IN LISTS ARG_DEPS)
    string(REPLACE "rove::" "" dep_name ${dep})
    list(FIND ROVE_MODULE_ORDER ${dep_name} dep_index)
    if(dep_index EQUAL -1 OR NOT dep_index LESS self_index)
      message(FATAL_ERROR "rove::${name} may not depend on ${dep}: dependencies must point "
                          "to modules earlier in: ${ROVE_MODULE_ORDER}")
    endif()
  endforeach()

  set(dir ${CMAKE_CURRENT_SOURCE_DIR})
  file(GLOB_RECURSE srcs CONFIGURE_DEPENDS ${dir}/src/*.cpp)
  add_library(rove_${name} ${srcs})
  rove_exact_float_sources(${srcs})
  foreach(src IN LISTS ARG_EXACT_FLOAT)
    set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/${src} PROPERTIES
      COMPILE_OPTIONS -ffp-contract=off)
  endforeach()
  add_library(rove::${name} ALIAS rove_${name})
  set_target_properties(rove_${name} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(rove_${name} PUBLIC
    $<BUILD_INTERFACE:${dir}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(rove_${name} PUBLIC ${ARG_DEPS} ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  rove_target_defaults(rove_${name})

  install(TARGETS rove_${name} EXPORT roveTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${dir}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

  if(ROVE_BUILD_TESTS)
    file(GLOB_RECURSE test_srcs CONFIGURE_DEPENDS ${dir}/tests/*.cpp)
    if(test_srcs)
      add_executable(rove_${name}_tests ${test_srcs})
      rove_exact_float_sources(${test_srcs})
      target_link_libraries(rove_${name}_tests PRIVATE rove::${name} GTest::gtest GTest::gtest_main)
      target_include_directories(rove_${name}_tests PRIVATE ${dir}/tests
        ${PROJECT_SOURCE_DIR}/modules/core/tests/support)
      target_compile_definitions(rove_${name}_tests PRIVATE
        ROVE_SOURCE_DIR="${PROJECT_SOURCE_DIR}" ROVE_DATASETS_DIR="${ROVE_DATASETS_DIR}")
      rove_target_defaults(rove_${name}_tests)
      gtest_discover_tests(rove_${name}_tests DISCOVERY_MODE PRE_TEST
        WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} PROPERTIES LABELS ${name})
      # A hook ctest runs after the discovery above: the suites that read the
      # shared datasets (name ending in "Datasets") get the label `datasets`;
      # the parity tests against MRPT's or PCL's own outputs, run through
      # the named compatibility strategy (suite name containing "MrptCompat"
      # or "PclCompat"), get the label `mrpt_compat`. Correctness tests
      # (ground truth, properties, oracles) carry neither. Suites ending in
      # "Browser" drive headless Chromium (Debian's chromium, installed by
      # scripts/install-deps): label `browser`; they fail, never skip, when
      # it is missing.
      set(hook ${CMAKE_CURRENT_BINARY_DIR}/rove_${name}_tests_datasets.cmake)
      file(WRITE ${hook}
        "foreach(t IN LISTS rove_${name}_tests_TESTS)\n"
        "  set(labels ${name})\n"
        "  if(t MATCHES \"(Mrpt|Pcl)Compat\")\n"
        "    list(APPEND labels mrpt_compat)\n"
        "  endif()\n"
        "  if(t MATCHES \"Browser\\\\.\")\n"
        "    list(APPEND labels browser)\n"
        "  endif()\n"
        "  if(t MATCHES \"Datasets\\\\.\")\n"
        "    list(APPEND labels datasets)\n"
        "    set_tests_properties(\"\${t}\" PROPERTIES DISABLED ${ROVE_DATASETS_DISABLED})\n"
        "  endif()\n"
        "  set_tests_properties(\"\${t}\" PROPERTIES LABELS \"\${labels}\")\n"
        "endforeach()\n")
      set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${hook})
    endif()
  endif()
endfunction()
