#!/usr/bin/env bash
# A long run's late phase (a cracked bridge, where the fast path spends most of its steps):
# programs resumed in turn from one run's checkpoint, SECONDS of wall each (then SIGINT),
# ROUNDS alternations on each thread count in THREADS, fixed teams, --profile. One CSV row
# per run; the stage columns are work us a step. The programs need not be the build that
# wrote the checkpoint (ISHIBASHI_RESUME_ANY_BUILD: fine for speed, not for bits). Make the
# checkpoint with, for instance, model F dry on the fast path stopped after 5 s of shaking:
#   ishibashi run scenarios/nishida_f_kobe_dry.toml --damping implicit --dt 4e-5 \
#     --checkpoint-every 0.5 --out /tmp/f_late   (Ctrl-C after the 5-s checkpoint)
# On a shared machine pause other work first and quote medians of back-to-back runs.
#   bash perf/late_phase_ab.sh RUN_DIR SECONDS ROUNDS "1 2" PROGRAM... > perf/results/NAME.csv
set -eu
RUN=$1 SECONDS_EACH=$2 ROUNDS=$3 THREADS=$4
shift 4
COPY=$(mktemp -d)
trap 'rm -rf "$COPY"' EXIT
echo "program,round,threads,steps,regroups,steps_per_s,narrowphase_us,contact_law_us,solve_us"
# (narrowphase and law: their rows, or their parts of the shared pass since session 74)
for round in $(seq "$ROUNDS"); do
  for t in $THREADS; do
    for program in "$@"; do
      rm -rf "$COPY/run" && cp -r "$RUN" "$COPY/run"
      ISHIBASHI_RESUME_ANY_BUILD=1 timeout -s INT "$SECONDS_EACH" "$program" run --resume "$COPY/run" --threads "$t" \
        --fixed-threads --profile > "$COPY/log" 2>&1 || true
      grep -q '^steps' "$COPY/log" || { echo "$program failed:" >&2; tail -3 "$COPY/log" >&2; exit 1; }
      awk -v p="$program" -v r="$round" -v t="$t" '
        /^narrowphase / {n += $5} /^  narrowphase part/ {n += $3} /^contact law/ {l += $6} /^  contact law part/ {l += $4}
        /^(gather\+)?damping solve/ {s = $6}
        /^steps/ {steps = $2; sub(",", "", steps); regroups = $8; sub(",", "", regroups); rate = $9}
        END {printf "%s,%s,%s,%s,%s,%s,%s,%s,%s\n", p, r, t, steps, regroups, rate, n, l, s}' "$COPY/log"
    done
  done
done
