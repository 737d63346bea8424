#!/usr/bin/env bash
# Whole-run benchmark, scene 2: Nishida model F (2,002 stones) shaken by the Kobe record,
# on 1 and 2 threads, through `ishibashi run --profile` (settling, shaking, outputs).
# Usage: perf/bridge_benchmark.sh [SHAKING_S] [SETTLE_S]   (defaults 0.5 and 0.05:
# a sample of the run; 10 s of shaking is SHAKING_S=10 SETTLE_S=1.0, the scenario's own).
# Prints one CSV row per thread count and extrapolates the wall time of 10 s of shaking.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
shaking=${1:-0.5}
settle=${2:-0.05}
exe="$root/build/apps/ishibashi"
[ -x "$exe" ] || { echo "build first: bash scripts/build.sh" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The scenario with absolute paths and the settling time of this benchmark.
sed -e "s#\"\.\./#\"$root/#g" -e "s#^settle_max_s = [0-9.]*#settle_max_s = $settle#" \
  "$root/scenarios/nishida_f_kobe_dry.toml" > "$work/scenario.toml"
echo "threads,blocks,subcontacts,dt_s,steps,wall_s,steps_per_s,shaking_s,extrapolated_10s_min"
for threads in 1 2; do
  log="$work/log_$threads.txt"
  "$exe" run "$work/scenario.toml" --out "$work/out_$threads" --duration "$shaking" --threads "$threads" \
    --quiet --profile > "$log"
  python3 - "$log" "$work/out_$threads/summary.json" "$threads" "$shaking" <<'PY'
import json, re, sys
log, summary, threads, shaking = open(sys.argv[1]).read(), json.load(open(sys.argv[2])), sys.argv[3], float(sys.argv[4])
blocks, subcontacts = re.search(r"(\d+) blocks, (\d+) sub-contacts", log).groups()
rate = summary["steps"] / summary["wall_time_s"]
minutes = 10.0 / summary["dt_s"] / rate / 60
print(f'{threads},{blocks},{subcontacts},{summary["dt_s"]:.4g},{summary["steps"]},{summary["wall_time_s"]:.1f},{rate:.0f},{shaking},{minutes:.1f}')
PY
  sed -n '/^stage/,/^steps/p' "$log" | sed 's/^/# /'
done
