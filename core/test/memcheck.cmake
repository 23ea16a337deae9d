# One memcheck test (cmake -P; core/test/CMakeLists.txt): the unit test
# binary BIN under valgrind's memcheck; an invalid read or write, a use of an
# uninitialised value, a leak (anything allocated) or a failed check fails.
#
# valgrind runs without --track-origins (about a third faster: the origins of
# uninitialised values are only looked up, never needed to find an error);
# when it finds an error the test runs again with --track-origins=yes, whose
# report (where each uninitialised value came from) is printed.
foreach(v VALGRIND BIN)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "memcheck.cmake: ${v} not set")
  endif()
endforeach()
set(args --tool=memcheck --error-exitcode=3 --leak-check=full --errors-for-leak-kinds=all -q)
execute_process(COMMAND ${VALGRIND} ${args} ${BIN}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(rc EQUAL 0 AND NOT err MATCHES "ERROR SUMMARY: [1-9]")
  message("memcheck: no error in ${BIN}")
  return()
endif()
message("${err}")
if(rc EQUAL 3 OR err MATCHES "ERROR SUMMARY: [1-9]")
  message("memcheck found errors (above); again with --track-origins=yes:")
  execute_process(COMMAND ${VALGRIND} ${args} --track-origins=yes ${BIN}
                  OUTPUT_QUIET ERROR_VARIABLE err2)
  message("${err2}")
endif()
message(FATAL_ERROR "memcheck of ${BIN} failed (exit ${rc})")
