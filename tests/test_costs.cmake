# Read by ctest after the discovered tests (tests/ and ros/tests/CMakeLists.txt;
# configured into the build folder). A fresh build folder has no record of
# how long each test took, so ctest would start tests in the order they were
# declared and the longest could start last, leaving one core busy and the
# other idle at the end of the run. These hints, seconds measured in the
# Release build and in the ASan + UBSan build (docs/reliability.md, "The
# check's time"), start the longest first; they change the order, never
# what runs. A test missing from a build (the sanitizer, TSan and ARM stages
# build fewer programs) is passed over. Tests declared with add_test in
# tests/CMakeLists.txt carry their COST there: this file is read before them.
set(stridemap_sanitized_build @STRIDEMAP_TESTS_SANITIZED@)
#   test                                                                      Release  sanitizer
set(stridemap_test_costs
  AttitudeCalibration.FindsTheImuBiasesOnAFlatFloorDespiteTheNoise              2   108
  FidelityCommand.TwoScenesGiveDistributionsInSummary                           3    65
  Fidelity.OneSceneGivesEveryFigureAndIsDeterministic                           3    58
  RockyWalkCommand.WritesMapsViewsSummaryAndTable                               2    58
  MixedPixelsExperiment.MixedPixelsAppearAndThePaperChainRemovesSome            2    56
  LongWalk.TenThousandScansKeepMemoryConstantAndTheMapValid                     1    49
  CartRailStructuredLight.ImagePathMapsTheBoxLikeTheGeometricTruth              3    44
  StructuredLightWalk.FigureFiveMountsRankAsSectionThreeThreeSays               2    38
  LiveCrash.KilledAtFiftyRandomMomentsLeavesCompleteOutputsAndLogsThatReplay    41   38
  MountAnalysisCommand.WritesHeatMapsAndNamesTheBestMount                       2    35
  MountAnalysis.ThePapersUrgMountsRankAsSectionFourTwoArgues                    1    34
  FillReference.FastFillMatchesTheReferenceBitForBit                            2    30
  MixedPixelsCommand.WritesTheComparison                                        2    26
  Soak.SameSeedSameMapsBitForBitAndAnotherSeedDiffers                           1    19
  RockyWalkCommand.StructuredLightVariantUsesFineCellsAndCas                    2    18
  TerminalOutput.PipedStderrGetsNoProgressBar                                   1    17
  LightingExperiment.DaylightDrownsTheStripeAndLeavesTheUrgAlone                1    17
  StructuredLightCli.CalibrationFromSimulatedTargetsRecoversBaselineAndSheetAngle 3  16
  StructuredLightCli.CartRailAndLightingExperiments                             2    15
  Soak.ShortRunLosesNothingAndKeepsEveryCellValid                               1    14
  CartRailStructuredLight.DeterministicForASeed                                 1    14
  StructuredLightWalk.MapsTheMockUpPreciselyWithAPerfectPose                    1    14
  CartRailCommand.TheReceiverCouplingIsOnWithMixedPixelsUnlessTurnedOff         2    13
  RockyWalk.TheMockUpIsMappedAndTheErrorGrowsWithThePoseError                   1    13
  Soak.TheWalkingRobotLosesNothingEither                                        1    12
  LiveAllocation.LiveLoopOnTheEmulatorAllocatesNothingPerScan                   6     6
  OutputSafety.InterruptedExperimentLeavesThePreviousResultsWhole               3     6
  GlobalMapCli.LiveMakesTheTilesItsReplayMakesAndRefusesAFile                   3     5
  LiveCli.DeviceThatIsNoUrgIsAClearError                                        4     4
  # ros/tests (Release only): one roscore at a time, so one after another
  RosNodeTest.BadCloudsAreCountedAndReportedNeverFatal                          11    0
  RosNodeTest.BadMessagesAreCountedAndReportedNeverFatal                        9     0
  RosNodeTest.MapsStripeCloudsLikeTheTruthAndLikeMapBagBitForBit                8     0
  RosNodeTest.MapsSimulatedScansLikeTheTruthAndLikeMapBagBitForBit              7     0
  RosNodeTest.PosesFromAnOdometryTopicGiveMapBagsMapBitForBit                   5     0)
# ctest passes over a name it does not know (and its if() has no TEST test).
while(stridemap_test_costs)
  list(POP_FRONT stridemap_test_costs name release_s sanitizer_s)
  if(stridemap_sanitized_build)
    set_tests_properties(${name} PROPERTIES COST ${sanitizer_s})
  else()
    set_tests_properties(${name} PROPERTIES COST ${release_s})
  endif()
endwhile()

# Tests that spend most of their time waiting (the tool live against the
# emulator in real time, roscore and the node), with the label of their
# program: `waits` added, tools/ctest-lanes.sh runs them beside the others
# (docs/reliability.md, "The check's time"). Not the browser test: its
# timings of the 3D view went wrong with four processes on two cores.
set(stridemap_waiting_tests
  LiveCrash.KilledAtFiftyRandomMomentsLeavesCompleteOutputsAndLogsThatReplay    cli
  RosNodeTest.TheReadmesDemoLinePublishesTheGridMapAndTheOccupancyGrid          ros
  RosNodeTest.MapsStripeCloudsLikeTheTruthAndLikeMapBagBitForBit                ros
  RosNodeTest.BadCloudsAreCountedAndReportedNeverFatal                          ros
  RosNodeTest.MapsSimulatedScansLikeTheTruthAndLikeMapBagBitForBit              ros
  RosNodeTest.BadMessagesAreCountedAndReportedNeverFatal                        ros
  RosNodeTest.PosesFromAnOdometryTopicGiveMapBagsMapBitForBit                   ros
  RosNodeTest.ABadQueueSizeStopsTheNodeNamingTheParameter                       ros
  RosNodeTest.AnUnknownOccupancyLayerStopsTheNodeNamingTheParameter             ros
  RosNodeTest.AParameterOfTheWrongTypeOrRangeOrNameStopsTheNodeNamingIt         ros)
while(stridemap_waiting_tests)
  list(POP_FRONT stridemap_waiting_tests name program_label)
  set_tests_properties(${name} PROPERTIES LABELS "${program_label};waits")
endwhile()
