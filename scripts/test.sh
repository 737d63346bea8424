#!/usr/bin/env bash
# Installs, builds and runs every test (ctest). This is what CI runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh"
# Tests that use threads must not fight ctest's own parallelism: run tests one by one,
# each with both cores.
# The half-hour preset hashes (label long) run with scripts/preset_hashes.sh.
cd "$root/build" && ctest --output-on-failure --timeout 600 -LE long
