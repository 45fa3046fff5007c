# Installs the libraries, headers and a CMake package so that an outside project can do
#   find_package(shatter REQUIRED)   target_link_libraries(app PRIVATE shatter::shatter)
# or link one engine-independent module alone: shatter::geometry, shatter::lattice,
# shatter::oriented, shatter::mpm (the 2D crack solver, no Bullet). shatter::shatter links
# them all, so every one of them must be in the export set.
include(CMakePackageConfigHelpers)

install(TARGETS shatter shatter_common shatter_geometry shatter_lattice shatter_oriented shatter_mpm shatter_fracture EXPORT shatterTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Headers land under <prefix>/include/shatter/, included as <shatter/bullet_ext/Plugin.h>:
# only the one folder name `shatter` is added to a consumer's include namespace.
install(DIRECTORY shatter DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(EXPORT shatterTargets NAMESPACE shatter:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/shatter)

configure_package_config_file(cmake/shatterConfig.cmake.in ${CMAKE_BINARY_DIR}/shatterConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/shatter)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/shatterConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/shatterConfig.cmake ${CMAKE_BINARY_DIR}/shatterConfigVersion.cmake
  cmake/ShatterDependencies.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/shatter)
