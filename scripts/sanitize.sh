#!/usr/bin/env bash
# Builds the tests a second time with AddressSanitizer and UndefinedBehaviorSanitizer
# (into build-sanitize/) and runs them; any finding fails the run (about 16 minutes to
# build on 2 cores, so CI leaves it out; run it before a release). The slowest tests (seconds in Release, minutes under the sanitizers: the
# arch ring standing 13 minutes, 200 random drops 4) are left out; the shorter ones run
# the same code (the step, the contact law, the readers and writers, a seismic run; the
# analysis tests are not built):
#   ArchRing.*Stands*, Impact.EdgeAndCornerDrops*, Impact.RandomDrops*, LimitState.*,
#   Checkpoint.*, Sweep.*, Study.*, SeismicRun.*, Run.InterruptedRunLeavesValidFiles
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
build="$root/build-sanitize"
# -O1: the sanitizers' reports stay exact and the build (CGAL, VTK headers) stays short.
flags="-O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=None -DISHIBASHI_BUILD_PERF=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" > /dev/null
# The physics, geometry and file tests, the program they run and the fuzz corpus replay;
# the end-to-end analyses (study, sweeps, checkpoints: minutes of runs) are left out.
cmake --build "$build" --target engine_tests io_tests replay_corpus ishibashi
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$root/scripts/ubsan.supp
cd "$build" && ctest --output-on-failure --timeout 900 \
  -E 'ArchRing\..*Stands|Impact.EdgeAndCornerDrops|Impact.RandomDrops|LimitState\.|Checkpoint\.|Sweep\.|Study\.|SeismicRun\.|Fragility\.|Run.InterruptedRun|NOT_BUILT'
