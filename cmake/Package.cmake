# `cpack -G DEB` (from the build folder): one Debian package with the
# libraries (libmbrt.so, libmbrt.a and the C++ static libraries), the
# headers, the CMake package and pkg-config file, the `mbrt` command and the
# Python module (in /usr/lib/python3/dist-packages). scripts/test-deb.sh
# builds it and lists it.
set(CPACK_PACKAGE_NAME mbrt)
set(CPACK_PACKAGE_VENDOR "mbrt")
set(CPACK_PACKAGE_CONTACT "mbrt maintainers <mbrt@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Ray tracing with motion blur: STBVH, MSBVH, MBKD, fuzzy kd-trees (C, C++, Python)")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION libs)
# The run-time dependencies from the binaries (dpkg-shlibdeps), plus numpy
# for the Python module.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(MBRT_PYTHON)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, python3-numpy")
endif()
include(CPack)
