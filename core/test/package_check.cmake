# The core as a library for firmware, run by ctest as `cmake -P`.
#   -DMODE=consumers : install the core (static library, headers, CMake package,
#                      pkg-config file) from a fresh build of the tree into a
#                      scratch prefix, then build and run the consumer
#                      (core/test/consumer) three ways: find_package (C++,
#                      main.cpp: the extern "C" guards), pkg-config's flags
#                      alone (C, main.c), add_subdirectory of the source tree
#                      (no host target built)
#   -DMODE=cross     : the core alone for a Cortex-M4F with the toolchain file
#                      cmake/arm-none-eabi-cortex-m4f.cmake: the static library
#                      (its ARM attributes, its size), installed, and the C
#                      consumer cross-built against it through find_package;
#                      the core compiled with the math hooks mapped
#                      (consumer/fw_math_hooks.h) calls no float libm function
# Every step is printed; any failure is a FATAL_ERROR (nothing is skipped: a
# missing pkg-config is replaced by reading the .pc file here, a missing cross
# toolchain fails).

cmake_minimum_required(VERSION 3.18)

foreach(v MODE SRC_DIR OUT_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "package_check.cmake: ${v} not given")
  endif()
endforeach()

# The nested builds are builds of their own, not jobs of the make that runs ctest.
foreach(e MAKEFLAGS MFLAGS MAKELEVEL)
  unset(ENV{${e}})
endforeach()

set(CONSUMER_DIR ${SRC_DIR}/core/test/consumer)
set(TOOLCHAIN ${SRC_DIR}/cmake/arm-none-eabi-cortex-m4f.cmake)
set(GEN_ARGS)
if(GENERATOR)
  set(GEN_ARGS -G ${GENERATOR})
endif()
file(REMOVE_RECURSE ${OUT_DIR})
file(MAKE_DIRECTORY ${OUT_DIR})

# Run a command; print it and, on failure, its output, and stop.
function(run what)
  string(REPLACE ";" " " line "${ARGN}")
  message("---- ${what}\n     $ ${line}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "FAIL: ${what} (exit ${rc})\n${out}${err}")
  endif()
  string(STRIP "${out}" out)
  set(RUN_OUT "${out}" PARENT_SCOPE)
endfunction()

function(expect_files what)
  foreach(f ${ARGN})
    if(NOT EXISTS ${f})
      message(FATAL_ERROR "FAIL: ${what}: ${f} missing")
    endif()
  endforeach()
endfunction()

# No file under dir whose path matches one of the regular expressions.
function(expect_none what dir)
  file(GLOB_RECURSE all LIST_DIRECTORIES false ${dir}/*)
  set(found)
  foreach(re ${ARGN})
    set(hits ${all})
    list(FILTER hits INCLUDE REGEX "${re}")
    list(APPEND found ${hits})
  endforeach()
  if(found)
    message(FATAL_ERROR "FAIL: ${what}: ${found}")
  endif()
  message("ok   ${what}")
endfunction()

function(expect_cache build var value)
  file(STRINGS ${build}/CMakeCache.txt line REGEX "^${var}:[A-Z]+=")
  if(NOT line MATCHES "=${value}$")
    message(FATAL_ERROR "FAIL: ${build}: ${var} is '${line}', expected ${value}")
  endif()
  message("ok   ${var}=${value} in ${build}")
endfunction()

file(GLOB CORE_SOURCES ${SRC_DIR}/core/src/*.c)
file(GLOB CORE_HEADERS RELATIVE ${SRC_DIR}/core/include/smodrive ${SRC_DIR}/core/include/smodrive/*.h)
list(LENGTH CORE_SOURCES n_sources)

# Configure, build and install the core alone from a fresh build of the tree.
# Extra arguments go to the configure step.
function(install_core build prefix)
  run("configure the core (${build})" ${CMAKE_COMMAND} ${GEN_ARGS} -S ${SRC_DIR} -B ${build}
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=${prefix}
      -DSMD_BUILD_TESTS=OFF -DSMD_BUILD_PYLIB=OFF -DSMD_BUILD_SIM=OFF ${ARGN})
  run("build the core" ${CMAKE_COMMAND} --build ${build} --parallel 4)
  run("install the core into ${prefix}" ${CMAKE_COMMAND} --install ${build})
  file(GLOB_RECURSE libs ${prefix}/libsmodrive_core.a)
  file(GLOB_RECURSE cfg ${prefix}/smodriveConfig.cmake)
  file(GLOB_RECURSE cfgv ${prefix}/smodriveConfigVersion.cmake)
  file(GLOB_RECURSE tgt ${prefix}/smodriveTargets.cmake)
  file(GLOB_RECURSE pc ${prefix}/smodrive.pc)
  foreach(x libs cfg cfgv tgt pc)
    list(LENGTH ${x} n)
    if(NOT n EQUAL 1)
      message(FATAL_ERROR "FAIL: install: ${x} found ${n} times under ${prefix}: ${${x}}")
    endif()
  endforeach()
  foreach(h ${CORE_HEADERS})
    expect_files("install: header" ${prefix}/include/smodrive/${h})
  endforeach()
  expect_none("install: no host library, no simulator header" ${prefix}
              "/libsmodrive\\.so" "/smd_engine\\.h$" "/smd_plant\\.h$")
  list(LENGTH CORE_HEADERS n_headers)
  message("ok   installed: ${libs}, ${n_headers} headers in ${prefix}/include/smodrive, "
          "${cfg}, ${cfgv}, ${tgt}, ${pc}")
  set(CORE_LIB ${libs} PARENT_SCOPE)
  set(CORE_PC ${pc} PARENT_SCOPE)
endfunction()

# --------------------------------------------------------------- consumers --
if(MODE STREQUAL "consumers")
  if(NOT C_COMPILER)
    message(FATAL_ERROR "package_check.cmake: C_COMPILER not given")
  endif()
  set(prefix ${OUT_DIR}/prefix)
  install_core(${OUT_DIR}/core ${prefix} -DCMAKE_C_COMPILER=${C_COMPILER})

  # 1. find_package(smodrive CONFIG REQUIRED), C++ consumer
  set(b ${OUT_DIR}/find_package)
  run("configure the C++ consumer with find_package" ${CMAKE_COMMAND} ${GEN_ARGS}
      -S ${CONSUMER_DIR} -B ${b} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
  run("build the C++ consumer" ${CMAKE_COMMAND} --build ${b})
  run("run the C++ consumer" ${b}/consumer)
  message("     ${RUN_OUT}")

  # 2. pkg-config: a plain C file compiled with its flags and nothing else
  get_filename_component(pcdir ${CORE_PC} DIRECTORY)
  file(STRINGS ${CORE_PC} pc_lines)
  set(pc_vars)
  foreach(line ${pc_lines})
    if(line MATCHES "^([A-Za-z_][A-Za-z0-9_.]*)=(.*)$")
      set(pcv_${CMAKE_MATCH_1} "${CMAKE_MATCH_2}")
      list(APPEND pc_vars ${CMAKE_MATCH_1})
    elseif(line MATCHES "^(Cflags|Libs):(.*)$")
      set(pcf_${CMAKE_MATCH_1} "${CMAKE_MATCH_2}")
    endif()
  endforeach()
  set(pcv_pcfiledir ${pcdir})
  foreach(f Cflags Libs)
    if(NOT DEFINED pcf_${f})
      message(FATAL_ERROR "FAIL: ${CORE_PC} has no ${f}: line")
    endif()
    set(val "${pcf_${f}}")
    foreach(guard RANGE 20)
      if(NOT val MATCHES "\\$\\{([A-Za-z_][A-Za-z0-9_.]*)\\}")
        break()
      endif()
      set(name ${CMAKE_MATCH_1})
      if(NOT DEFINED pcv_${name})
        message(FATAL_ERROR "FAIL: ${CORE_PC}: \${${name}} not defined")
      endif()
      string(REPLACE "\${${name}}" "${pcv_${name}}" val "${val}")
    endforeach()
    string(STRIP "${val}" val)
    set(parsed_${f} "${val}")
  endforeach()
  separate_arguments(parsed UNIX_COMMAND "${parsed_Cflags} ${parsed_Libs}")
  string(REPLACE ";" " " shown "${parsed}")
  message("     ${CORE_PC}, read here: ${shown}")
  find_program(PKG_CONFIG pkg-config NO_CACHE)
  if(PKG_CONFIG AND NOT NO_PKG_CONFIG) # NO_PKG_CONFIG: try the fallback
    set(ENV{PKG_CONFIG_PATH} ${pcdir})
    run("pkg-config --cflags --libs smodrive (PKG_CONFIG_PATH=${pcdir})"
        ${PKG_CONFIG} --cflags --libs smodrive)
    string(STRIP "${RUN_OUT}" pc_out)
    separate_arguments(pc_flags UNIX_COMMAND "${pc_out}")
    message("     ${pc_out}")
    set(a ${pc_flags})
    set(b_ ${parsed})
    list(SORT a)
    list(SORT b_)
    if(NOT a STREQUAL b_)
      message(FATAL_ERROR "FAIL: pkg-config gives '${pc_flags}', the .pc file read here '${parsed}'")
    endif()
    set(flags ${pc_flags})
  else()
    message("     pkg-config not found (or NO_PKG_CONFIG): the flags read from ${CORE_PC} here")
    set(flags ${parsed})
  endif()
  set(exe ${OUT_DIR}/pkgconfig_consumer)
  # flags of the .pc file only, besides the language and the warnings
  run("compile the C consumer with the pkg-config flags only" ${C_COMPILER} -std=c99 -Wall
      -Wextra -pedantic -Werror ${CONSUMER_DIR}/main.c -o ${exe} ${flags})
  run("run the C consumer" ${exe})
  message("     ${RUN_OUT}")

  # 3. add_subdirectory of the source tree: no host target configured or built
  set(b ${OUT_DIR}/add_subdirectory)
  run("configure the C++ consumer with add_subdirectory(${SRC_DIR})" ${CMAKE_COMMAND} ${GEN_ARGS}
      -S ${CONSUMER_DIR} -B ${b} -DCMAKE_BUILD_TYPE=Release -DSMODRIVE_SOURCE_DIR=${SRC_DIR}
      -DCMAKE_C_COMPILER=${C_COMPILER})
  expect_cache(${b} SMD_BUILD_PYLIB OFF)
  expect_cache(${b} SMD_BUILD_SIM OFF)
  expect_cache(${b} SMD_INSTALL OFF)
  run("build the consumer" ${CMAKE_COMMAND} --build ${b} --parallel 4)
  run("run the consumer" ${b}/consumer)
  message("     ${RUN_OUT}")
  expect_files("add_subdirectory: the static library" ${b}/smodrive/libsmodrive_core.a)
  expect_none("add_subdirectory: no libsmodrive.so, no simulator or host-core objects built" ${b}
              "/libsmodrive\\.so" "/smd_sim\\.dir/.*\\.o(bj)?$" "/smd_core_f\\.dir/.*\\.o(bj)?$")
  message("package checks passed: install + find_package (C++), pkg-config (C), add_subdirectory")
  return()
endif()

# ------------------------------------------------------------------- cross --
if(MODE STREQUAL "cross")
  find_program(ARM_GCC arm-none-eabi-gcc PATHS /usr/bin NO_CACHE)
  find_program(ARM_READELF arm-none-eabi-readelf PATHS /usr/bin NO_CACHE)
  find_program(ARM_SIZE arm-none-eabi-size PATHS /usr/bin NO_CACHE)
  foreach(tool ARM_GCC ARM_READELF ARM_SIZE)
    if(NOT ${tool})
      message(FATAL_ERROR "FAIL: ${tool} (arm-none-eabi toolchain) not found; "
                          "install gcc-arm-none-eabi (make toolchain)")
    endif()
  endforeach()
  get_filename_component(bindir ${ARM_GCC} DIRECTORY)
  set(prefix ${OUT_DIR}/prefix)
  set(b ${OUT_DIR}/core)
  # SMD_BUILD_PYLIB and SMD_BUILD_SIM are left to their defaults: OFF when cross-compiling
  run("configure the core for the Cortex-M4F (${TOOLCHAIN})" ${CMAKE_COMMAND} ${GEN_ARGS}
      -S ${SRC_DIR} -B ${b} -DCMAKE_TOOLCHAIN_FILE=${TOOLCHAIN}
      -DARM_NONE_EABI_PREFIX=${bindir}/arm-none-eabi- -DCMAKE_BUILD_TYPE=Release
      -DCMAKE_INSTALL_PREFIX=${prefix})
  expect_cache(${b} SMD_BUILD_PYLIB OFF)
  expect_cache(${b} SMD_BUILD_SIM OFF)
  run("build" ${CMAKE_COMMAND} --build ${b} --parallel 4)
  set(lib ${b}/libsmodrive_core.a)
  expect_files("cross build" ${lib})
  expect_none("cross build: no host library, no simulator objects" ${b}
              "/libsmodrive\\.so" "/smd_sim\\.dir/.*\\.o(bj)?$")

  run("ARM attributes of the archive" ${ARM_READELF} -A ${lib})
  set(attrs "${RUN_OUT}")
  string(REGEX MATCHALL "File: [^\n]*" members "${attrs}")
  list(LENGTH members n_members)
  if(NOT n_members EQUAL n_sources)
    message(FATAL_ERROR "FAIL: ${n_members} objects in ${lib}, ${n_sources} core sources")
  endif()
  foreach(tag "Tag_CPU_name: \"7E-M\"" "Tag_FP_arch: VFPv4-D16" "Tag_ABI_VFP_args: VFP registers"
              "Tag_ABI_HardFP_use: SP only")
    string(REGEX MATCHALL "${tag}" hits "${attrs}")
    list(LENGTH hits n)
    if(NOT n EQUAL n_members)
      message(FATAL_ERROR "FAIL: ${tag} in ${n} of ${n_members} objects of ${lib}\n${attrs}")
    endif()
    message("ok   ${tag} (every object)")
  endforeach()
  run("size" ${ARM_SIZE} -t ${lib})
  if(RUN_OUT MATCHES "\n[ \t]*([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)[ \t]+[0-9]+[ \t]+[0-9a-fA-F]+[ \t]+\\(TOTALS\\)")
    message("     libsmodrive_core.a (Cortex-M4F, Release): text ${CMAKE_MATCH_1} B, "
            "data ${CMAKE_MATCH_2} B, bss ${CMAKE_MATCH_3} B in ${n_members} objects")
  else()
    message(FATAL_ERROR "FAIL: could not parse the TOTALS line of arm-none-eabi-size:\n${RUN_OUT}")
  endif()

  # The math hooks: every core source compiled with all eight mapped to the
  # functions of fw_math_hooks.h calls those and no float libm function.
  find_program(ARM_NM arm-none-eabi-nm PATHS /usr/bin NO_CACHE)
  if(NOT ARM_NM)
    message(FATAL_ERROR "FAIL: arm-none-eabi-nm not found")
  endif()
  set(hooks)
  set(hook_defs "-DSMD_MATH_HEADER=\"fw_math_hooks.h\"")
  foreach(f sin cos sqrt atan2 fabs exp expm1 floor)
    string(TOUPPER ${f} F)
    list(APPEND hook_defs -DSMD_${F}F=fw_${f}f)
    list(APPEND hooks fw_${f}f)
  endforeach()
  set(hdir ${OUT_DIR}/hooks)
  file(MAKE_DIRECTORY ${hdir})
  set(called)
  message("---- the core with the math hooks mapped: ${hook_defs}")
  foreach(src ${CORE_SOURCES})
    get_filename_component(name ${src} NAME_WE)
    # a source on the hooks includes a header built on smd_types.h (every
    # one but a math implementation's own, smd_fmath.h, which may call libm)
    file(STRINGS ${src} incs REGEX "^#include \"smodrive/")
    list(FILTER incs EXCLUDE REGEX "smd_fmath\\.h")
    if(NOT incs)
      message("     ${name}.c: not on the hooks (no header built on smd_types.h)")
      continue()
    endif()
    execute_process(COMMAND ${ARM_GCC} -std=c99 -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16
                            -mfloat-abi=hard -O2 -Wall -Wextra -Wdouble-promotion -Werror
                            ${hook_defs} -I${SRC_DIR}/core/include -I${CONSUMER_DIR}
                            -c ${src} -o ${hdir}/${name}.o
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "FAIL: ${name}.c with the math hooks:\n${out}${err}")
    endif()
    run("undefined symbols of ${name}.o" ${ARM_NM} -u ${hdir}/${name}.o)
    string(REGEX MATCHALL "[A-Za-z_][A-Za-z0-9_]*" undef "${RUN_OUT}")
    foreach(sym ${undef})
      if(sym MATCHES "^(sinf|cosf|sqrtf|atan2f|fabsf|expf|expm1f|floorf)$")
        message(FATAL_ERROR "FAIL: ${name}.o calls ${sym} although SMD_..F is mapped")
      endif()
      if(sym MATCHES "^fw_")
        list(APPEND called ${sym})
      endif()
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES called)
  list(SORT called)
  # the hooks the core calls (fabsf and sqrtf may be inlined by the
  # compiler only when they are the builtins: mapped, they are calls)
  foreach(h fw_sinf fw_cosf fw_sqrtf fw_atan2f fw_fabsf fw_expm1f fw_floorf)
    if(NOT h IN_LIST called)
      message(FATAL_ERROR "FAIL: no core object calls the hook ${h} (called: ${called})")
    endif()
  endforeach()
  message("ok   math hooks: the core calls ${called} and no float libm function")

  run("install into ${prefix}" ${CMAKE_COMMAND} --install ${b})
  expect_files("cross install" ${prefix}/include/smodrive/smd_drive.h)
  # a firmware executable through find_package: newlib's stubs stand in for
  # the startup code and linker script of a real board
  set(c ${OUT_DIR}/consumer)
  run("cross-configure the C consumer with find_package" ${CMAKE_COMMAND} ${GEN_ARGS}
      -S ${CONSUMER_DIR} -B ${c} -DCONSUMER_LANG=C -DCMAKE_TOOLCHAIN_FILE=${TOOLCHAIN}
      -DARM_NONE_EABI_PREFIX=${bindir}/arm-none-eabi- -DCMAKE_BUILD_TYPE=Release
      -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_EXE_LINKER_FLAGS=--specs=nosys.specs)
  run("cross-build (link) the C consumer" ${CMAKE_COMMAND} --build ${c})
  run("size of the consumer" ${ARM_SIZE} ${c}/consumer)
  message("${RUN_OUT}")
  message("cross checks passed: libsmodrive_core.a for cortex-m4 (fpv4-sp-d16, hard float), "
          "installed, linked into a firmware executable through find_package")
  return()
endif()

message(FATAL_ERROR "package_check.cmake: unknown MODE ${MODE}")
