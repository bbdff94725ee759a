# gistream_add_test_suites(<target> [TIMEOUT <s>] [ISOLATED <suite>...])
#
# Registers a GoogleTest binary with ctest as one test per suite (not one
# per case, as gtest_discover_tests does): the cases of a suite share one
# process, so a fixture rendered once per binary (a path-traced reference,
# the shared engine, shaders compiled on first use) is made once, not once
# per case. ctest -j still runs suites side by side.
#
# Each suite writes its GoogleTest XML to <build>/test-results/ (per-case
# times, recorded measurements); scripts/test_times.py prints the slowest.
# Suites named in ISOLATED keep a process per case (state that must not
# leak between cases). The suites are listed after each build by running
# the binary with --gtest_list_tests (cmake/GTestSuitesDiscover.cmake).
set(GISTREAM_GTEST_DISCOVER_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/GTestSuitesDiscover.cmake)

function(gistream_add_test_suites target)
  cmake_parse_arguments(A "" "TIMEOUT" "ISOLATED" ${ARGN})
  if(NOT A_TIMEOUT)
    set(A_TIMEOUT 600)
  endif()
  set(ctest_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake)
  set(include_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_suites_include.cmake)
  string(REPLACE ";" "," isolated "${A_ISOLATED}")
  add_custom_command(
    TARGET ${target} POST_BUILD
    BYPRODUCTS ${ctest_file}
    COMMAND ${CMAKE_COMMAND} -DTARGET=${target} -DEXECUTABLE=$<TARGET_FILE:${target}>
            -DCTEST_FILE=${ctest_file} -DTIMEOUT=${A_TIMEOUT} -DISOLATED=${isolated}
            -DRESULTS_DIR=${PROJECT_BINARY_DIR}/test-results
            -P ${GISTREAM_GTEST_DISCOVER_SCRIPT}
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
    VERBATIM)
  file(WRITE ${include_file}
       "if(EXISTS \"${ctest_file}\")\n"
       "  include(\"${ctest_file}\")\n"
       "else()\n"
       "  add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)\n"
       "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${include_file})
endfunction()
