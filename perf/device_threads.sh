#!/usr/bin/env bash
# Issue 47's 16-core measurements in one call of the device machine (about 8 minutes),
# from the project's root there. Pack this checkout's program and one to compare with:
#   bash perf/device_pack.sh caa3656=before
#   device: carry [".devpack"], command
#     tar xJf .devpack/dev.tar.xz && bash .dev/device_threads.sh
# Writes under $OUT:
#   clock.txt                     core_probe clock: how much slower each core computes with
#                                 2..16 busy at once (no data shared): the growth of the
#                                 stages' work with the threads that is the machine's own
#   loops.txt                     core_probe loops: one parallel loop's cost beyond its chunks
#                                 on 1..16 threads (a step has 4-5, 20 with implicit dashpots)
#   f_scaling.csv + profiles.log  model F dry, 0.02 s settling and 0.05 s of the strongest
#                                 Kobe pulses (the record's 7.3 s), fixed teams 1..16, with
#                                 run --profile's tables and the end state's hash: the study's
#                                 explicit dashpots, then the fast path (implicit, 4e-5 s); then
#                                 16 threads beside four busy cores, fixed and adaptive team;
#                                 then a fixed team of 2 on two cores (taskset), alone and
#                                 with a busy loop on one of them (0.01 s of shaking)
#   trace_f_16.json               explicit, 16 threads, steps 6000-6020 (Perfetto)
#   clock_end.txt                 core_probe clock 1 16 again at the end
#   ab.csv                        .dev/bin/ishibashi_before (if there) and this program
#                                 alternated: 16 threads three rounds, then one thread once,
#                                 then implicit dashpots (4e-5 s) on 16 threads three rounds
#   parallel12.csv, wall.csv      only with EXTRAS=1: the study's twelve runs side by side
#                                 (one thread each, 0.1 s), the 1,534-block wall, teams 1..16
# A stage's imbalance far above 1 in every stage at once means another process held a
# thread off its core: rerun before comparing.
set -u
D=$PWD/.dev; export LD_LIBRARY_PATH=$D/lib
O=${OUT:-/tmp/device_out}; mkdir -p "$O"
lscpu > "$O/cpu.txt"
cd "$D/main"
[ -x "$D/bin/core_probe" ] && timeout 60 "$D/bin/core_probe" clock 1 2 4 8 12 16 > "$O/clock.txt" 2>&1
[ -x "$D/bin/core_probe" ] && timeout 60 "$D/bin/core_probe" loops 1 2 4 8 16 > "$O/loops.txt" 2>&1
sed -e 's/^settle_max_s = .*/settle_max_s = 0.02/' scenarios/nishida_f_kobe_dry.toml > scenarios/bench_f.toml
f_run() {  # program threads label [extra...]: prints the stepping rate and the end state's hash
  local bin=$1 t=$2 label=$3; shift 3
  ${PIN:-} timeout "${LIMIT:-150}" "$D/bin/$bin" run scenarios/bench_f.toml --start 7.3 --duration "${DURATION:-0.05}" --threads "$t" --quiet \
    --profile --out "/tmp/$label" "$@" > "/tmp/$label.log" 2>&1
  { echo "=== $label: $bin, $t threads $*"; cat "/tmp/$label.log"; } >> "$O/profiles.log"
  echo "$(grep -o "[0-9.]* steps/s" "/tmp/$label.log" | head -1 | cut -d' ' -f1),$(grep -o '"state_hash": "[0-9a-f]*"' "/tmp/$label/summary.json" | cut -d'"' -f4)"
}
echo "scheme,team,threads,steps_per_s,state_hash" > "$O/f_scaling.csv"
for t in 1 2 4 8 12 16; do
  extra=(); [ "$t" = 16 ] && extra=(--trace "$O/trace_f_16.json" --trace-steps 6000:6020)
  echo "explicit,fixed,$t,$(f_run ishibashi "$t" "f_$t" --fixed-threads "${extra[@]}")" >> "$O/f_scaling.csv"
done
for t in 1 2 4 8 16; do
  echo "implicit 4e-5,fixed,$t,$(f_run ishibashi "$t" "imp_$t" --fixed-threads --damping implicit --dt 4e-5)" >> "$O/f_scaling.csv"
done
for k in 1 2 3 4; do timeout 60 sh -c 'while :; do :; done' & done  # four busy cores
echo "explicit beside 4 busy,fixed,16,$(f_run ishibashi 16 f_16_busy_fixed --fixed-threads)" >> "$O/f_scaling.csv"
echo "explicit beside 4 busy,adaptive,16,$(f_run ishibashi 16 f_16_busy_adaptive)" >> "$O/f_scaling.csv"
kill $(jobs -p) 2> /dev/null; wait
# The issue's shared-core target: a fixed team of 2 beside a busy core, here both pinned to
# cores 2 and 3 (the busy loop on core 3), against the same team alone there.
export DURATION=0.01 LIMIT=90 PIN="taskset -c 2,3"
echo "explicit pinned to 2 cores,fixed,2,$(f_run ishibashi 2 f_2_pinned --fixed-threads)" >> "$O/f_scaling.csv"
timeout 95 taskset -c 3 sh -c 'while :; do :; done' &
busy=$!
echo "explicit pinned to 2 cores beside 1 busy,fixed,2,$(f_run ishibashi 2 f_2_pinned_busy --fixed-threads)" >> "$O/f_scaling.csv"
kill "$busy" 2> /dev/null; wait
unset DURATION LIMIT PIN
echo "program,threads,steps_per_s,state_hash" > "$O/ab.csv"
if [ -x "$D/bin/ishibashi_before" ]; then
  for rep in 1 2 3; do for bin in ishibashi_before ishibashi; do
    echo "$bin,16,$(f_run $bin 16 "ab_${bin}_$rep" --fixed-threads)" >> "$O/ab.csv"
  done; done
  echo "ishibashi_before,1,$(f_run ishibashi_before 1 ab_before_1 --fixed-threads)" >> "$O/ab.csv"
  for rep in 1 2 3; do for bin in ishibashi_before ishibashi; do
    echo "$bin implicit 4e-5,16,$(f_run $bin 16 "abi_${bin}_$rep" --fixed-threads --damping implicit --dt 4e-5)" >> "$O/ab.csv"
  done; done
fi
# Again at the end: a host that slowed or sped up during the call shows here.
[ -x "$D/bin/core_probe" ] && timeout 60 "$D/bin/core_probe" clock 1 16 > "$O/clock_end.txt" 2>&1
cat "$O/clock.txt" "$O/loops.txt" "$O/f_scaling.csv" "$O/ab.csv" "$O/clock_end.txt"
[ "${EXTRAS:-0}" = 1 ] || exit 0
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
