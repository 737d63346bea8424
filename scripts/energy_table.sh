#!/usr/bin/env bash
# The trust table of the presets: each scenario through the strong motion of the Kobe
# record (from START s, DURATION s of shaking), one row per run with the energy balance
# error (of the energy exchanged), the error until the first stone fell, the first
# opening, the crown drop and the outcome. Builds first.
#   bash scripts/energy_table.sh [OUT_CSV] [scenario names...]
# e.g. bash scripts/energy_table.sh perf/results/energy.csv nishida_d_kobe_dry nishida_e_kobe_dry
# Environment: START (6), DURATION (5), THREADS (0: all cores), EXTRA (more `run` options).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
table=${1:-$root/out/energy_table.csv}
shift || true
scenarios=("$@")
if [ ${#scenarios[@]} -eq 0 ]; then
  for m in a b c d e f; do scenarios+=("nishida_${m}_kobe_dry" "nishida_${m}_kobe_mortar"); done
fi
bash "$root/scripts/build.sh" > /dev/null
start=${START:-6} duration=${DURATION:-5} threads=${THREADS:-0}
mkdir -p "$(dirname "$table")"
[ -f "$table" ] || echo "scenario,start_s,duration_s,dt_s,balance_error_pct,balance_error_before_first_fall_pct,first_opening_s,crown_drop_m,joints_cracked,fallen_stones,blocks_left_model,collapse,wall_s" > "$table"
mkdir -p "$root/out/energy"
for name in "${scenarios[@]}"; do
  out="$root/out/energy/$name"
  # shellcheck disable=SC2086
  "$root/build/apps/ishibashi" run "$root/scenarios/$name.toml" --out "$out" --start "$start" --duration "$duration" \
    --threads "$threads" --quiet ${EXTRA:-} > "$out.log" 2>&1 || { echo "$name failed: $(tail -3 "$out.log")"; continue; }
  python3 - "$out" "$name" "$start" "$duration" >> "$table" <<'PY'
import csv, json, sys
out, name, start, duration = sys.argv[1:5]
s = json.load(open(out + "/summary.json"))
rows = [r for r in csv.DictReader(open(out + "/history.csv"))]
def exchanged(r):
    return sum(abs(float(r[k])) for k in ("ground_work_j", "damping_j", "friction_j", "bond_j"))
before = [r for r in rows if int(r["fallen_blocks"]) == 0]
last = before[-1]
early = 100 * float(last["balance_error_j"]) / max(exchanged(last), 1e-30)
print("%s,%s,%s,%.4g,%.3f,%.3f,%s,%.4f,%d,%d,%d,%s,%.0f" % (
    name, start, duration, s["dt_s"], 100 * s["energy_balance_error_relative"], early,
    "none" if s["first_opening_time_s"] is None else "%.3f" % s["first_opening_time_s"],
    s["largest_crown_drop_m"], s["joints_cracked"], s["fallen_stones"], s["blocks_left_model"],
    "yes" if s["collapse"] else "no", s["wall_time_s"]))
PY
  tail -1 "$table"
done
