#!/usr/bin/env bash
# How much slower a run gets when another process keeps one core busy (issue 13: at most
# 2.5 times), for the team size chosen as the run goes (the default) and for a fixed team
# of all cores: the 1,534-block wall (1,000 steps), model A through 0.2 s of Kobe, and a
# tiny scene (a wall of 8 stones). Medians of REPS runs (default 3), alone and beside
# `yes > /dev/null`; one CSV row per case. Builds first; stop other work while it runs.
#   bash perf/contention_benchmark.sh [OUT_CSV]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh" > /dev/null
out=${1:-$root/out/contention.csv}
reps=${REPS:-3}
bin=$root/build/apps/ishibashi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"; kill $(jobs -p) 2> /dev/null || true' EXIT

seconds() {  # wall seconds of a command
  local t0 t1
  t0=$(date +%s%N)
  "$@" > /dev/null 2>&1
  t1=$(date +%s%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f", (b - a) / 1e9}'
}
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

declare -A cases=(
  [wall_adaptive]="$root/build/perf/wall_benchmark 1000 26 30 $(nproc) adaptive"
  [wall_fixed]="$root/build/perf/wall_benchmark 1000 26 30 $(nproc) fixed"
  [model_a_adaptive]="$bin run $root/scenarios/nishida_a_kobe_dry.toml --duration 0.2 --quiet --out $tmp/a"
  [model_a_fixed]="$bin run $root/scenarios/nishida_a_kobe_dry.toml --duration 0.2 --quiet --fixed-threads --out $tmp/a"
  [tiny_wall_8_stones]="$bin demo --scene shake --courses 2 --stones 2 --duration 2 --fps 5 --out $tmp/tiny"
)
echo "case,threads,alone_s,busy_s,slowdown" > "$out"
for name in wall_adaptive wall_fixed model_a_adaptive model_a_fixed tiny_wall_8_stones; do
  read -r -a cmd <<< "${cases[$name]}"
  alone=() busy=()
  for _ in $(seq "$reps"); do
    alone+=("$(seconds "${cmd[@]}")")
    yes > /dev/null &
    busy+=("$(seconds "${cmd[@]}")")
    kill $! 2> /dev/null; wait $! 2> /dev/null || true
  done
  a=$(median "${alone[@]}") b=$(median "${busy[@]}")
  awk -v n="$name" -v t="$(nproc)" -v a="$a" -v b="$b" 'BEGIN {printf "%s,%s,%.3f,%.3f,%.2f\n", n, t, a, b, b / a}' | tee -a "$out"
done
