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
  stridemap_skip_thread_sanitizer(stridemap_${name} ${name})
  if(STRIDEMAP_BUILD_FUZZERS AND name IN_LIST STRIDEMAP_FUZZ_COVERAGE_LAYERS)
    target_compile_options(stridemap_${name} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
  stridemap_unity_build_library(stridemap_${name})
  if(NOT STRIDEMAP_UNITY_BUILD)
    stridemap_precompile_common_headers(stridemap_${name})
  endif()
endfunction()

# The layers that parse what the fuzzers of fuzz/targets feed them: files,
# device bytes, images. libFuzzer's coverage feedback goes into these alone.
set(STRIDEMAP_FUZZ_COVERAGE_LAYERS io config render mapfile recordings sensors vision)

# ThreadSanitizer looks for two threads touching the same memory, so a layer
# whose code never runs on a second thread gains nothing from it and runs its
# tests several times slower (`make test-tsan` names these layers). Its inline
# functions stay hidden so that no instrumented library calls an
# uninstrumented copy (which would hide the atomics TSan must see).
# Configuring fails if such a layer's sources start a thread.
set(STRIDEMAP_TSAN_UNINSTRUMENTED_LAYERS "" CACHE STRING
  "Layers compiled without -fsanitize=thread in a ThreadSanitizer build (their code runs on one thread)")
function(stridemap_skip_thread_sanitizer target layer)
  if(NOT layer IN_LIST STRIDEMAP_TSAN_UNINSTRUMENTED_LAYERS)
    return()
  endif()
  file(GLOB_RECURSE files ${PROJECT_SOURCE_DIR}/src/${layer}/* ${PROJECT_SOURCE_DIR}/include/stridemap/${layer}/*)
  foreach(file IN LISTS files)
    file(STRINGS ${file} starts REGEX "std::(thread|jthread|async)|pthread_create")
    if(starts)
      message(FATAL_ERROR "${file} starts a thread, so layer ${layer} must be instrumented: "
        "take it out of STRIDEMAP_TSAN_UNINSTRUMENTED_LAYERS (Makefile, TSAN_UNINSTRUMENTED)")
    endif()
  endforeach()
  target_compile_options(${target} PRIVATE -fno-sanitize=thread -fvisibility-inlines-hidden)
endfunction()

# Eigen and the standard headers every layer uses are parsed once per target
# instead of once per file: about 2 s less per library file and 4 s per test
# file, which CI pays in three builds (docs/reliability.md). Headers are still
# each file's own business: a build with STRIDEMAP_PRECOMPILED_HEADERS=OFF
# (what an installed consumer sees) must compile too.
option(STRIDEMAP_PRECOMPILED_HEADERS "Precompile Eigen, the standard library and (for tests) GoogleTest headers" ON)
function(stridemap_precompile_common_headers target)
  if(NOT STRIDEMAP_PRECOMPILED_HEADERS)
    return()
  endif()
  target_precompile_headers(${target} PRIVATE <Eigen/Core> <Eigen/Geometry> <algorithm> <array> <cmath>
    <cstdint> <functional> <limits> <memory> <optional> <string> <string_view> <utility> <vector> ${ARGN})
  # Through ccache (its manual, "Precompiled headers"): g++'s users of the
  # header are cached only with -fpch-preprocess; clang's header must carry
  # no file times, or one taken from the cache of another clone, whose
  # cmake_pch.hxx is older, would be refused as out of date.
  if(CMAKE_CXX_COMPILER_LAUNCHER AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -fpch-preprocess)
  elseif(CMAKE_CXX_COMPILER_LAUNCHER AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    target_compile_options(${target} PRIVATE "SHELL:-Xclang -fno-pch-timestamp")
  endif()
endfunction()

# The test programs' own code (assertions, fixtures, GoogleTest's templates)
# and the tool's command files (CLI11) compile in 40 % less CPU at -O1 than
# at -O3, and a run's time moves little: the work they drive runs in the
# libraries, which keep the build type's level (docs/reliability.md, "Build
# choices"). Empty: the build type's, the default off x86: where fused
# multiply-add is in the base instruction set (aarch64) g++ fuses a * b + c
# only from -O2, so a reference computed in a test at -O1 would differ in
# the last bit from the library it checks bit for bit.
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64|i.86)$")
  set(stridemap_default_glue_optimization "-O1")
else()
  set(stridemap_default_glue_optimization "")
endif()
set(STRIDEMAP_GLUE_OPTIMIZATION "${stridemap_default_glue_optimization}" CACHE STRING
  "Optimisation flags of the test programs and the tool's command files")
function(stridemap_glue_optimization target)
  if(STRIDEMAP_GLUE_OPTIMIZATION)
    target_compile_options(${target} PRIVATE ${STRIDEMAP_GLUE_OPTIMIZATION})
  endif()
endfunction()

function(stridemap_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
  if(STRIDEMAP_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# One translation unit per program (STRIDEMAP_UNITY_BUILD, top CMakeLists.txt):
# the precompiled header, GoogleTest's and Eigen's templates and CLI11 are
# compiled once a program instead of once a file. The core tests' 15 files
# took 49 s of CPU one by one and 24 s as one (docs/reliability.md).
function(stridemap_unity_build target)
  if(STRIDEMAP_UNITY_BUILD)
    stridemap_unity_batches(${target} 0)
  endif()
endfunction()

# A library in batches of STRIDEMAP_UNITY_BATCH_SIZE files (STRIDEMAP_UNITY_BUILD):
# the layers build one after another (each links the one below), so one
# translation unit per layer would leave the second core of a 2-core build
# idle; batches keep both busy. No precompiled header: a batch parses Eigen
# and the standard headers once anyway, and building the header cost more
# than it saved (docs/performance.md). A file whose file-local names clash
# with another file of its layer is marked SKIP_UNITY_BUILD_INCLUSION where
# its layer is declared (src/CMakeLists.txt); any file with its own
# COMPILE_OPTIONS or COMPILE_DEFINITIONS is compiled alone too.
set(STRIDEMAP_UNITY_BATCH_SIZE 8 CACHE STRING "Library files per translation unit with STRIDEMAP_UNITY_BUILD")
function(stridemap_unity_build_library target)
  if(NOT STRIDEMAP_UNITY_BUILD)
    return()
  endif()
  stridemap_unity_batches(${target} ${STRIDEMAP_UNITY_BATCH_SIZE})
  # g++ takes every file of a batch but the generated one for a header, and
  # warns that a class of it (ScanLogReader::State, say) holds a type from
  # the file's anonymous namespace; the class is defined in that file only.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
endfunction()

# The batches are written here rather than by CMake's UNITY_BUILD, whose
# batch files include every source by its absolute path: the preprocessed
# text then names the clone's folder, and a compiler cache filled by one
# clone never hits in another clone of the same commit. Ours include each
# source by its path relative to the batch file, so with ccache's base
# directory at the source root (cmake/StridemapCompilerCache.cmake) two
# clones of one commit compile identical text. The batches are formed once
# every directory has been read (a deferred call), because the sources'
# properties (SKIP_UNITY_BUILD_INCLUSION, COMPILE_OPTIONS) and some sources
# (ros/ adds the tool's --bag files) come after the target is declared.
function(stridemap_unity_batches target batch_size)
  cmake_language(EVAL CODE
    "cmake_language(DEFER DIRECTORY [[${PROJECT_SOURCE_DIR}]] CALL stridemap_write_unity_batches [[${target}]] [[${batch_size}]])")
endfunction()

function(stridemap_write_unity_batches target batch_size)
  get_target_property(target_dir ${target} SOURCE_DIR)
  get_target_property(sources ${target} SOURCES)
  set(kept_sources)
  set(batched_sources)
  foreach(source IN LISTS sources)
    if(source MATCHES "\\$<" OR NOT source MATCHES "\\.(cpp|cc|cxx)$")
      list(APPEND kept_sources ${source})
      continue()
    endif()
    cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${target_dir} NORMALIZE OUTPUT_VARIABLE path)
    set(compiled_alone FALSE)
    foreach(property SKIP_UNITY_BUILD_INCLUSION COMPILE_OPTIONS COMPILE_DEFINITIONS COMPILE_FLAGS INCLUDE_DIRECTORIES
                     HEADER_FILE_ONLY GENERATED)
      get_source_file_property(value ${path} DIRECTORY ${target_dir} ${property})
      if(value)
        set(compiled_alone TRUE)
      endif()
    endforeach()
    if(compiled_alone)
      list(APPEND kept_sources ${path})
    else()
      list(APPEND batched_sources ${path})
    endif()
  endforeach()
  list(LENGTH batched_sources batched_count)
  if(batched_count LESS 2)
    return()  # nothing to gain: the target keeps its sources as they are
  endif()
  if(batch_size EQUAL 0)
    set(batch_size ${batched_count})
  endif()
  set(batch_dir ${CMAKE_BINARY_DIR}/unity/${target})
  set(batch_files)
  set(content "")
  set(in_batch 0)
  set(index 0)
  foreach(path IN LISTS batched_sources)
    file(RELATIVE_PATH relative ${batch_dir} ${path})
    string(APPEND content "#include \"${relative}\"\n")
    math(EXPR in_batch "${in_batch} + 1")
    if(in_batch EQUAL batch_size)
      file(CONFIGURE OUTPUT ${batch_dir}/batch_${index}.cpp CONTENT "${content}" @ONLY)
      list(APPEND batch_files ${batch_dir}/batch_${index}.cpp)
      math(EXPR index "${index} + 1")
      set(content "")
      set(in_batch 0)
    endif()
  endforeach()
  if(in_batch GREATER 0)
    file(CONFIGURE OUTPUT ${batch_dir}/batch_${index}.cpp CONTENT "${content}" @ONLY)
    list(APPEND batch_files ${batch_dir}/batch_${index}.cpp)
  endif()
  set_property(TARGET ${target} PROPERTY SOURCES ${kept_sources} ${batch_files})
endfunction()

# The library behind tests/test_paths.hpp, which tests and benchmarks link.
# Its one generated file is the only compile of the test programs that names
# this clone's folder.
function(stridemap_add_test_paths_library)
  get_filename_component(shared_data_dir ${PROJECT_SOURCE_DIR}/../shared/data ABSOLUTE)
  set(source ${CMAKE_BINARY_DIR}/test_paths/test_paths.cpp)
  file(GENERATE OUTPUT ${source} CONTENT "#include \"test_paths.hpp\"
namespace stridemap::test_paths {
const char* source_dir() { return \"${PROJECT_SOURCE_DIR}\"; }
const char* shared_data_dir() { return \"${shared_data_dir}\"; }
const char* cli_path() { return \"$<$<TARGET_EXISTS:stridemap_cli>:$<TARGET_FILE:stridemap_cli>>\"; }
const char* node_path() { return \"$<$<TARGET_EXISTS:stridemap_node>:$<TARGET_FILE:stridemap_node>>\"; }
}  // namespace stridemap::test_paths
")
  add_library(stridemap_test_paths STATIC ${source})
  target_include_directories(stridemap_test_paths PUBLIC ${PROJECT_SOURCE_DIR}/tests)
endfunction()
