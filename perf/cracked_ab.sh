#!/usr/bin/env bash
# Model B dry in its cracked phase: 0.05 s of settling, then SHAKE seconds (default 0.2) of
# Kobe from the record's 7.3 s, where its joints crack and rock (a pair regroups its
# sub-contacts in about half the steps: the calm samples of implicit_ab.sh miss this
# phase). Programs BEFORE and AFTER alternated ROUNDS times on THREADS threads (fixed
# teams), each with the study's explicit dashpots and with implicit dashpots at 4e-5 s.
# One CSV row per run; the stage columns are work us a step from --profile (profile_row.awk). On a shared
# machine pause other work first and quote medians of back-to-back runs.
#   bash perf/cracked_ab.sh BEFORE AFTER [ROUNDS] [THREADS] [SHAKE] > perf/results/cracked_ab.csv
set -eu
BEFORE=$1 AFTER=$2 ROUNDS=${3:-3} THREADS=${4:-2} SHAKE=${5:-0.2}
PERF=$(cd "$(dirname "$0")" && pwd)
SCENARIO=$PERF/../scenarios/nishida_b_kobe_dry.toml
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
source "$PERF/profile_run.sh"
run() {  # label program extra-flags...
  local label=$1 program=$2 row; shift 2
  row=$(profiled_run "$program" "$SCENARIO" --settle-max 0.05 --start 7.3 --duration "$SHAKE" --threads "$THREADS" \
    --fixed-threads "$@")
  echo "$label,$round,$THREADS,$row"
}
echo "run,round,threads,steps_per_s,pose_us,narrowphase_us,contact_law_us,gather_us,solve_us,integrate_us,regroups,solve_serial_pct,state_hash"
for round in $(seq "$ROUNDS"); do
  run before_explicit "$BEFORE"
  run after_explicit "$AFTER"
  run before_implicit "$BEFORE" --damping implicit --dt 4e-5
  run after_implicit "$AFTER" --damping implicit --dt 4e-5
done
