# Run by gistream_add_test_suites (cmake/GTestSuites.cmake) after each build
# of a test binary: lists its tests and writes CTEST_FILE, one add_test per
# suite (or per case for the suites in ISOLATED, comma-separated).
# Inputs: TARGET, EXECUTABLE, CTEST_FILE, TIMEOUT, ISOLATED, RESULTS_DIR.
cmake_minimum_required(VERSION 3.24)

# Test discovery runs the binary: no leak check there (sanitizer builds).
set(ENV{ASAN_OPTIONS} "detect_leaks=0")
execute_process(
  COMMAND "${EXECUTABLE}" --gtest_list_tests
  OUTPUT_VARIABLE listing
  ERROR_VARIABLE errors
  RESULT_VARIABLE result
  TIMEOUT 60)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${TARGET} --gtest_list_tests failed (${result}):\n${errors}\n${listing}")
endif()

string(REPLACE "," ";" isolated "${ISOLATED}")
string(REPLACE ";" "\\;" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")

set(script "")
set(suite "")
set(cases "")
file(MAKE_DIRECTORY "${RESULTS_DIR}")

# Writes the ctest entries of the suite read so far.
macro(flush_suite)
  if(NOT suite STREQUAL "" AND NOT suite MATCHES "^DISABLED_" AND NOT cases STREQUAL "")
    if(suite IN_LIST isolated)
      foreach(one IN LISTS cases)
        set(names "${names};${suite}.${one}")
      endforeach()
    else()
      set(names "${names};${suite}")
    endif()
  endif()
  set(cases "")
endmacro()

set(names "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ #][^ ]*)\\.")
    set(next_suite "${CMAKE_MATCH_1}")  # (flush_suite's MATCHES resets it)
    flush_suite()
    set(suite "${next_suite}")
  elseif(line MATCHES "^  ([^ #]+)")
    set(case "${CMAKE_MATCH_1}")  # (the next MATCHES resets CMAKE_MATCH_1)
    if(NOT case MATCHES "^DISABLED_")
      list(APPEND cases "${case}")
    endif()
  endif()
endforeach()
flush_suite()

foreach(name IN LISTS names)
  if(name STREQUAL "")
    continue()
  endif()
  if(name MATCHES "\\.")
    set(filter "${name}")
  else()
    set(filter "${name}.*")
  endif()
  string(REGEX REPLACE "[^A-Za-z0-9_.-]" "_" xml "${TARGET}.${name}")
  string(APPEND script
         "add_test([==[${TARGET}:${name}]==] [==[${EXECUTABLE}]==] [==[--gtest_filter=${filter}]==] "
         "--gtest_brief=1 [==[--gtest_output=xml:${RESULTS_DIR}/${xml}.xml]==])\n"
         "set_tests_properties([==[${TARGET}:${name}]==] PROPERTIES TIMEOUT ${TIMEOUT} "
         "LABELS ${TARGET})\n")
endforeach()
file(WRITE "${CTEST_FILE}" "${script}")
