# How ctest -j packs the gtest cases; read after their discovered lists (a name this build does not
# have, Bullet's tests without Bullet, is ignored).
# PROCESSORS 2: the cases that step one model on two or three threads. Beside another test on a
# two-core machine their threads wait at every barrier for a core (a case of 2 s of CPU took 55 s
# of wall time); alone they take their CPU time.
set_tests_properties(
  PlausibleScale.ThreadCountDoesNotChangeTheResult
  PlausibleScale.BandedSweepGivesTheColouredSweepsBits
  PlausibleScale.VectorLanesGiveTheScalarBitsOnEveryWeave
  TorusXpbd.OneAndTwoThreadsGiveTheSameHash
  Run.ThreadCountChangesNeitherTheResultNorWhatIsRecorded
  PROPERTIES PROCESSORS 2)
# COST: the longest first, so that a fresh build (no cost data yet) does not end on one of them
# with the other core idle; their seconds beside another test on a busy two-core machine (the
# rest cost 0 and follow in order)
foreach(cost IN ITEMS
    PlausibleScale.LargeHangingSheetKeepsItsLinksWithinTheRings=62
    Bullet.CurtainHangsWithoutBrokenOrFalseLinks=46
    PlausiblePhysics.NoLinkBeyondTheRingsOnAnyBenchScene=44
    Bullet.ChainSagMatchesCatenary=39
    Bench.QuickModeWritesEveryResultsFile=31
    Render.ThinWiresDoNotShimmerUnderSubPixelMotion=26
    Cli.UnstableRunExitsOneWithItsVerdictWritten=20
    OdeBackend.CurtainKeepsItsLinks=20
    RenderCli.RedrawsTheRunsOwnImagesByteForByteAndAtOtherSizes=16
    Run.InjectedInstabilityIsReportedNotCrashed=13
    Bullet.SheetRestsOnPlaneWithoutJitter=11
    TorusXpbd.ASheetHungFromTwoCornersHoldsItsLinksShallowerThanTheCapsuleReferences=11
    RenderCli.BackendsListOrdersThePanels=10
    OdeBackend.ChainHangsAsACatenary=9
    Cli.LongRunStaysWithinAMemoryLimitTheOldRunnerExceeded=9)
  string(REPLACE "=" ";" cost "${cost}")
  list(GET cost 0 name)
  list(GET cost 1 seconds)
  set_tests_properties(${name} PROPERTIES COST ${seconds})
endforeach()
