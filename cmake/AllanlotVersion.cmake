# The version and git revision go into every results file (tool_version), so a result can be
# traced to the code that produced it.
include_guard(GLOBAL)
find_package(Git QUIET)
set(ALLANLOT_GIT_SHA "unknown")
if(GIT_FOUND AND EXISTS ${CMAKE_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD
                  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE _sha
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE _rc)
  if(_rc EQUAL 0 AND _sha)
    set(ALLANLOT_GIT_SHA ${_sha})
  endif()
endif()
configure_file(${CMAKE_SOURCE_DIR}/src/version.hpp.in ${CMAKE_BINARY_DIR}/generated/allanlot/version.hpp
               @ONLY)
