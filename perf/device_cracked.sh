#!/usr/bin/env bash
# One device call (about 4 minutes), after `bash ../shared/tools/device_bundle.sh`: carry [".dev"].
# Model B dry in its cracked phase (perf/cracked_ab.sh's window: 0.05 s of settling, 0.1 s of
# Kobe from the record's 7.3 s, where its joints crack and regroup every other step), the
# study's explicit dashpots and implicit ones at 4e-5 s, fixed teams of 1, 2, 4, 8 and 16:
# the per-stage scaling of the phase a shaken bridge spends its run in (issues 45 and 47).
# Writes $OUT/runs.csv (steps/s and work us a step per stage) and $OUT/profiles.log.
set -u
R=$PWD; D=$R/.dev; export LD_LIBRARY_PATH=$D/lib
O=${OUT:-/tmp/device_out}; mkdir -p "$O"
cd "$D/main"
b_run() {
  local t=$1 label=$2; shift 2
  timeout 150 "$D/bin/ishibashi" run scenarios/nishida_b_kobe_dry.toml --settle-max 0.05 --start 7.3 --duration 0.1 \
    --threads "$t" --fixed-threads --quiet --profile --out "/tmp/$label" "$@" > "/tmp/$label.log" 2>&1
  { echo "=== $label: $t threads $*"; cat "/tmp/$label.log"; } >> "$O/profiles.log"
  echo "$label,$t,$(awk -f "$R/perf/profile_row.awk" "/tmp/$label.log")" >> "$O/runs.csv"
}
echo "label,threads,steps_per_s,pose_us,narrowphase_us,contact_law_us,gather_us,solve_us,integrate_us,regroups,solve_serial_pct" > "$O/runs.csv"
for t in 1 2 4 8 16; do
  b_run "$t" "explicit_$t"
  b_run "$t" "implicit_$t" --damping implicit --dt 4e-5
done
cat "$O/runs.csv"
