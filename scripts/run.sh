#!/usr/bin/env bash
# Installs, builds and runs the main job: Nishida model A (dry joints) shaken by the 1995
# Kobe record (10 s from 4 s into the record, all three components), writing ParaView
# output to out/nishida_a_kobe_dry/. Arguments go to `ishibashi run`.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh"
"$root/build/apps/ishibashi" run "$root/scenarios/nishida_a_kobe_dry.toml" --out "$root/out/nishida_a_kobe_dry" "$@"
