#!/usr/bin/env bash
# The 1,534-cube wall in ishibashi (wall_benchmark) and in Rockable, back to back, ROUNDS
# rounds, 1 and 2 threads (THREADS="1 2 4 ..." for more). Rockable is not part of this
# project: build it from its public source (github.com/richefeu/rockable, with toofus)
# and pass its `rockable` program as ROCKABLE. Prints CSV: code, round, threads,
# neighbour-list interval (steps; Rockable only), steps/s (Rockable: the median of its
# reports, each 500 steps), contact points.
#   ROCKABLE=/path/to/rockable bash perf/rockable_benchmark.sh [ROUNDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
: "${ROCKABLE:?set ROCKABLE to a Rockable program built from its source}"
rounds=${1:-3} threads=${THREADS:-1 2}
bash "$root/scripts/build.sh" > /dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "code,round,threads,verlet_steps,steps_per_s,contact_points"
for round in $(seq "$rounds"); do
  for j in $threads; do
    # Rockable's own default neighbour-list interval (0.01 s = 250 steps; safe for a
    # resting wall) and a 20-step one, each for 2,500 / 1,000 steps.
    for verlet in 250 20; do
      steps=$([ "$verlet" = 250 ] && echo 2500 || echo 1000)
      VERLET_STEPS=$verlet python3 "$root/perf/rockable_wall.py" "$work" "$steps" 500 > /dev/null
      (cd "$work" && rm -f perf.txt conf[1-9]* && "$ROCKABLE" -j "$j" -v 2 input.txt > /dev/null 2>&1)
      rate=$(awk '{print $2 / 4e-5}' "$work/perf.txt" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
      points=$(ls "$work"/conf* | sort -V | tail -1 | xargs awk '/^Interactions/ {print $2; exit}')
      echo "rockable,$round,$j,$verlet,$rate,$points"
    done
    "$root/build/perf/wall_benchmark" 2000 26 30 "$j" fixed | awk -F, -v r="$round" -v j="$j" \
      'NR == 2 {print "ishibashi," r "," j ",," $7 "," $4}'
  done
done
