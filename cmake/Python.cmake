# The Python module `mbrt` (python/): pybind11 from Debian (python3-pybind11)
# and numpy, built for MBRT_PYTHON_EXECUTABLE (/usr/bin/python3: the
# interpreter that has them). The package lands in <build>/python/mbrt, so
# that PYTHONPATH=<build>/python imports it; the pytest suite in
# tests/python runs as CTests; `pip install --no-build-isolation .` drives
# this file through setup.py.
set(MBRT_PYTHON_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the module is built for")
set(_mbrt_python_default OFF)
set(_mbrt_pybind11_dir "")
if(EXISTS "${MBRT_PYTHON_EXECUTABLE}")
  execute_process(
    COMMAND "${MBRT_PYTHON_EXECUTABLE}" -c "import numpy, pybind11; print(pybind11.get_cmake_dir())"
    RESULT_VARIABLE _mbrt_python_rc OUTPUT_VARIABLE _mbrt_pybind11_dir
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  # A sanitized library cannot be loaded into an uninstrumented interpreter.
  if(_mbrt_python_rc EQUAL 0 AND NOT MBRT_SANITIZE)
    set(_mbrt_python_default ON)
  endif()
endif()
option(MBRT_PYTHON "Build the Python module (pybind11 + numpy)" ${_mbrt_python_default})
message(STATUS "mbrt Python module: ${MBRT_PYTHON} (${MBRT_PYTHON_EXECUTABLE})")
if(NOT MBRT_PYTHON)
  return()
endif()

set(PYBIND11_FINDPYTHON ON)
set(Python_EXECUTABLE "${MBRT_PYTHON_EXECUTABLE}")
find_package(pybind11 2.6 CONFIG REQUIRED HINTS "${_mbrt_pybind11_dir}")

file(GLOB MBRT_PYTHON_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/src/*.cpp)
pybind11_add_module(mbrt_python MODULE NO_EXTRAS ${MBRT_PYTHON_SOURCES})
set(MBRT_PYTHON_PACKAGE_DIR ${PROJECT_BINARY_DIR}/python/mbrt)
set_target_properties(mbrt_python PROPERTIES OUTPUT_NAME _mbrt LIBRARY_OUTPUT_DIRECTORY ${MBRT_PYTHON_PACKAGE_DIR})
target_link_libraries(mbrt_python PRIVATE mbrt::mbrt)
target_compile_options(mbrt_python PRIVATE ${MBRT_ISA_FLAGS} $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra>)
target_compile_definitions(mbrt_python PRIVATE MBRT_VERSION="${PROJECT_VERSION}")
# The static mbrt code inside the module stays private to it.
target_link_options(mbrt_python PRIVATE -Wl,--exclude-libs,ALL)

# The pure-Python part and the stubs, next to the extension.
file(GLOB MBRT_PYTHON_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/mbrt/*.py
     ${PROJECT_SOURCE_DIR}/python/mbrt/*.pyi ${PROJECT_SOURCE_DIR}/python/mbrt/py.typed)
set(_mbrt_python_copies "")
foreach(file IN LISTS MBRT_PYTHON_FILES)
  get_filename_component(name ${file} NAME)
  add_custom_command(OUTPUT ${MBRT_PYTHON_PACKAGE_DIR}/${name}
                     COMMAND ${CMAKE_COMMAND} -E copy ${file} ${MBRT_PYTHON_PACKAGE_DIR}/${name}
                     DEPENDS ${file} VERBATIM)
  list(APPEND _mbrt_python_copies ${MBRT_PYTHON_PACKAGE_DIR}/${name})
endforeach()
add_custom_target(mbrt_python_files ALL DEPENDS ${_mbrt_python_copies})
add_dependencies(mbrt_python mbrt_python_files)

# Installed where Debian's python3 looks (the DEB package; cmake --install).
set(MBRT_PYTHON_INSTALL_DIR "lib/python3/dist-packages" CACHE STRING
    "Where `cmake --install` puts the Python package (relative to the prefix)")
install(TARGETS mbrt_python LIBRARY DESTINATION ${MBRT_PYTHON_INSTALL_DIR}/mbrt COMPONENT python)
install(FILES ${MBRT_PYTHON_FILES} DESTINATION ${MBRT_PYTHON_INSTALL_DIR}/mbrt COMPONENT python)

if(MBRT_BUILD_TESTS)
  # One CTest per test file, with the build's package first on the path.
  file(GLOB MBRT_PYTHON_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/python/test_*.py)
  set(_mbrt_python_env "PYTHONPATH=${PROJECT_BINARY_DIR}/python" "PYTHONDONTWRITEBYTECODE=1")
  if(MBRT_BUILD_TOOLS)
    list(APPEND _mbrt_python_env "MBRT_CLI=$<TARGET_FILE:mbrt_cli>")
  endif()
  foreach(test IN LISTS MBRT_PYTHON_TESTS)
    get_filename_component(name ${test} NAME_WE)
    string(REGEX REPLACE "^test_" "" name ${name})
    add_test(NAME python.${name}
             COMMAND ${MBRT_PYTHON_EXECUTABLE} -m pytest -q -p no:cacheprovider ${test}
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    set_tests_properties(python.${name} PROPERTIES ENVIRONMENT "${_mbrt_python_env}")
  endforeach()
endif()
