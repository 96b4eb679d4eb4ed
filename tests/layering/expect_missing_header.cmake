# Run by the test layering_upward_include: builds every probe of PROBES in
# BUILD_DIR in one run of the build tool that keeps going past failures
# (KEEP_GOING, the tool's flag). PROBES is a comma-separated list of
# target:source:header. Every probe must fail, and because the compiler did
# not find that header in that source: a probe that failed for another
# reason (a typo, a broken library) would prove nothing about the layering.
string(REPLACE "," ";" probes "${PROBES}")
string(REPLACE "," ";" keep_going "${KEEP_GOING}")
set(targets "")
foreach(probe IN LISTS probes)
  string(REPLACE ":" ";" fields "${probe}")
  list(GET fields 0 target)
  list(APPEND targets ${target})
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target ${targets} -- ${keep_going}
  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(result EQUAL 0)
  message(FATAL_ERROR "every probe compiled: a layer sees a header of a layer it does not link\n${output}")
endif()
foreach(probe IN LISTS probes)
  string(REPLACE ":" ";" fields "${probe}")
  list(GET fields 0 target)
  list(GET fields 1 source)
  list(GET fields 2 header)
  string(REPLACE "." "\\." header_pattern "${header}")
  string(REPLACE "." "\\." source_pattern "${source}")
  if(output MATCHES "Built target ${target}[\r\n]")
    message(FATAL_ERROR "${target} compiled: its layer sees ${header}, a header of a layer it does not link")
  endif()
  # GCC: "...: stridemap/x.hpp: No such file or directory"; clang: "'stridemap/x.hpp' file not found".
  if(NOT output MATCHES "${source_pattern}:[0-9]+:[0-9]+: fatal error: '?stridemap/${header_pattern}'?:? (No such file or directory|file not found)")
    message(FATAL_ERROR "${target} failed, but not for want of stridemap/${header}:\n${output}")
  endif()
  message(STATUS "${target}: stridemap/${header} not found, as it should be")
endforeach()
