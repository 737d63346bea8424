#!/usr/bin/env bash
# The state hash of every preset after settling and 0.2 s of Kobe against
# tests/data/preset_hashes.txt (about half an hour on two cores): run it before committing a
# refactor of the engine or the run driver, which must keep every hash bit for bit.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh"
cd "$root/build" && ctest --output-on-failure -L long
