#!/usr/bin/env bash
# Model F dry, one thread, 0.02 s of settling and 0.03 s from the record's 7.3 s (the
# strongest pulses), fixed teams, --profile: programs BEFORE and AFTER alternated ROUNDS
# times, each with implicit dashpots at 4e-5 s (the solve's tolerance 1e-3, the default,
# and 1e-2) and once a round AFTER with the study's explicit dashpots. Writes one CSV row
# per run to stdout. On a shared machine pause other work first: medians and minima of
# back-to-back runs are the figures to quote.
#   bash perf/implicit_ab.sh BEFORE AFTER [ROUNDS] > perf/results/implicit_ab_issue45.csv
set -eu
BEFORE=$1 AFTER=$2 ROUNDS=${3:-5}
SCENARIO=$(dirname "$0")/../scenarios/nishida_f_kobe_dry.toml
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
run() {  # label program extra-flags...
  local label=$1 program=$2; shift 2
  "$program" run "$SCENARIO" --settle-max 0.02 --start 7.3 --duration 0.03 --threads 1 --fixed-threads --profile --quiet --out "$OUT/run" "$@" > "$OUT/log" 2>&1
  awk -v label="$label" -v round="$round" '
    /^contact law/ {law += $6} /^  contact law part/ {law += $4} /^(gather\+)?damping solve/ {solve = $6}
    /steps\/s/ {for (i = 1; i <= NF; ++i) if ($i == "steps/s,") rate = $(i - 1)}
    /iterations per step/ {iterations = $3}
    END {printf "%s,%s,%s,%s,%s,%s\n", label, round, rate, law, solve, iterations}' "$OUT/log"
}
echo "run,round,steps_per_s,contact_law_us_per_step,solve_us_per_step,iterations_per_step"
for round in $(seq "$ROUNDS"); do
  run before_implicit "$BEFORE" --damping implicit --dt 4e-5
  run after_implicit "$AFTER" --damping implicit --dt 4e-5
  run after_implicit_tolerance_1e-2 "$AFTER" --damping implicit --dt 4e-5 --solve-tolerance 1e-2
  run after_explicit "$AFTER"
done
