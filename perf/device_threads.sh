#!/usr/bin/env bash
# Issue 47's 16-core measurements in one call of the device machine (about 6 minutes),
# from the project's root there, after `bash ../shared/tools/device_bundle.sh` here:
#   cp perf/device_threads.sh .dev/ && [cp OTHER_BUILD/apps/ishibashi .dev/bin/ishibashi_before]
#   device: command "bash .dev/device_threads.sh", carry [".dev"]
# (the tree and .dev travel together, at most 64 MiB: with a second program, pack them
# with perf/device_pack.sh COMMIT=before)
# Writes under $OUT:
#   f_scaling.csv + profiles.log  model F dry, 0.02 s settling and 0.05 s of the strongest
#                                 Kobe pulses (the record's 7.3 s), fixed teams 1..16, with
#                                 run --profile's tables and the end state's hash: the study's
#                                 explicit dashpots, then the fast path (implicit, 4e-5 s); then
#                                 16 threads beside four busy cores, fixed and adaptive team;
#                                 trace_f_16.json: explicit, steps 6000-6020
#   ab.csv                        16 threads, .dev/bin/ishibashi_before (if there) and this
#                                 program alternated twice: the same machine, back to back
#   parallel12.csv                the study's twelve runs side by side, one thread each, 0.1 s
#   wall.csv                      the 1,534-block wall, 1,500 steps, teams 1..16
# A stage's imbalance far above 1 in every stage at once means another process held a
# thread off its core: rerun before comparing.
set -u
D=$PWD/.dev; export LD_LIBRARY_PATH=$D/lib
O=${OUT:-/tmp/device_out}; mkdir -p "$O"
lscpu > "$O/cpu.txt"
cd "$D/main"
sed -e 's/^settle_max_s = .*/settle_max_s = 0.02/' scenarios/nishida_f_kobe_dry.toml > scenarios/bench_f.toml
f_run() {  # program threads label [extra...]: prints the stepping rate and the end state's hash
  local bin=$1 t=$2 label=$3; shift 3
  timeout 150 "$D/bin/$bin" run scenarios/bench_f.toml --start 7.3 --duration 0.05 --threads "$t" --quiet \
    --profile --out "/tmp/$label" "$@" > "/tmp/$label.log" 2>&1
  { echo "=== $label: $bin, $t threads $*"; cat "/tmp/$label.log"; } >> "$O/profiles.log"
  echo "$(grep -o "[0-9.]* steps/s" "/tmp/$label.log" | head -1 | cut -d' ' -f1),$(grep -o '"state_hash": "[0-9a-f]*"' "/tmp/$label/summary.json" | cut -d'"' -f4)"
}
echo "scheme,team,threads,steps_per_s,state_hash" > "$O/f_scaling.csv"
for t in 1 2 4 8 16; do
  extra=(); [ "$t" = 16 ] && extra=(--trace "$O/trace_f_16.json" --trace-steps 6000:6020)
  echo "explicit,fixed,$t,$(f_run ishibashi "$t" "f_$t" --fixed-threads "${extra[@]}")" >> "$O/f_scaling.csv"
done
for t in 1 2 4 8 16; do
  echo "implicit 4e-5,fixed,$t,$(f_run ishibashi "$t" "imp_$t" --fixed-threads --damping implicit --dt 4e-5)" >> "$O/f_scaling.csv"
done
for k in 1 2 3 4; do ( timeout 35 sh -c 'while :; do :; done' ) & done  # four busy cores
echo "explicit beside 4 busy,fixed,16,$(f_run ishibashi 16 f_16_busy_fixed --fixed-threads)" >> "$O/f_scaling.csv"
echo "explicit beside 4 busy,adaptive,16,$(f_run ishibashi 16 f_16_busy_adaptive)" >> "$O/f_scaling.csv"
wait
echo "program,threads,steps_per_s,state_hash" > "$O/ab.csv"
if [ -x "$D/bin/ishibashi_before" ]; then
  for rep in 1 2; do for bin in ishibashi_before ishibashi; do
    echo "$bin,16,$(f_run $bin 16 "ab_${bin}_$rep" --fixed-threads)" >> "$O/ab.csv"
  done; done
fi
for m in a b c d e f; do for v in dry mortar; do
  sed -e 's/^settle_max_s = .*/settle_max_s = 0.02/' "scenarios/nishida_${m}_kobe_${v}.toml" > "scenarios/par_${m}_${v}.toml"
  ( timeout 200 "$D/bin/ishibashi" run "scenarios/par_${m}_${v}.toml" --start 7.3 --duration 0.1 --threads 1 --quiet \
      --out "/tmp/p_${m}_${v}" > /dev/null 2>&1 ) &
done; done
wait
echo "run,dt_s,steps,wall_s,steps_per_s,extrapolated_10s_min" > "$O/parallel12.csv"
for m in a b c d e f; do for v in dry mortar; do
  python3 - "${m}_${v}" "/tmp/p_${m}_${v}/summary.json" >> "$O/parallel12.csv" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[2])); r = s['steps'] / s['wall_s']
    print(f"{sys.argv[1]},{s['dt_s']:.4g},{s['steps']},{s['wall_s']:.2f},{r:.0f},{10 / s['dt_s'] / r / 60:.1f}")
except Exception as e:
    print(f"{sys.argv[1]},,,,,error {e}")
PY
done; done
timeout 100 "$D/bin/wall_benchmark" 1500 > "$O/wall.csv" 2>&1
cat "$O/f_scaling.csv" "$O/ab.csv" "$O/parallel12.csv" "$O/wall.csv"
