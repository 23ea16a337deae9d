# Static analysis of the core with cppcheck (cmake -P; core/test/CMakeLists.txt):
#   MODE=warning  cppcheck --enable=warning over core/src (the headers of
#                 core/include through them): any finding fails
#   MODE=misra    the MISRA C:2012 addon over the same: the findings are
#                 counted and listed by rule (reported, not failing); the
#                 full list goes to OUT
# The configuration with SMD_MATH_HEADER defined is not checked: it names a
# firmware's own header (CMSIS-DSP, ...), which is not here.
foreach(v MODE CPPCHECK SRC_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "cppcheck.cmake: ${v} not set")
  endif()
endforeach()
set(args --std=c99 --inline-suppr -USMD_MATH_HEADER -I ${SRC_DIR}/core/include
         ${SRC_DIR}/core/src)

if(MODE STREQUAL "warning")
  execute_process(COMMAND ${CPPCHECK} --enable=warning --error-exitcode=1 -q ${args}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message("${out}${err}")
    message(FATAL_ERROR "cppcheck --enable=warning: findings in core/ (exit ${rc})")
  endif()
  message("cppcheck --enable=warning over core/: no findings")
elseif(MODE STREQUAL "misra")
  execute_process(COMMAND ${CPPCHECK} --addon=misra -q ${args}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message("${out}${err}")
    message(FATAL_ERROR "cppcheck --addon=misra did not run (exit ${rc})")
  endif()
  if(DEFINED OUT)
    file(WRITE ${OUT} "${err}")
  endif()
  string(REGEX MATCHALL "misra-c2012-[0-9]+\\.[0-9]+" hits "${err}")
  list(LENGTH hits total)
  set(rules ${hits})
  list(REMOVE_DUPLICATES rules)
  list(SORT rules COMPARE NATURAL)
  set(table "")
  foreach(r ${rules})
    set(n 0)
    foreach(h ${hits})
      if(h STREQUAL r)
        math(EXPR n "${n} + 1")
      endif()
    endforeach()
    string(REPLACE "misra-c2012-" "" rr "${r}")
    string(APPEND table "  rule ${rr}: ${n}\n")
  endforeach()
  list(LENGTH rules nrules)
  message("MISRA C:2012 (cppcheck misra addon) over core/: ${total} findings, ${nrules} rules\n${table}"
          "(reported, not required to be zero; the list: ${OUT})")
else()
  message(FATAL_ERROR "cppcheck.cmake: MODE must be warning or misra")
endif()
