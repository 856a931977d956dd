# Registers one ctest test per GoogleTest suite of a test executable (run after it is built; see
# lacet_add_suites in tests/CMakeLists.txt): `ctest -R Suite` runs `EXE --gtest_filter=Suite.*`.
# A test process starts GDAL, OpenImageIO, TBB and, in the sanitized build, AddressSanitizer (about
# 0.4 s, 1.4 s sanitized): one process per suite rather than per test saves most of that.
#   cmake -D EXECUTABLE=... -D OUTPUT=... -D TIMEOUT=seconds [-D COST=n] -P list_suites.cmake
cmake_policy(SET CMP0057 NEW)  # if(IN_LIST)
execute_process(COMMAND "${EXECUTABLE}" --gtest_list_tests
                OUTPUT_VARIABLE listing ERROR_VARIABLE listing_error RESULT_VARIABLE code TIMEOUT 120)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE} --gtest_list_tests failed (${code}): ${listing_error}")
endif()
string(REPLACE "\n" ";" lines "${listing}")
# The suites that take longest (over 60 s each under the sanitizers in CI, 2026-12-07): started
# first under ctest -j, so that they do not run alone at the end (a clean clone has no ctest cost
# data). A suite missing from the list only starts in its turn.
set(long_suites LazyForestTest LazyForestEditTest LazySaveTest Incremental PyramidBuild SplineFit SceneRegion)
set(script "")
set(suites 0)
foreach(line IN LISTS lines)
  # A suite's line is its name and a dot at the start (a parameterized one: Prefix/Suite.); a test's is indented.
  if(line MATCHES "^([A-Za-z_][A-Za-z0-9_/]*)\\.")
    set(suite "${CMAKE_MATCH_1}")
    string(APPEND script "add_test([=[${suite}]=] [=[${EXECUTABLE}]=] [=[--gtest_filter=${suite}.*]=])\n")
    string(APPEND script "set_tests_properties([=[${suite}]=] PROPERTIES TIMEOUT ${TIMEOUT}")
    if(suite IN_LIST long_suites)
      string(APPEND script " COST 500")
    elseif(DEFINED COST)
      string(APPEND script " COST ${COST}")
    endif()
    string(APPEND script ")\n")
    math(EXPR suites "${suites} + 1")
  endif()
endforeach()
if(suites EQUAL 0)
  message(FATAL_ERROR "${EXECUTABLE} lists no test suite")
endif()
file(WRITE "${OUTPUT}" "${script}")
