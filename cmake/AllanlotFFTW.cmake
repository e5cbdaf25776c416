# FFTW3 (double precision) and its threads library through pkg-config, as FINUFFT does.
include_guard(GLOBAL)
find_package(PkgConfig REQUIRED)
pkg_check_modules(fftw3 REQUIRED IMPORTED_TARGET fftw3)
find_library(ALLANLOT_FFTW3_THREADS_LIB NAMES fftw3_threads HINTS ${fftw3_LIBRARY_DIRS} REQUIRED)
add_library(allanlot_fftw INTERFACE)
target_link_libraries(allanlot_fftw INTERFACE ${ALLANLOT_FFTW3_THREADS_LIB} PkgConfig::fftw3)
add_library(allanlot::fftw ALIAS allanlot_fftw)
