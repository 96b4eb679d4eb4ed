# Installs the libraries and headers and exports a CMake package so that robot
# code can say find_package(stridemap) and link stridemap::core etc.
include(CMakePackageConfigHelpers)

set(STRIDEMAP_LAYERS core sensors preprocess pipeline sim io experiments live)
set(stridemap_install_targets)
foreach(layer IN LISTS STRIDEMAP_LAYERS)
  list(APPEND stridemap_install_targets stridemap_${layer})
endforeach()

install(TARGETS ${stridemap_install_targets}
  EXPORT stridemapTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS stridemap_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/stridemap DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/stridemap)
install(EXPORT stridemapTargets NAMESPACE stridemap:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/stridemapConfig.cmake.in
  ${CMAKE_BINARY_DIR}/stridemapConfig.cmake INSTALL_DESTINATION ${config_dir})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/stridemapConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/stridemapConfig.cmake ${CMAKE_BINARY_DIR}/stridemapConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/FindOpenCVImgproc.cmake
  DESTINATION ${config_dir})
