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

function(allanlot_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE ${ALLANLOT_WARNING_FLAGS})
  if(ALLANLOT_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
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
