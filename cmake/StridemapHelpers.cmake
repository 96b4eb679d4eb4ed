# One library per layer of design.md section 2; sources are every .cpp of the
# layer's folder so that adding a file never means editing a shared list.
#
# Each layer exposes only its own headers: its include root is a folder in
# the build tree that holds just include/stridemap/<layer> (a symbolic link),
# so a layer sees the headers of the layers it links and no others, and an
# upward #include fails to compile instead of relying on discipline. The
# installed package keeps the one include/ folder.
function(stridemap_layer_include_root name out_var)
  set(root ${CMAKE_BINARY_DIR}/layer_include/${name})
  if(NOT EXISTS ${root}/stridemap/${name})
    file(MAKE_DIRECTORY ${root}/stridemap)
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/include/stridemap/${name} ${root}/stridemap/${name} SYMBOLIC)
  endif()
  set(${out_var} ${root} PARENT_SCOPE)
endfunction()

function(stridemap_add_layer name)
  cmake_parse_arguments(ARG "" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  stridemap_layer_include_root(${name} include_root)
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(NOT sources)
    # A layer whose sources are still to come is header-only for now.
    add_library(stridemap_${name} INTERFACE)
    target_include_directories(stridemap_${name} INTERFACE
      $<BUILD_INTERFACE:${include_root}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(stridemap_${name} INTERFACE ${ARG_PUBLIC_DEPS})
    set_target_properties(stridemap_${name} PROPERTIES EXPORT_NAME ${name})
    add_library(stridemap::${name} ALIAS stridemap_${name})
    return()
  endif()
  add_library(stridemap_${name} ${sources})
  add_library(stridemap::${name} ALIAS stridemap_${name})
  # While the version is 0.x every minor release may change the ABI, so the
  # soname carries major.minor (libstridemap_core.so.0.1).
  set_target_properties(stridemap_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME stridemap_${name}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_include_directories(stridemap_${name} PUBLIC
    $<BUILD_INTERFACE:${include_root}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(stridemap_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  stridemap_set_warnings(stridemap_${name})
endfunction()

function(stridemap_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
  if(STRIDEMAP_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
