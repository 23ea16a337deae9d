# Firmware checks of the real-time core, run by ctest as `cmake -P`.
#   -DMODE=compile : cross-compile every core/src/*.c for a Cortex-M4F with -Werror
#   -DMODE=symbols : cross-compile, then check the objects with arm-none-eabi-nm
#                    (no heap, no stdio, no double soft-float, no writable
#                    globals) and print the arm-none-eabi-size totals
# A missing cross toolchain is a failure, not a skip (the Makefile installs it).

foreach(v MODE SRC_DIR INC_DIR OUT_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "firmware_check.cmake: ${v} not given")
  endif()
endforeach()

find_program(ARM_GCC arm-none-eabi-gcc PATHS /usr/bin NO_CACHE)
find_program(ARM_NM arm-none-eabi-nm PATHS /usr/bin NO_CACHE)
find_program(ARM_SIZE arm-none-eabi-size PATHS /usr/bin NO_CACHE)
foreach(tool ARM_GCC ARM_NM ARM_SIZE)
  if(NOT ${tool})
    message(FATAL_ERROR "FAIL: ${tool} (arm-none-eabi toolchain) not found; "
                        "install gcc-arm-none-eabi (make toolchain)")
  endif()
endforeach()

set(FW_FLAGS -std=c99 -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -O2
             -Wall -Wextra -Wdouble-promotion -Werror)

file(GLOB SOURCES ${SRC_DIR}/*.c)
list(SORT SOURCES)
list(LENGTH SOURCES n_sources)
if(n_sources EQUAL 0)
  message(FATAL_ERROR "FAIL: no sources in ${SRC_DIR}")
endif()
file(REMOVE_RECURSE ${OUT_DIR})
file(MAKE_DIRECTORY ${OUT_DIR})

set(OBJECTS)
set(n_fail 0)
foreach(src ${SOURCES})
  get_filename_component(name ${src} NAME_WE)
  set(obj ${OUT_DIR}/${name}.o)
  execute_process(COMMAND ${ARM_GCC} ${FW_FLAGS} -I${INC_DIR} -c ${src} -o ${obj}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message("FAIL compile ${name}.c:\n${out}${err}")
    math(EXPR n_fail "${n_fail} + 1")
  else()
    message("ok   compile ${name}.c")
    list(APPEND OBJECTS ${obj})
  endif()
endforeach()
if(n_fail GREATER 0)
  message(FATAL_ERROR "${n_fail} of ${n_sources} core sources failed to cross-compile")
endif()
message("all ${n_sources} core sources cross-compile for cortex-m4 (fpv4-sp-d16, hard float)")

if(MODE STREQUAL "compile")
  return()
endif()

# Undefined references that a firmware core must not have.
set(FORBIDDEN_UNDEF
    "^(malloc|calloc|realloc|free|aligned_alloc|_malloc_r|_free_r|_calloc_r|_realloc_r)$"
    "^(printf|puts|putchar|fprintf|sprintf|snprintf|vprintf|vfprintf|vsprintf|vsnprintf|_printf_r|_sprintf_r|_vfprintf_r)$"
    "^(fputs|fputc|fwrite|fread|fopen|fclose|fflush|scanf|sscanf|fscanf|getchar|perror|_impure_ptr|__sfputs_r|__swbuf_r|__srget_r)$"
    "^__aeabi_d"           # double-precision soft-float helpers
    "^__aeabi_(f|i|ui|l|ul)2d$" # conversions to double
    "^(sin|cos|tan|sqrt|atan2|atan|exp|log|floor|ceil|fabs|pow|fmod)$") # double libm

set(n_bad 0)
foreach(obj ${OBJECTS})
  get_filename_component(name ${obj} NAME)
  execute_process(COMMAND ${ARM_NM} ${obj} RESULT_VARIABLE rc OUTPUT_VARIABLE nm_out
                  ERROR_VARIABLE nm_err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "FAIL: arm-none-eabi-nm ${name}: ${nm_err}")
  endif()
  string(REPLACE "\n" ";" lines "${nm_out}")
  set(undef_list)
  foreach(line ${lines})
    if(line MATCHES "^[ \t]*U[ \t]+([^ \t]+)$")
      set(sym ${CMAKE_MATCH_1})
      list(APPEND undef_list ${sym})
      foreach(re ${FORBIDDEN_UNDEF})
        if(sym MATCHES "${re}")
          message("FAIL ${name}: forbidden undefined reference ${sym}")
          math(EXPR n_bad "${n_bad} + 1")
        endif()
      endforeach()
    elseif(line MATCHES "^[0-9a-fA-F]+[ \t]+([DdBbCGgSsV])[ \t]+([^ \t]+)$")
      # D/d initialised data, B/b bss, C common, G/g S/s small data, V weak object
      message("FAIL ${name}: writable global/static ${CMAKE_MATCH_2} (nm type ${CMAKE_MATCH_1})")
      math(EXPR n_bad "${n_bad} + 1")
    endif()
  endforeach()
  message("     ${name}: undefined symbols: ${undef_list}")
endforeach()

execute_process(COMMAND ${ARM_SIZE} -t ${OBJECTS} RESULT_VARIABLE rc OUTPUT_VARIABLE size_out
                ERROR_VARIABLE size_err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "FAIL: arm-none-eabi-size: ${size_err}")
endif()
message("arm-none-eabi-size -t (Cortex-M4F, -O2):\n${size_out}")
# The TOTALS line must show data = 0 and bss = 0 as well.
if(size_out MATCHES "\n[ \t]*([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)[ \t]+[0-9]+[ \t]+[0-9a-fA-F]+[ \t]+\\(TOTALS\\)")
  set(text ${CMAKE_MATCH_1})
  set(data ${CMAKE_MATCH_2})
  set(bss ${CMAKE_MATCH_3})
  message("totals: text ${text} B, data ${data} B, bss ${bss} B")
  if(NOT data EQUAL 0 OR NOT bss EQUAL 0)
    message("FAIL: the core has ${data} B of .data and ${bss} B of .bss")
    math(EXPR n_bad "${n_bad} + 1")
  endif()
else()
  message("FAIL: could not parse the TOTALS line of arm-none-eabi-size")
  math(EXPR n_bad "${n_bad} + 1")
endif()

if(n_bad GREATER 0)
  message(FATAL_ERROR "${n_bad} firmware symbol check(s) failed")
endif()
message("firmware symbol checks passed: no heap, no stdio, no double soft-float or double libm, "
        "no writable globals")
