# Run by the test layering_upward_include: builds each probe of PROBES
# (comma-separated) in BUILD_DIR on its own. Every one must fail, and
# because a header was not found: a probe that failed for another reason
# (a typo, a broken library) would prove nothing about the layering.
string(REPLACE "," ";" probes "${PROBES}")
foreach(probe IN LISTS probes)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target ${probe}
    RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(result EQUAL 0)
    message(FATAL_ERROR "${probe} compiled: its layer sees a header of a layer it does not link")
  endif()
  if(NOT output MATCHES "No such file or directory|file not found")
    message(FATAL_ERROR "${probe} failed, but not for a missing header:\n${output}")
  endif()
  message(STATUS "${probe}: refused, as it should be")
endforeach()
