# Every compile goes through ccache when it is installed (STRIDEMAP_COMPILER_CACHE),
# set up so that two clones of one commit in different folders share hits:
# CI builds a fresh clone on the machine where the work before it was built,
# and `make check` builds another (docs/reliability.md, "The check's time").
#   CCACHE_BASEDIR   paths under the source root enter the key relative to the
#                    build folder, so the clone's folder does not
#   CCACHE_NOHASHDIR the working directory stays out of the key (objects of a
#                    debug-info build then name the first clone's folder)
#   CCACHE_SLOPPINESS the precompiled headers are cacheable (pch_defines,
#                    time_macros), and a fresh clone's new file times do not
#                    turn the cache off (include_file_mtime, include_file_ctime)
# The unity batches name their sources relatively (cmake/StridemapHelpers.cmake)
# and the tests find the source tree through a library, not a -D path
# (tests/test_paths.hpp), for the same reason. A machine without ccache, or
# -DSTRIDEMAP_COMPILER_CACHE=OFF, or a launcher of the user's own, compiles
# as before; CCACHE_DISABLE=1 in the environment turns the cache off for one build.
option(STRIDEMAP_COMPILER_CACHE "Compile through ccache when it is installed" ON)
if(STRIDEMAP_COMPILER_CACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER AND NOT DEFINED ENV{CMAKE_CXX_COMPILER_LAUNCHER})
  find_program(STRIDEMAP_CCACHE_PROGRAM ccache)
  if(STRIDEMAP_CCACHE_PROGRAM)
    set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR} CCACHE_NOHASHDIR=1
      CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime ${STRIDEMAP_CCACHE_PROGRAM})
    message(STATUS "stridemap: compiling through ${STRIDEMAP_CCACHE_PROGRAM} (STRIDEMAP_COMPILER_CACHE)")
  endif()
endif()
