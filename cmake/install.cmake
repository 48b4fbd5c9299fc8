# `cmake --install`: the command line, the library with its public headers (include/isoquad/
# only) and a CMake package, so that a project does find_package(isoquad) and links
# isoquad::isoquad.
include(CMakePackageConfigHelpers)
set(ISOQUAD_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/isoquad)

install(TARGETS isoquad_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS isoquad EXPORT isoquadTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/isoquad DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT isoquadTargets NAMESPACE isoquad:: DESTINATION ${ISOQUAD_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/isoquadConfig.cmake.in
  ${PROJECT_BINARY_DIR}/isoquadConfig.cmake INSTALL_DESTINATION ${ISOQUAD_CMAKE_DIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/isoquadConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/isoquadConfig.cmake
  ${PROJECT_BINARY_DIR}/isoquadConfigVersion.cmake DESTINATION ${ISOQUAD_CMAKE_DIR})
