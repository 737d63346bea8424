#!/usr/bin/env bash
# One device call (about 4 minutes), from the project root there, after
# `bash ../shared/tools/device_bundle.sh` here and copying this file and the programs compared
# into .dev/ (.dev/bin/ishibashi_before, .dev/bin/ishibashi_tol2): carry [".dev"].
# Model F dry, 0.02 s settling + 0.05 s from the record's 7.3 s, fixed teams, --profile:
# explicit (study) 1..16 threads; implicit dashpots at 4e-5 s 1..16 threads (this program),
# then 1 and 16 threads for the program before this session (before) and tolerance 1e-2 (tol2).
set -u
D=$PWD/.dev; export LD_LIBRARY_PATH=$D/lib
O=${OUT:-/tmp/device_out}; mkdir -p "$O"
lscpu > "$O/cpu.txt"; nproc >> "$O/cpu.txt"
cd "$D/main"
sed -e 's/^settle_max_s = .*/settle_max_s = 0.02/' scenarios/nishida_f_kobe_dry.toml > scenarios/bench_f.toml
f_run() {  # program threads label [extra...]
  local bin=$1 t=$2 label=$3; shift 3
  timeout 120 "$D/bin/$bin" run scenarios/bench_f.toml --start 7.3 --duration 0.05 --threads "$t" --fixed-threads --quiet \
    --profile --out "/tmp/$label" "$@" > "/tmp/$label.log" 2>&1
  { echo "=== $label: $bin, $t threads $*"; cat "/tmp/$label.log"; } >> "$O/profiles.log"
  echo "$label,$bin,$t,$(grep -o '[0-9.]* steps/s' /tmp/$label.log | head -1 | cut -d' ' -f1),$(grep -o '"state_hash": "[0-9a-f]*"' /tmp/$label/summary.json | cut -d'"' -f4)" >> "$O/runs.csv"
}
echo "label,program,threads,steps_per_s,state_hash" > "$O/runs.csv"
for t in 1 2 4 8 16; do f_run ishibashi $t "imp_$t" --damping implicit --dt 4e-5; done
for b in ishibashi_before ishibashi_tol2; do for t in 1 16; do f_run $b $t "imp_${b}_$t" --damping implicit --dt 4e-5; done; done
f_run ishibashi 16 imp_16_again --damping implicit --dt 4e-5
for t in 16 8 4 2 1; do f_run ishibashi $t "exp_$t"; done
cat "$O/runs.csv"
