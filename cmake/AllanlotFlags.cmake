# One helper applies the language standard, warnings, sanitizers and OpenMP to every target,
# so that no target is built with different flags from its neighbours.
include_guard(GLOBAL)

set(ALLANLOT_WARNING_FLAGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                           -Wcast-align -Wunused -Woverloaded-virtual)

if(ALLANLOT_SANITIZE STREQUAL "ASAN")
  set(ALLANLOT_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=undefined
                               -fno-omit-frame-pointer)
elseif(ALLANLOT_SANITIZE STREQUAL "TSAN")
  set(ALLANLOT_SANITIZER_FLAGS -fsanitize=thread -fno-omit-frame-pointer)
elseif(NOT ALLANLOT_SANITIZE STREQUAL "OFF")
  message(FATAL_ERROR "ALLANLOT_SANITIZE must be OFF, ASAN or TSAN, not '${ALLANLOT_SANITIZE}'")
endif()

# Fuzzing (fuzz/): every library is compiled with libFuzzer's coverage instrumentation; only
# the fuzz targets themselves link libFuzzer's main (-fsanitize=fuzzer, fuzz/CMakeLists.txt).
if(ALLANLOT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "ALLANLOT_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++")
  endif()
  list(APPEND ALLANLOT_SANITIZER_FLAGS -fsanitize=fuzzer-no-link)
endif()

# The sanitized builds (presets asan and tsan, scripts/fuzz) link with LLVM's lld: with ASan
# and line tables a test program is 50 to 160 MB, and lld links one in under half the CPU time of
# GNU ld (docs/validation/2026-11-29-ci-time.md). Off elsewhere: the release build's Python
# module is compiled with GCC's -flto, whose objects only GNU ld's plugin reads.
option(ALLANLOT_LLD "Link with lld (-fuse-ld=lld; the sanitized presets turn it on)" OFF)
set(ALLANLOT_LINKER_FLAGS)
if(ALLANLOT_LLD)
  include(CheckLinkerFlag)
  check_linker_flag(CXX -fuse-ld=lld ALLANLOT_HAVE_LLD)
  if(ALLANLOT_HAVE_LLD)
    set(ALLANLOT_LINKER_FLAGS -fuse-ld=lld)
  else()
    message(WARNING "ALLANLOT_LLD: the compiler cannot link with lld (scripts/setup installs "
                    "lld); linking with the default linker")
  endif()
endif()

# Precompiled headers for the files that all include the same heavy headers (GoogleTest in the
# test programs, CLI11 in src/cli/): in a build from scratch, as CI's, they save about a tenth of
# the compile time (docs/validation/2026-11-29-ci-time.md). GCC only: clang (the TSan and fuzz
# builds) refuses a header precompiled under other macro definitions than the file's. Off by
# default under ccache, which caches a compile that uses a precompiled header only with
# CCACHE_SLOPPINESS=pch_defines,time_macros (docs/development.md "Building").
if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  set(_pch_default OFF)
else()
  set(_pch_default ON)
endif()
option(ALLANLOT_PCH "Precompile the headers the test programs and src/cli/ share (GCC)"
       ${_pch_default})
set(ALLANLOT_USE_PCH OFF)
if(ALLANLOT_PCH AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set(ALLANLOT_USE_PCH ON)
endif()

function(allanlot_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE ${ALLANLOT_WARNING_FLAGS})
  if(ALLANLOT_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  target_link_options(${target} PRIVATE ${ALLANLOT_LINKER_FLAGS})
  if(ALLANLOT_SANITIZER_FLAGS)
    target_compile_options(${target} PUBLIC ${ALLANLOT_SANITIZER_FLAGS})
    target_link_options(${target} PUBLIC ${ALLANLOT_SANITIZER_FLAGS})
  endif()
  if(ALLANLOT_USE_OPENMP)
    target_link_libraries(${target} PUBLIC OpenMP::OpenMP_CXX)
  else()
    # Without OpenMP the `#pragma omp` lines are meant to be ignored (the serial build gives
    # the same results); they must not become warnings, and so errors in CI.
    target_compile_options(${target} PRIVATE -Wno-unknown-pragmas)
  endif()
endfunction()
