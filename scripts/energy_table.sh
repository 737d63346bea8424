#!/usr/bin/env bash
# Runs of the presets through the strong motion of the Kobe record (from START s,
# DURATION s of shaking), one row per run: the energy balance error (of the energy
# exchanged, at the end and before the first stone fell), the first opening, the crown
# drop at 3 s of shaking and at most, the cracked joints and the outcome. Builds first.
#   bash scripts/energy_table.sh [OUT_CSV] [scenario names...]
# e.g. bash scripts/energy_table.sh out/energy.csv nishida_d_kobe_dry nishida_e_kobe_dry
# Environment: START (6), DURATION (5), THREADS (0: all cores), EXTRA (more `run` options,
# e.g. "--dt-factor 0.5" or "--subdivision 2"), TAG (appended to the run folders' names),
# ISHIBASHI (a program to run instead of building this tree: a copy keeps long runs going
# while the tree is rebuilt). Each run writes a checkpoint every 10 min of wall time: an
# interrupted one goes on with `ishibashi run --resume out/energy/NAME`.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
table=${1:-$root/out/energy_table.csv}
shift || true
scenarios=("$@")
if [ ${#scenarios[@]} -eq 0 ]; then
  for m in a b c d e f; do scenarios+=("nishida_${m}_kobe_dry" "nishida_${m}_kobe_mortar"); done
fi
bin=${ISHIBASHI:-$root/build/apps/ishibashi}
[ -n "${ISHIBASHI:-}" ] || bash "$root/scripts/build.sh" > /dev/null
start=${START:-6} duration=${DURATION:-5} threads=${THREADS:-0}
mkdir -p "$(dirname "$table")" "$root/out/energy"
[ -f "$table" ] || python3 "$root/scripts/run_row.py" --header > "$table"
for name in "${scenarios[@]}"; do
  out="$root/out/energy/$name${TAG:-}"
  # shellcheck disable=SC2086
  "$bin" run "$root/scenarios/$name.toml" --out "$out" --start "$start" --duration "$duration" \
    --threads "$threads" --checkpoint-wall 600 --quiet ${EXTRA:-} > "$out.log" 2>&1 || { echo "$name failed: $(tail -3 "$out.log")"; continue; }
  python3 "$root/scripts/run_row.py" "$out" "$name" "${EXTRA:-}" "$start" "$duration" >> "$table"
  tail -1 "$table"
done
