# The `multiray` Python module (src/python) with Debian's pybind11. MULTIRAY_WITH_PYTHON:
#   AUTO (default) build it when pybind11 and the Python headers are found, else warn;
#   ON   strict: fail the configure when it cannot be built, or cannot be tested (numpy,
#        pytest);
#   OFF  never build it.
# Sets MULTIRAY_PYTHON_ENABLED (build src/python) and MULTIRAY_PYTHON_TESTS (numpy and
# pytest import in that interpreter: tests/python is registered with ctest).
#
# The interpreter: Debian's pybind11, numpy and pytest are packages of /usr/bin/python3, so
# that one is preferred to whatever `python3` is first on PATH (a pyenv or virtualenv one
# would lack them); -DPython_EXECUTABLE=... chooses another.
#
# A Python module is a shared object, so every static library it links is then compiled
# as position-independent code (-fPIC rather than the compiler's default -fPIE; the same
# speed on x86-64), which is why this is included before the libraries are declared.
set(MULTIRAY_WITH_PYTHON AUTO CACHE STRING "Build the multiray Python module (pybind11): AUTO, ON or OFF")
set_property(CACHE MULTIRAY_WITH_PYTHON PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${MULTIRAY_WITH_PYTHON}" _multiray_python_mode)
set(MULTIRAY_PYTHON_ENABLED OFF)
set(MULTIRAY_PYTHON_TESTS OFF)
if(_multiray_python_mode STREQUAL "AUTO" OR _multiray_python_mode STREQUAL "ON")
  if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The interpreter of the multiray module")
  endif()
  find_package(Python 3.8 QUIET COMPONENTS Interpreter Development.Module)
  if(Python_FOUND)
    find_package(pybind11 2.6 QUIET CONFIG)
  endif()
  if(Python_FOUND AND pybind11_FOUND)
    set(MULTIRAY_PYTHON_ENABLED ON)
    set(CMAKE_POSITION_INDEPENDENT_CODE ON)
    message(STATUS "multiray: Python module enabled (pybind11 ${pybind11_VERSION}, ${Python_EXECUTABLE})")
    execute_process(COMMAND ${Python_EXECUTABLE} -c "import numpy, pytest"
                    RESULT_VARIABLE _multiray_python_test_deps OUTPUT_QUIET ERROR_QUIET)
    if(_multiray_python_test_deps EQUAL 0)
      set(MULTIRAY_PYTHON_TESTS ON)
    elseif(_multiray_python_mode STREQUAL "ON")
      message(FATAL_ERROR "MULTIRAY_WITH_PYTHON=ON but ${Python_EXECUTABLE} cannot import numpy "
                          "and pytest (python3-numpy, python3-pytest)")
    else()
      message(WARNING "multiray: ${Python_EXECUTABLE} cannot import numpy and pytest "
                      "(python3-numpy, python3-pytest): the Python tests are not registered")
    endif()
  else()
    set(_multiray_python_why "needs pybind11-dev, python3-pybind11 and python3-dev")
    if(_multiray_python_mode STREQUAL "ON")
      message(FATAL_ERROR "MULTIRAY_WITH_PYTHON=ON but the module cannot be built: ${_multiray_python_why}")
    endif()
    message(WARNING "multiray: Python module disabled (${_multiray_python_why})")
  endif()
elseif(NOT _multiray_python_mode STREQUAL "OFF")
  message(FATAL_ERROR "MULTIRAY_WITH_PYTHON must be AUTO, ON or OFF, not '${MULTIRAY_WITH_PYTHON}'")
endif()
