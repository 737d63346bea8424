#!/usr/bin/env bash
# Model F dry's window on this machine (0.02 s of settling, 0.03 s from the record's 7.3 s,
# the strongest pulses; the study's explicit dashpots unless EXTRA says otherwise), fixed
# teams, --profile: programs BEFORE and AFTER alternated ROUNDS times on each thread count
# in THREADS ("2+busy": 2 threads beside a busy process, the issue's shared machine). One
# CSV row per run; the stage columns are work us a step (profile_row.awk).
# On a shared machine pause other work first and quote medians of back-to-back runs.
#   bash perf/window_ab.sh BEFORE AFTER [ROUNDS] ["1 2 2+busy"] [EXTRA...] > perf/results/NAME.csv
set -eu
BEFORE=$1 AFTER=$2 ROUNDS=${3:-3} THREADS=${4:-1 2}
shift $(($# < 4 ? $# : 4))
EXTRA=("$@")
PERF=$(cd "$(dirname "$0")" && pwd)
SCENARIO=$PERF/../scenarios/nishida_f_kobe_dry.toml
OUT=$(mktemp -d)
BUSY=
trap 'rm -rf "$OUT"; [ -z "$BUSY" ] || kill "$BUSY"' EXIT
source "$PERF/profile_run.sh"
run() {  # label program threads (N, or N+busy: beside a busy process, `yes`)
  local row threads=${3%+busy}
  if [ "$threads" != "$3" ]; then yes > /dev/null & BUSY=$!; fi
  row=$(profiled_run "$2" "$SCENARIO" --settle-max 0.02 --start 7.3 --duration 0.03 --threads "$threads" --fixed-threads "${EXTRA[@]}")
  if [ -n "$BUSY" ]; then kill "$BUSY"; BUSY=; fi
  echo "$1,$round,$3,$row"
}
echo "run,round,threads,steps_per_s,pose_us,narrowphase_us,contact_law_us,gather_us,solve_us,integrate_us,regroups,solve_serial_pct,state_hash"
for round in $(seq "$ROUNDS"); do
  for t in $THREADS; do
    run before "$BEFORE" "$t"
    run after "$AFTER" "$t"
  done
done
