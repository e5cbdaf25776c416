# The Python module (python/, docs/python.md) needs Python 3 with its headers and pybind11
# (Debian: python3-dev, pybind11-dev; scripts/setup installs them). Without them the module is
# left out with a message: the command line never needs Python. ThreadSanitizer and fuzzing
# builds leave it out too (they test the C++ paths; the ASan build tests the module).
include_guard(GLOBAL)

if(ALLANLOT_BUILD_PYTHON AND (ALLANLOT_SANITIZE STREQUAL "TSAN" OR ALLANLOT_FUZZ))
  set(ALLANLOT_BUILD_PYTHON OFF)
endif()
if(ALLANLOT_BUILD_PYTHON)
  # Debian's interpreter, whose numpy and pytest scripts/setup installs, rather than whichever
  # python3 comes first on PATH (a pyenv or conda one has neither); -DPython3_EXECUTABLE=...
  # chooses another.
  if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python interpreter of the module")
  endif()
  find_package(Python3 3.9 COMPONENTS Interpreter Development.Module)
  if(Python3_FOUND)
    # pybind11 finds Python through FindPython: point it at the same interpreter.
    set(Python_EXECUTABLE ${Python3_EXECUTABLE})
    set(PYBIND11_FINDPYTHON ON)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
  if(NOT Python3_FOUND OR NOT pybind11_FOUND)
    message(STATUS "Python 3 headers or pybind11 not found: the Python module allanlot is not "
                   "built (scripts/setup installs python3-dev and pybind11-dev)")
    set(ALLANLOT_BUILD_PYTHON OFF)
  else()
    # The static libraries are linked into the extension module, a shared object.
    set(CMAKE_POSITION_INDEPENDENT_CODE ON)
  endif()
endif()
