# Sourced by the A/B scripts (cracked_ab.sh, window_ab.sh): profiled_run PROGRAM ARGS...
# runs `PROGRAM run ARGS --profile --quiet` into $OUT/run and prints the CSV fragment of
# profile_row.awk (steps/s, work us a step by stage, regroups) and the end state's hash.
# Needs OUT (a scratch folder) and PERF (this folder). A failed run returns 1: call it as
# `row=$(profiled_run ...)` under set -e so that the script stops.
profiled_run() {
  local program=$1 hash
  shift
  "$program" run "$@" --profile --quiet --out "$OUT/run" > "$OUT/log" 2>&1 ||
    { echo "$program failed:" >&2; tail -3 "$OUT/log" >&2; return 1; }
  hash=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['state_hash'])" "$OUT/run/summary.json")
  echo "$(awk -f "$PERF/profile_row.awk" "$OUT/log"),$hash"
}
