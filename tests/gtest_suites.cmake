# Included by ctest (the tests folder's TEST_INCLUDE_FILES, tests/CMakeLists.txt): one
# ctest per GoogleTest suite of FFD_GTEST_EXECUTABLE, which runs the suite's tests in one
# process (--gtest_filter=<suite>.*), named after the suite. Its output names each test
# that failed. COST is the suite's number of tests, so that with no timing history (a
# fresh machine: CI) ctest starts the larger suites first.
# Set by the file that includes this one: FFD_GTEST_EXECUTABLE, FFD_GTEST_WORKING_DIRECTORY,
# FFD_GTEST_TIMEOUT, FFD_GTEST_ENVIRONMENT (each suite's process's environment).
execute_process(COMMAND "${FFD_GTEST_EXECUTABLE}" --gtest_list_tests
                WORKING_DIRECTORY "${FFD_GTEST_WORKING_DIRECTORY}"
                OUTPUT_VARIABLE listing ERROR_VARIABLE listing_errors RESULT_VARIABLE listing_status
                TIMEOUT 60)
# Not built, or the listing failed: one test that runs the listing and fails with its
# message, rather than a suite of none.
if(NOT listing_status EQUAL 0)
  add_test([=[ffd_tests.listing]=] "${FFD_GTEST_EXECUTABLE}" --gtest_list_tests)
  set_tests_properties([=[ffd_tests.listing]=] PROPERTIES WORKING_DIRECTORY "${FFD_GTEST_WORKING_DIRECTORY}")
  return()
endif()
# A suite's line has no indent and ends with its name's '.', then maybe "  # TypeParam =
# ..."; each of its tests is a line indented by two spaces. Other lines (gtest_main's
# "Running main() from ...") are neither.
string(REPLACE ";" "," listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(suite "")
set(suites "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([A-Za-z0-9_/]+)\\.( .*)?$")
    set(suite "${CMAKE_MATCH_1}")
    list(APPEND suites "${suite}")
    set(count_${suite} 0)
  elseif(suite AND line MATCHES "^  [A-Za-z0-9_/]")
    math(EXPR count_${suite} "${count_${suite}} + 1")
  endif()
endforeach()
foreach(suite IN LISTS suites)
  add_test("${suite}" "${FFD_GTEST_EXECUTABLE}" "--gtest_filter=${suite}.*")
  set_tests_properties("${suite}" PROPERTIES WORKING_DIRECTORY "${FFD_GTEST_WORKING_DIRECTORY}"
                       TIMEOUT "${FFD_GTEST_TIMEOUT}" COST "${count_${suite}}"
                       ENVIRONMENT "${FFD_GTEST_ENVIRONMENT}")
endforeach()
