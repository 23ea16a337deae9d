# One fuzz test (cmake -P; fuzz/CMakeLists.txt):
#   MODE=fuzz    fuzz BIN for SECONDS (-seed=1) from a fresh working corpus
#                WORK, with the committed corpus CORPUS as the seeds (it is
#                read, never written); a crash, a sanitizer report, a leak or
#                a slow input (> 10 s) fails, its input in ARTIFACTS*
#   MODE=corpus  run BIN once on every file of CORPUS (the regression inputs
#                of fixed findings stay fixed)
foreach(v MODE BIN CORPUS)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_fuzz.cmake: ${v} not set")
  endif()
endforeach()
file(GLOB inputs LIST_DIRECTORIES false ${CORPUS}/*)
list(LENGTH inputs n_inputs)
if(n_inputs EQUAL 0)
  message(FATAL_ERROR "no corpus files in ${CORPUS}")
endif()

if(MODE STREQUAL "fuzz")
  file(REMOVE_RECURSE ${WORK})
  file(MAKE_DIRECTORY ${WORK})
  get_filename_component(adir ${ARTIFACTS} DIRECTORY)
  file(MAKE_DIRECTORY ${adir})
  execute_process(COMMAND ${BIN} -max_total_time=${SECONDS} -seed=1 -max_len=8192 -timeout=10
                          -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=${ARTIFACTS}
                          ${WORK} ${CORPUS}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  # libFuzzer reports on stderr: its summary lines and any crash in full
  string(REGEX MATCHALL "(#[0-9]+[ \t]+(INITED|DONE)[^\n]*|stat::[a-z_]+:[^\n]*|Done [0-9]+ runs[^\n]*)"
         summary "${err}")
  string(REPLACE ";" "\n" summary "${summary}")
  message("${summary}")
  if(NOT rc EQUAL 0)
    message("${err}")
    message(FATAL_ERROR "fuzz target ${BIN} failed (exit ${rc}): input saved as ${ARTIFACTS}*")
  endif()
  file(GLOB found LIST_DIRECTORIES false ${WORK}/*)
  list(LENGTH found n_found)
  message("fuzz: ${n_inputs} corpus inputs, ${n_found} new in ${WORK}; no crash")
elseif(MODE STREQUAL "corpus")
  execute_process(COMMAND ${BIN} -timeout=30 ${inputs}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message("${err}")
    message(FATAL_ERROR "a corpus input of ${CORPUS} fails (exit ${rc}) (see above)")
  endif()
  message("corpus: ${n_inputs} inputs of ${CORPUS} run, no crash")
else()
  message(FATAL_ERROR "run_fuzz.cmake: MODE must be fuzz or corpus")
endif()
