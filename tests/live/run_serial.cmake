# Read by ctest after the discovered tests (tests/CMakeLists.txt): the test
# that keeps every core busy on purpose runs alone, so that it neither
# starves the timing-sensitive tests beside it (the live loop at 100 scans a
# second) nor is disturbed by them.
set_tests_properties(LoadedHost.NoFalseFaultAndNoScanLostWithEveryCoreBusy PROPERTIES RUN_SERIAL TRUE)
