#!/usr/bin/env bash
# Builds the libraries and the program a second time with AddressSanitizer and
# UndefinedBehaviorSanitizer (into build-sanitize/), links the Release build's objects of the
# tests to them (CMakeLists.txt, ishibashi_plain_objects), and runs the tests; any finding
# fails the run. CI runs it after the Release tests (about 6 minutes to build and 2 to run on
# 2 cores). Left out, because
# each takes minutes under the sanitizers (seconds in Release) and runs the same code as a
# shorter test that stays in:
#   ArchRing.*Stands* (13 min), Impact.EdgeAndCornerDrops* and Impact.RandomDrops* (4 min),
#   LimitState.*, the presets B-F's CGAL validation (Presets.*nishida_[b-f]: CGAL code,
#   compiled plain), and the end-to-end analyses, each several seismic runs (more than
#   4 min each): SeismicRun.*, Study.QuickStudy* and Study.Interrupted* (two quick studies
#   each), Sweep.*, Checkpoint.* (the checkpoint
#   test also stops a run after 3 s, before a run under the sanitizers has settled).
#   Determinism.*OneToFourThreads (75 s each): the same steps on 1 to 4 threads, compared
#   bit for bit in the Release run; the team-size change test stays.
#   PresetHashes.* (the twelve presets, a minute in Release): the program path of SeismicRun.
#   BondBending.BondedWall* (1-4 min each): the pillar tests' code on a wall of 24 stones.
#   Run.ShortSeismicRun* stays: the program's whole run path, VTK output included.
#   Run.ProfileTableAndTrace* (40 s): the same run path with --profile and --trace, whose
#   engine and writer code ChromeTrace.* runs under the sanitizers.
#   Ensemble.PerturbedBridge* (5 min) and Ensemble.RunMembers* (4 min: model A's members):
#   the members' folders, resumption and outcome tables run under the sanitizers in
#   ChaosProbe.BlockSliding* (a stone on a slab), the draws in Ensemble.MembersDraw*.
#   Study.RunsAsEnsembles* (a study of two members and its report): the same code.
#   Study.RunSettingsOnTheCommandLine* (three short studies of model A): the overrides'
#   plain code, the run path of Run.ShortSeismicRun*.
#   Ensemble.Mpirun*, Study.Mpirun* and ChaosProbe.Mpirun*: runs on one machine and under
#   mpirun, as Sweep.* (OpenMPI's own allocations would be reported as leaks); the runs'
#   code stays in Run.ShortSeismicRun* and ChaosProbe.BlockSliding*.
#   Run.FinerFrames* (5 min: two runs of model A that differ in their frames only) and
#   Impulse.FaceUnitBesideTheCrown* (1 min): the run and impulse paths of
#   Run.ShortSeismicRun* and the other Impulse.* tests, which stay.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# The Release build first (nothing to do after scripts/test.sh): the sanitizer build links
# its objects of the tests and of the CGAL-heavy files.
bash "$root/scripts/build.sh"
build="$root/build-sanitize"
# ISHIBASHI_SANITIZE: -O1 -g1 with both sanitizers.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=None -DISHIBASHI_BUILD_PERF=OFF \
  -DISHIBASHI_SANITIZE=ON -DISHIBASHI_PLAIN_OBJECTS="$root/build" > /dev/null
cmake --build "$build" --target engine_tests step_allocation_tests io_tests analysis_tests replay_corpus ishibashi
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd "$build" && ctest --output-on-failure --timeout 600 -j 2 \
  -E 'PresetHashes\.|ArchRing\..*Stands|Impact\.EdgeAndCornerDrops|Impact\.RandomDrops|LimitState\.|Presets\..*nishida_[b-f]|SeismicRun\.|Study\.(QuickStudy|Interrupted|RunsAsEnsembles|RunSettingsOnTheCommandLine|Mpirun)|Sweep\.|Checkpoint\.|Determinism\..*OneToFourThreads|BondBending\.BondedWall|Run\.ProfileTableAndTrace|Ensemble\.(PerturbedBridge|RunMembers|Mpirun)|ChaosProbe\.Mpirun|Run\.FinerFrames|Impulse\.FaceUnitBesideTheCrown'
