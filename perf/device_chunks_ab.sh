#!/usr/bin/env bash
# One device call (about 4 minutes) for issue 47: model F dry's window (0.02 s settling,
# 0.05 s from the record's 7.3 s, --profile, fixed teams) on programs put in .dev/bin as
# ishibashi_NAME (after `bash ../shared/tools/device_bundle.sh`), alternated: 16 threads
# three rounds, 8 threads once, one thread once for the first two, and the fast path
# (implicit, 4e-5 s) on 16 threads for the last two. Writes runs.csv and profiles.log.
#   PROGRAMS="before s1 c4 c2" bash .dev/device_chunks_ab.sh
# .dev with several programs is too large to travel beside the tree (64 MiB): pack it with
#   bash perf/device_pack.sh 41911c5=front        (this checkout's program is "main")
# and give the device the command, carrying [".devpack"]:
#   tar xJf .devpack/dev.tar.xz && PROGRAMS="front main" bash .dev/device_chunks_ab.sh
set -u
D=$PWD/.dev; export LD_LIBRARY_PATH=$D/lib
O=${OUT:-/tmp/device_out}; mkdir -p "$O"
nproc > "$O/cpu.txt"; lscpu | grep "Model name" >> "$O/cpu.txt"
cd "$D/main"
sed -e 's/^settle_max_s = .*/settle_max_s = 0.02/' scenarios/nishida_f_kobe_dry.toml > scenarios/bench_f.toml
read -r -a programs <<< "${PROGRAMS:-before s1 c4 c2}"
echo "label,program,threads,damping,steps_per_s,state_hash" > "$O/runs.csv"
f_run() {  # program threads label [extra...]
  local bin=$1 t=$2 label=$3; shift 3
  timeout 120 "$D/bin/ishibashi_$bin" run scenarios/bench_f.toml --start 7.3 --duration 0.05 --threads "$t" --fixed-threads \
    --quiet --profile --out "/tmp/$label" "$@" > "/tmp/$label.log" 2>&1
  { echo "=== $label: $bin, $t threads $*"; cat "/tmp/$label.log"; } >> "$O/profiles.log"
  echo "$label,$bin,$t,${*:-explicit},$(grep -o '[0-9.]* steps/s' "/tmp/$label.log" | head -1 | cut -d' ' -f1),$(grep -o '"state_hash": "[0-9a-f]*"' "/tmp/$label/summary.json" | cut -d'"' -f4)" >> "$O/runs.csv"
}
for round in 1 2 3; do for p in "${programs[@]}"; do f_run "$p" 16 "x16_${p}_$round"; done; done
for p in "${programs[@]}"; do f_run "$p" 8 "x8_$p"; done
for p in "${programs[@]:0:2}"; do f_run "$p" 1 "x1_$p"; done
n=${#programs[@]}
for p in "${programs[@]:n-2:2}" "${programs[@]:n-2:2}"; do f_run "$p" 16 "i16_$p" --damping implicit --dt 4e-5; done
cat "$O/runs.csv"
