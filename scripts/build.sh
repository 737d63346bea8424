#!/usr/bin/env bash
# Installs what is missing (scripts/setup.sh), then configures and builds ishibashi
# (Release) into build/. Extra arguments go to CMake, e.g. -DISHIBASHI_NATIVE=ON.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" > "$root/build.cmake.log" 2>&1 ||
  { cat "$root/build.cmake.log"; exit 1; }
cmake --build "$root/build" --parallel "$(nproc)"
