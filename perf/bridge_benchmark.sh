#!/usr/bin/env bash
# Whole-run benchmark, scene 2: Nishida model F (2,002 stones; MODEL=a..e for the others)
# shaken by the Kobe record, on 1 and 2 threads, through `ishibashi run --profile`
# (settling, shaking, outputs).
# Usage: perf/bridge_benchmark.sh [SHAKING_S] [SETTLE_S]   (defaults 0.5 and 0.05:
# a sample of the run; 10 s of shaking is SHAKING_S=10 SETTLE_S=1.0, the scenario's own).
# Prints one CSV row per thread count (THREADS="1 2" by default) and extrapolates the wall
# time of 10 s of shaking.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
shaking=${1:-0.5}
settle=${2:-0.05}
exe="${ISHIBASHI:-$root/build/apps/ishibashi}"  # ISHIBASHI=another build: compare two back to back
[ -x "$exe" ] || { echo "build first: bash scripts/build.sh" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The scenario with absolute paths and the settling time of this benchmark.
sed -e "s#\"\.\./#\"$root/#g" -e "s#^settle_max_s = [0-9.]*#settle_max_s = $settle#" \
  "$root/scenarios/nishida_${MODEL:-f}_kobe_dry.toml" > "$work/scenario.toml"
echo "threads,blocks,subcontacts,dt_s,steps,wall_s,steps_per_s,shaking_s,extrapolated_10s_min,ns_per_subcontact_step"
for threads in ${THREADS:-1 2}; do
  log="$work/log_$threads.txt"
  # RUN_ARGS: more options of `ishibashi run`, e.g. RUN_ARGS="--joint-rule moments"
  # shellcheck disable=SC2086
  "$exe" run "$work/scenario.toml" --out "$work/out_$threads" --duration "$shaking" --threads "$threads" \
    --quiet --profile ${RUN_ARGS:-} > "$log"
  # summary.json's top-level value (its "settings" come last and repeat a few names)
  field() { sed -n "s/^  \"$1\": \([0-9.e+-]*\).*/\1/p" "$work/out_$threads/summary.json" | head -1; }
  counts=$(sed -n 's/.*: \([0-9]*\) blocks, \([0-9]*\) sub-contacts.*/\1,\2/p' "$log")
  awk -v t="$threads" -v c="$counts" -v dt="$(field dt_s)" -v steps="$(field steps)" -v wall="$(field wall_s)" \
    -v shaking="$shaking" 'BEGIN { rate = steps / wall;
      split(c, n, ","); printf "%s,%s,%.4g,%d,%.1f,%.0f,%s,%.1f,%.1f\n", t, c, dt, steps, wall, rate, shaking,
      10 / dt / rate / 60, 1e9 / rate / n[2] }'
  sed -n '/^stage/,/^steps/p' "$log" | sed 's/^/# /'
done
