#!/usr/bin/env bash
# Installs, builds and runs every test (ctest). This is what CI runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh"
# Tests side by side, one per core: most use one thread, and the threaded ones only compare
# results, which do not depend on the team or its load (the team lends a descheduled
# thread's chunks to the others, engine/team.h); the longest start first (their COST in
# tests/CMakeLists.txt). One by one the tests took 529 s on 2 cores, side by side 370 s.
# The half-hour preset hashes (label long) run with scripts/preset_hashes.sh.
cd "$root/build" && ctest --output-on-failure --timeout 600 -LE long -j "$(nproc)"
