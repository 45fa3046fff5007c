# Every dependency is a Debian package; see third_party_notes/ for why each one is here.
# This file is also installed and included by shatterConfig.cmake, so that a consumer
# finds the same libraries the same way.
include(CMakeFindDependencyMacro)
find_dependency(Eigen3 3.3)
find_dependency(PkgConfig)
if(SHATTER_BULLET_DOUBLE)
  pkg_check_modules(BULLET REQUIRED IMPORTED_TARGET GLOBAL bullet-float64)
else()
  pkg_check_modules(BULLET REQUIRED IMPORTED_TARGET GLOBAL bullet)
endif()
pkg_check_modules(CCD REQUIRED IMPORTED_TARGET GLOBAL ccd)
# voro++ (Debian voro++-dev) ships neither a pkg-config file nor a CMake package: find its
# header and library directly.
if(NOT TARGET Voro::voro)
  find_path(VORO_INCLUDE_DIR voro++.hh PATH_SUFFIXES voro++ REQUIRED)
  find_library(VORO_LIBRARY voro++ REQUIRED)
  add_library(Voro::voro UNKNOWN IMPORTED)
  set_target_properties(Voro::voro PROPERTIES IMPORTED_LOCATION "${VORO_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${VORO_INCLUDE_DIR}/..")
endif()
