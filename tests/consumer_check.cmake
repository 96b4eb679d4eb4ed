# Runs as `cmake -P`: installs the build tree into a fresh prefix, then uses
# it as a user would: builds the example consumer with find_package(stridemap)
# and again with pkg-config, and runs the installed tool from outside the
# source tree with a default scene, which it must find under the prefix.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run_step)
  cmake_parse_arguments(STEP "" "IN;OUTPUT" "" ${ARGN})
  if(NOT STEP_IN)
    set(STEP_IN ${WORK_DIR})
  endif()
  execute_process(COMMAND ${STEP_UNPARSED_ARGUMENTS} WORKING_DIRECTORY ${STEP_IN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${STEP_UNPARSED_ARGUMENTS}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
  if(STEP_OUTPUT)
    set(${STEP_OUTPUT} "${out}" PARENT_SCOPE)
  endif()
endfunction()
file(MAKE_DIRECTORY ${WORK_DIR})
run_step(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# find_package
run_step(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${WORK_DIR}/build
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
run_step(${CMAKE_COMMAND} --build ${WORK_DIR}/build -j2)
run_step(${WORK_DIR}/build/flat_ground_map)

# pkg-config: the flags alone must compile, link and (shared) run the example.
file(GLOB pc_file ${prefix}/*/pkgconfig/stridemap.pc ${prefix}/*/*/pkgconfig/stridemap.pc)
if(NOT pc_file)
  message(FATAL_ERROR "no stridemap.pc installed under ${prefix}")
endif()
get_filename_component(pc_dir "${pc_file}" DIRECTORY)
get_filename_component(lib_dir "${pc_dir}" DIRECTORY)
run_step(${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} pkg-config --cflags --libs stridemap OUTPUT pc_flags)
string(STRIP "${pc_flags}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
if(NOT "${pc_flags}" MATCHES "-lstridemap_core")
  message(FATAL_ERROR "pkg-config --libs stridemap lacks -lstridemap_core: ${pc_flags}")
endif()
run_step(${CXX_COMPILER} -std=c++20 -O1 ${SOURCE_DIR}/examples/consumer/flat_ground_map.cpp ${pc_flags}
  -Wl,-rpath,${lib_dir} -o ${WORK_DIR}/flat_ground_map_pkgconfig)
run_step(${WORK_DIR}/flat_ground_map_pkgconfig)

# The installed tool, run from a folder that holds no scenes/: its default
# scene comes from <prefix>/share/stridemap.
file(MAKE_DIRECTORY ${WORK_DIR}/elsewhere)
run_step(${prefix}/bin/stridemap soak --scans 20 --out ${WORK_DIR}/elsewhere/out IN ${WORK_DIR}/elsewhere OUTPUT soak_out)
if(NOT EXISTS ${WORK_DIR}/elsewhere/out/soak/summary.json)
  message(FATAL_ERROR "the installed stridemap soak wrote no summary:\n${soak_out}")
endif()
file(READ ${WORK_DIR}/elsewhere/out/soak/summary.json summary)
if(NOT summary MATCHES "share/stridemap/scenes/soak_circuit.yaml")
  message(FATAL_ERROR "the installed tool did not take its scene from the prefix:\n${summary}")
endif()
foreach(shipped scenes/rocky_mockup.yaml configs/urg_messor.yaml)
  if(NOT EXISTS ${prefix}/share/stridemap/${shipped})
    message(FATAL_ERROR "${shipped} is not installed under ${prefix}/share/stridemap")
  endif()
endforeach()
