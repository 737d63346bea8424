#!/usr/bin/env bash
# One device call (about 2.5 minutes), after `bash ../shared/tools/device_bundle.sh` and copying
# the earlier program to .dev/bin/ishibashi_before: carry [".dev"].
# Model F dry, implicit dashpots at 4e-5 s, 0.02 s settling + 0.05 s from 7.3 s, fixed teams:
# dec2bc0 (before) and this program alternated twice at 1 and 16 threads; then 2, 4, 8.
set -u
D=$PWD/.dev; export LD_LIBRARY_PATH=$D/lib
O=${OUT:-/tmp/device_out}; mkdir -p "$O"
cd "$D/main"
sed -e 's/^settle_max_s = .*/settle_max_s = 0.02/' scenarios/nishida_f_kobe_dry.toml > scenarios/bench_f.toml
f_run() {
  local bin=$1 t=$2 label=$3; shift 3
  timeout 120 "$D/bin/$bin" run scenarios/bench_f.toml --start 7.3 --duration 0.05 --threads "$t" --fixed-threads --quiet \
    --profile --out "/tmp/$label" --damping implicit --dt 4e-5 > "/tmp/$label.log" 2>&1
  { echo "=== $label: $bin, $t threads"; cat "/tmp/$label.log"; } >> "$O/profiles.log"
  echo "$label,$bin,$t,$(grep -o '[0-9.]* steps/s' /tmp/$label.log | head -1 | cut -d' ' -f1),$(grep -E '^(gather[+])?damping solve' /tmp/$label.log | awk '{print $3}'),$(grep '^contact law' /tmp/$label.log | awk '{print $4}'),$(grep -o '"state_hash": "[0-9a-f]*"' /tmp/$label/summary.json | cut -d'"' -f4)" >> "$O/runs.csv"
}
echo "label,program,threads,steps_per_s,solve_s,contact_law_s,state_hash" > "$O/runs.csv"
for rep in 1 2; do for t in 1 16; do for b in ishibashi_before ishibashi; do f_run $b $t "${b}_${t}_$rep"; done; done; done
for t in 2 4 8; do f_run ishibashi $t "ishibashi_$t"; done
cat "$O/runs.csv"
