#!/usr/bin/env bash
# Installs, builds and runs the main job, writing ParaView output. For now the main job
# is the demo (a masonry wall on a shaking base); arguments go to `ishibashi demo`.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh"
"$root/build/apps/ishibashi" demo --out "$root/out/demo" "$@"
