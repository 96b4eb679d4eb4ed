# Installs the libraries, headers, the tool and its shipped scenes and
# configs, and describes the libraries twice: a CMake package (robot code
# says find_package(stridemap) and links stridemap::core etc.) and a
# pkg-config file (pkg-config --cflags --libs stridemap). docs/install.md.
include(CMakePackageConfigHelpers)

set(STRIDEMAP_LAYERS core sensors preprocess pipeline sim io config render mapfile recordings devices vision experiments
  live)
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
# io/detail/ is shared by the library's layers that write files; no
# installed header includes it.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/stridemap DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  PATTERN detail EXCLUDE)
# The tool looks for its default scenes here, relative to itself (apps/CMakeLists.txt).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes ${PROJECT_SOURCE_DIR}/configs
  DESTINATION ${CMAKE_INSTALL_DATADIR}/stridemap)

# Installed binaries find the libraries beside them whatever the prefix: the
# tool through bin/../lib, each library its siblings through $ORIGIN. The
# build tree keeps CMake's absolute build RPATH.
file(RELATIVE_PATH stridemap_lib_from_bin ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR})
set_target_properties(stridemap_cli PROPERTIES INSTALL_RPATH "$ORIGIN/${stridemap_lib_from_bin}")
foreach(target IN LISTS stridemap_install_targets)
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "SHARED_LIBRARY")
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN")
  endif()
endforeach()

# pkg-config: the layers highest first, so a static link resolves in order.
# Eigen is in the public headers (Requires); the rest only in the libraries:
# a shared build needs none of them on the consumer's link line
# (Requires.private / Libs.private serve --static).
set(stridemap_pc_libs "")
set(layers_high_first ${STRIDEMAP_LAYERS})
list(REVERSE layers_high_first)
foreach(layer IN LISTS layers_high_first)
  string(APPEND stridemap_pc_libs " -lstridemap_${layer}")
endforeach()
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(stridemap_pc_libdir "${CMAKE_INSTALL_LIBDIR}")
else()
  set(stridemap_pc_libdir "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(stridemap_pc_includedir "${CMAKE_INSTALL_INCLUDEDIR}")
else()
  set(stridemap_pc_includedir "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
file(RELATIVE_PATH stridemap_pc_prefix_from_pcdir ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
configure_file(${PROJECT_SOURCE_DIR}/cmake/stridemap.pc.in ${CMAKE_BINARY_DIR}/stridemap.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/stridemap.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/stridemap)
install(EXPORT stridemapTargets NAMESPACE stridemap:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/stridemapConfig.cmake.in
  ${CMAKE_BINARY_DIR}/stridemapConfig.cmake INSTALL_DESTINATION ${config_dir})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/stridemapConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/stridemapConfig.cmake ${CMAKE_BINARY_DIR}/stridemapConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/FindOpenCVImgproc.cmake
  DESTINATION ${config_dir})
