# Writes the CTest entries of one GoogleTest executable (run by tests/CMakeLists.txt
# after each link, like gtest_discover_tests, whose one-process-per-case layout this
# replaces): one entry per test suite, running the suite's cases in one process
# (--gtest_filter=Suite.*), and one entry per case only for the suites named in
# PER_CASE: cases that change process-wide state (signal handlers, rlimits,
# floating-point traps, death tests) or are heavy enough that ctest -j should spread
# them. A process per case bought nothing else: each test program loads its shared
# libraries again (tests/README.md, "Test registration").
#
#   cmake -D EXE=path -D OUT=file.cmake -D WORKDIR=dir -D TIMEOUT=s
#         -D PER_CASE=Suite1,Suite2 -P gtest_ctest_entries.cmake
cmake_minimum_required(VERSION 3.22)
execute_process(COMMAND "${EXE}" --gtest_list_tests
  OUTPUT_VARIABLE listing ERROR_VARIABLE errors RESULT_VARIABLE rc TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${rc}):\n${listing}\n${errors}")
endif()
string(REPLACE "," ";" perCase "${PER_CASE}")
string(REPLACE ";" "\\;" listing "${listing}")
string(REGEX MATCHALL "[^\n]+" lines "${listing}")

set(script "# Written by tests/gtest_ctest_entries.cmake from ${EXE} --gtest_list_tests.\n")
set(suite "")
set(nEntries 0)
macro(rosy_entry name filter skip)
  string(APPEND script "add_test([==[${name}]==] [==[${EXE}]==] [==[--gtest_filter=${filter}]==])\n"
    "set_tests_properties([==[${name}]==] PROPERTIES WORKING_DIRECTORY [==[${WORKDIR}]==] TIMEOUT ${TIMEOUT}")
  if(${skip})
    # Only for a single case: in a group a skipped case must not hide a failed one.
    string(APPEND script " SKIP_REGULAR_EXPRESSION [==[\\[  SKIPPED \\]]==]")
  endif()
  string(APPEND script ")\n")
  math(EXPR nEntries "${nEntries} + 1")
endmacro()
macro(rosy_flush_suite)
  if(NOT suite STREQUAL "" AND NOT suite MATCHES "^DISABLED_" AND NOT suite IN_LIST perCase)
    rosy_entry("${suite}.*" "${suite}.*" FALSE)
  endif()
endmacro()
foreach(line IN LISTS lines)
  string(REGEX REPLACE " *#.*$" "" line "${line}")
  if(line MATCHES "^([^ ].*)\\.$")
    set(nextSuite "${CMAKE_MATCH_1}") # before rosy_flush_suite(), whose MATCHES resets CMAKE_MATCH_1
    rosy_flush_suite()
    set(suite "${nextSuite}")
  elseif(line MATCHES "^  +([^ ]+)$" AND NOT suite STREQUAL "")
    set(case "${CMAKE_MATCH_1}")
    # A suite's short name for PER_CASE: "Quality/ExampleScene" or "ExampleScene".
    string(REGEX REPLACE "^.*/" "" shortSuite "${suite}")
    if((suite IN_LIST perCase OR shortSuite IN_LIST perCase) AND NOT case MATCHES "^DISABLED_")
      list(APPEND perCase "${suite}")
      rosy_entry("${suite}.${case}" "${suite}.${case}" TRUE)
    endif()
  endif()
endforeach()
rosy_flush_suite()
if(nEntries EQUAL 0)
  message(FATAL_ERROR "${EXE} lists no test")
endif()
file(WRITE "${OUT}" "${script}")
