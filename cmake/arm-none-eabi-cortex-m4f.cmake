# CMake toolchain file: bare-metal Cortex-M4F (FPv4-SP-D16, hard-float ABI)
# with the GNU Arm Embedded toolchain (arm-none-eabi-gcc, newlib).
#   cmake -S . -B build/m4f -DCMAKE_TOOLCHAIN_FILE=cmake/arm-none-eabi-cortex-m4f.cmake
# Set ARM_NONE_EABI_PREFIX (e.g. /opt/arm-gnu-toolchain/bin/arm-none-eabi-) for
# a toolchain outside PATH. The executables of a firmware project still need
# its startup code and linker script, or `--specs=nosys.specs` (newlib stubs).
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

if(NOT ARM_NONE_EABI_PREFIX)
  set(ARM_NONE_EABI_PREFIX arm-none-eabi-)
endif()
set(CMAKE_C_COMPILER ${ARM_NONE_EABI_PREFIX}gcc)
set(CMAKE_CXX_COMPILER ${ARM_NONE_EABI_PREFIX}g++)
set(CMAKE_ASM_COMPILER ${ARM_NONE_EABI_PREFIX}gcc)
set(CMAKE_AR ${ARM_NONE_EABI_PREFIX}ar CACHE FILEPATH "")
set(CMAKE_RANLIB ${ARM_NONE_EABI_PREFIX}ranlib CACHE FILEPATH "")

# The compiler checks build a static library: nothing to link without the
# firmware's startup code and linker script.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CMAKE_TRY_COMPILE_PLATFORM_VARIABLES ARM_NONE_EABI_PREFIX)

set(SMD_M4F_FLAGS "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
set(CMAKE_C_FLAGS_INIT "${SMD_M4F_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${SMD_M4F_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_ASM_FLAGS_INIT "${SMD_M4F_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${SMD_M4F_FLAGS} -Wl,--gc-sections")

# Programs from the host; libraries and headers from the target's sysroot
# (CMAKE_FIND_ROOT_PATH) only. Packages from both: a host build of a package
# found by mistake is rejected by its version file (pointer size).
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
