# The tests that take more than 15 s on the project machine (2 cores, the default ctest -j2), with
# their group's label: `ctest -LE slow` leaves them out (about 3 of the suite's ~7 minutes).
# Included by ctest after every test is defined (tests/CMakeLists.txt).
set(gdsmc_slow_tests
  "Conformance.EveryPluginOfTheBuildConformsBareInTheContextItShips|unit"
  "Poiseuille.RarefiedMolecularGasHasABimodalTemperatureAtKnTenthAndDeltaTPositive|physics"
  "Poiseuille.SlipAtTheWallFromTheFixedReachFitDoesNotMoveWithTheSamplingBins|physics"
  "Poiseuille.ElasticFlowRateAtKnOneAndTheMomentumBalance|physics"
  "Mpi.AJobInterruptedAtTwoRanksResumesAtThreeRanksToTheSerialBits|mpi"
  "HeatFlux.HeatFluxIsLinearInTheField|physics"
  "HeatFlux.ElasticConductivityIsTheConvergedSonineValueAndBothSonineRoutesAgree|physics"
  "ProfilesFourierLaw.ElasticFourierFlowConductsAsChapmanEnskogSays|physics"
  "slab_physics.LeesEdwardsSteadyRheologyEqualsTheHomogeneousEngine|physics"
  "Checkpoint.SigintSavesTheStateAndAForeignCheckpointIsRefusedNamingWhatDiffers|unit"
  "Checkpoint.ALeesEdwardsSweepWithRealizationsKilledThreeTimesAndResumedIsTheSameBits|unit"
  "HcsPhysics.HaffLawAlpha05|physics"
  "usf_physics.EhsSteadyEnergyBalanceWithZeta0AndIndependenceOfTheShearRate|physics")
foreach(entry IN LISTS gdsmc_slow_tests)
  string(REPLACE "|" ";" parts "${entry}")
  list(GET parts 0 test)
  list(GET parts 1 group)
  set_tests_properties("${test}" PROPERTIES LABELS "${group};slow")
endforeach()
