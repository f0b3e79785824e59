# Build options and compiler settings shared by every target.
option(SRICS_NATIVE "Compile for this host's vector instructions (-march=native); without, the products still use them through oneDNN" ON)
option(SRICS_ONEDNN "Multiply float matrices with oneDNN (kernels chosen at run time for the CPU); Eigen without" ON)
option(SRICS_BUILD_TESTS "Build the test suite" ON)
option(SRICS_BUILD_BENCHMARKS "Build the benchmarks" ON)
option(SRICS_BUILD_DEV_TOOLS "Build the development tools (graph_probe, toy_learn)" OFF)
option(SRICS_WARNINGS_AS_ERRORS "Treat compiler warnings as errors" OFF)

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)

find_program(SRICS_CCACHE ccache)
if(SRICS_CCACHE)
  set(CMAKE_C_COMPILER_LAUNCHER ${SRICS_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${SRICS_CCACHE})
endif()

add_compile_options(-Wall -Wextra -Wno-unused-parameter)
if(SRICS_WARNINGS_AS_ERRORS)
  add_compile_options(-Werror)
endif()
if(SRICS_NATIVE)
  add_compile_options(-march=native)
endif()
# Release keeps assertions off; RelWithDebInfo is the profiling build.
set(CMAKE_CXX_FLAGS_RELEASE "-O2 -DNDEBUG")

# libFuzzer harnesses (tests/fuzz, ./tests/fuzz.sh): a separate build with clang, everything
# instrumented for coverage, AddressSanitizer and UndefinedBehaviorSanitizer (any report aborts).
option(SRICS_FUZZ "Build the libFuzzer harnesses of tests/fuzz (clang only; a separate build)" OFF)
if(SRICS_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "SRICS_FUZZ needs clang: -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer -g -Wno-unknown-warning-option)
  add_link_options(-fsanitize=address,undefined)
endif()

# AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer over the whole build, for
# ./tests/sanitize.sh (a separate build folder; any report fails the test that caused it).
# The debug info comes from the build type (tests/sanitize.sh: clang, -O1 -gline-tables-only, enough
# for symbolised reports at a third of the compile time of gcc with -g over the Eigen code).
option(SRICS_SANITIZE "Build everything with ASan + UBSan (./tests/sanitize.sh)" OFF)
if(SRICS_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    add_compile_options(-Wno-unknown-warning-option)
  endif()
  add_link_options(-fsanitize=address,undefined)
endif()
