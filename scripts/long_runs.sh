#!/usr/bin/env bash
# The long measurements under way (issue 45 items 2-3, issue 48 item 5): hours of one core
# each, run niced in the background across sessions. Each job is resumed from its
# checkpoints or skipped when finished, so `bash scripts/long_runs.sh LANE` (LANE: one of
# the lanes below, `list`, or `save`) only ever continues where the last session stopped.
# Each job runs the program of its commit, frozen in out/bin/ishibashi_COMMIT
# (scripts/frozen_binary.sh), so that a later build never changes a comparison half way. The
# results and what they mean: scenarios/results/README.md.
#
#   nohup nice -n 19 bash scripts/long_runs.sh d_mortar d_mortar3 c_mortar c_mortar2 c_dry c_dry2 > out/long_runs.log 2>&1 &
#   nohup nice -n 19 bash scripts/long_runs.sh d_mortar3 d_mortar c_mortar2 c_mortar c_dry2 c_dry > out/long_runs_b.log 2>&1 &
#   bash scripts/long_runs.sh save    # before committing: keeps the finished members
#   bash scripts/long_runs.sh park    # at a session's end: keeps the members under way
# The whole script is one brace group ending in `exit`: bash reads a script as it goes, so
# without it a lane that ends after this file was edited would read on at its old byte
# offset in the new text and could run a fragment of the job loop again. A group is read
# whole before it runs, so an edit reaches only the lanes started after it.
{
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

# lane | commit | output folder | the run's arguments (scenario first)
jobs=(
  # (Finished jobs leave this list once their results are committed: B dry's explicit
  # ensemble, B, C, D and F's runs against dt, dry and with mortar (F dry's last at 5e-6 s,
  # session 42), B with mortar's ensemble on the fast path (session 44), and the chaos
  # probes of A, B and E dry and B with mortar, in scenarios/results.) B with mortar runs
  # 5406021's program, built with clang: every preset's hash as ff7154d's (perf/results,
  # clang_vs_gcc). A member's bits are the same on any number of threads. A new checkout
  # starts with an empty out/, and only the members kept in the repository (below) survive
  # it, and the members under way parked there (`park`, below) go on from their checkpoints.
  # Issue 45 item 3's second model, B with mortar: the explicit reference, the same seed as
  # the fast path's five (session 44, scenarios/results/ensembles/b_mortar_implicit_4e-5_*);
  # 2.5 million steps a member, 3.5-6.5 ms each on one thread once the shaking has cracked
  # it (session 46): about 3-4 hours on two quiet cores, far more beside builds and tests.
  # Members 0 and 1 on 5406021's program (1 was half done when fd2dc55 came); members 2-4
  # on fd2dc55's, in folders of their own: the same motion (B with mortar's preset hash,
  # and 30 history rows of member 0 resumed on its rule, byte for byte), the late step at
  # about 0.76 of 5406021's. The three folders' members make one ensemble of five (a
  # member's draws depend on the seed and its number only, not on the share).
  "b_mortar|5406021|out/ensembles/b_mortar_explicit|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 0:2 --seed 1 --jobs 1 --threads 2"
  # Since session 50 B's members run side by side, on one thread each where two lanes
  # share the cores (members 2-3 in b_mortar_b, member 4 in b_mortar_c, which the first
  # process takes up once b_mortar's share is done or under way elsewhere), and E waits: B with mortar's five decide issue
  # 45 item 3, and with it whether E's ensembles need the explicit reference at all (issue
  # 48 item 5 asks for the fast path once it is verified). E on the explicit reference is
  # about 90 core-hours; B's members 1-4 left about 20. (Members 2-4 were one share, 2:5,
  # in session 49's plan; member 2 had begun in it and goes on in 2_4, its folder renamed:
  # a member's key holds neither the share nor the folder.)
  "b_mortar_b|fd2dc55|out/ensembles/b_mortar_explicit_2_4|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 2:4 --seed 1 --jobs 1 --threads 1"
  "b_mortar_c|fd2dc55|out/ensembles/b_mortar_explicit_4_5|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 4:5 --seed 1 --jobs 1 --threads 1"
  # Issue 48 item 5's other marginal runs on the explicit reference (the fast path is not
  # verified): model E dry and with mortar, five members each, the seed of A's and B's
  # ensembles; about 3.5 core-hours a member. They run fd2dc55's program: the same motion
  # as 5406021's (every preset's hash but D's, whose open points alone differ), its
  # narrowphase no longer re-clipping stones that cannot touch (the late step at 0.76 of
  # 5406021's, perf/results). One thread a member, one lane each: each of the two
  # processes above goes on to them when its share of B ends (a lane under way in the
  # other process is skipped: its lock).
  # Why B with mortar's member 0 opens at the 1.44-s pulse on the fast path (1.444 s) and not
  # explicitly (2.699 s): its bond utilisation (5655e32's program, the first with it) through
  # 1.6 s of shaking under each scheme, the record's baseline fitted over those 1.6 s in both
  # (--duration), so that both see the same ground. The fast path's is about 20 minutes of a
  # core, the explicit one's about an hour and a half (scenarios/results: "Session 51"). The
  # fast path at half its step (session 52) says whether its utilisation at that pulse
  # converges toward the explicit run's as the step falls (lane b_mortar_u0h, beside b_mortar_u0).
  "b_mortar_u0|5655e32|out/ensembles/b_mortar_u0_implicit_4e-5|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 0:1 --seed 1 --jobs 1 --threads 1 --duration 1.6 --damping implicit --dt 4e-5"
  "b_mortar_u0|5655e32|out/ensembles/b_mortar_u0_explicit|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 0:1 --seed 1 --jobs 1 --threads 1 --duration 1.6"
  "b_mortar_u0h|5655e32|out/ensembles/b_mortar_u0_implicit_2e-5|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 0:1 --seed 1 --jobs 1 --threads 1 --duration 1.6 --damping implicit --dt 2e-5"
  # Whether the fast path at half the study's step keeps B with mortar's outcomes as the
  # explicit reference has them (issue 45 items 3 and 4): at 4e-5 s four of its five members
  # open a joint at the 1.44-s pulse, and member 0's bond there is over-stressed at 4e-5 s but
  # not at 2e-5 s (session 52). The same seed's five members at 2e-5 s, program b38cfde (the
  # same motion as 5406021's and fd2dc55's; its history.csv keeps the bond utilisation's peak
  # between frames); about 1.5 core-hours a member (session 53).
  "b_mortar_h|b38cfde|out/ensembles/b_mortar_implicit_2e-5|scenarios/nishida_b_kobe_mortar.toml --members 5 --seed 1 --jobs 1 --threads 1 --damping implicit --dt 2e-5"
  # Issue 45's question left open (scenarios/results/README.md, "Item 4's decision"): B with
  # mortar's debris on the fast path is about 1.6 times the reference's at 4e-5 and at 2e-5 s
  # alike. Does it turn back toward the reference at 1e-5 s? The same seed's five members,
  # b38cfde's program as at 2e-5 s (so that only the step differs), about 1.1 core-hours a
  # member on a quiet core (member 3: 1.14 h); in two shares (one a lane: list both, in
  # either order).
  "b_mortar_q|b38cfde|out/ensembles/b_mortar_implicit_1e-5|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 0:3 --seed 1 --jobs 1 --threads 1 --damping implicit --dt 1e-5"
  "b_mortar_q2|b38cfde|out/ensembles/b_mortar_implicit_1e-5_3_5|scenarios/nishida_b_kobe_mortar.toml --members 5 --member-range 3:5 --seed 1 --jobs 1 --threads 1 --damping implicit --dt 1e-5"
  "e_dry|fd2dc55|out/ensembles/e_dry_explicit|scenarios/nishida_e_kobe_dry.toml --members 5 --seed 1 --jobs 1 --threads 1"
  "e_mortar|fd2dc55|out/ensembles/e_mortar_explicit|scenarios/nishida_e_kobe_mortar.toml --members 5 --seed 1 --jobs 1 --threads 1"
  # Model D, the study's clearest answer that mortar helps (its single runs: 195 stones fall
  # dry, 3 with mortar), as ensembles: five members each, E's seed and program (D and E have
  # the same stones and step, so about 1.4 core-hours a member on a quiet core). Not asked by
  # issue 48 (it leaves D a single run); queued in session 58, since it bears on the study's
  # verdict, in one lane while the other finishes the 1e-5 s fast path. Two shares a
  # variant, so that both lanes can work on one ensemble.
  "d_dry|fd2dc55|out/ensembles/d_dry_explicit|scenarios/nishida_d_kobe_dry.toml --members 5 --member-range 0:3 --seed 1 --jobs 1 --threads 1"
  "d_dry2|fd2dc55|out/ensembles/d_dry_explicit_3_5|scenarios/nishida_d_kobe_dry.toml --members 5 --member-range 3:5 --seed 1 --jobs 1 --threads 1"
  # D with mortar in three shares (session 62; none of 0:3's members had started): members 3-4
  # in one lane, 0-1 in the other, and 2 in whichever frees first, so that both cores stay
  # busy to the end (a member is about 1.6 core-hours).
  "d_mortar|fd2dc55|out/ensembles/d_mortar_explicit|scenarios/nishida_d_kobe_mortar.toml --members 5 --member-range 0:2 --seed 1 --jobs 1 --threads 1"
  "d_mortar2|fd2dc55|out/ensembles/d_mortar_explicit_3_5|scenarios/nishida_d_kobe_mortar.toml --members 5 --member-range 3:5 --seed 1 --jobs 1 --threads 1"
  "d_mortar3|fd2dc55|out/ensembles/d_mortar_explicit_2_3|scenarios/nishida_d_kobe_mortar.toml --members 5 --member-range 2:3 --seed 1 --jobs 1 --threads 1"
  # Model C after D (queued in session 62): its single runs stand dry and with mortar, but
  # with mortar its crown sank 93 mm (dry 13 mm; F's 0-0.2 mm), the study's closest call
  # among the bridges that stand, so one run says little about whether C with mortar
  # survives. Five members each, the seed and program of D's and E's; C's single runs took
  # about 2 core-hours on 5acb07b's program. With mortar first.
  "c_mortar|fd2dc55|out/ensembles/c_mortar_explicit|scenarios/nishida_c_kobe_mortar.toml --members 5 --member-range 0:3 --seed 1 --jobs 1 --threads 1"
  "c_mortar2|fd2dc55|out/ensembles/c_mortar_explicit_3_5|scenarios/nishida_c_kobe_mortar.toml --members 5 --member-range 3:5 --seed 1 --jobs 1 --threads 1"
  "c_dry|fd2dc55|out/ensembles/c_dry_explicit|scenarios/nishida_c_kobe_dry.toml --members 5 --member-range 0:3 --seed 1 --jobs 1 --threads 1"
  "c_dry2|fd2dc55|out/ensembles/c_dry_explicit_3_5|scenarios/nishida_c_kobe_dry.toml --members 5 --member-range 3:5 --seed 1 --jobs 1 --threads 1"
  # C dry as built (session 68): its single run stood on 5acb07b's program, while the first
  # three members of its ensemble on fd2dc55's collapse (scenarios/results/README.md, "Model C
  # as ensembles"). The scenario's own geometry on fd2dc55's program says whether the program
  # or the construction tolerance moved the verdict: an ensemble of one member with no
  # tolerance (scenarios/results/c_dry_as_built.toml: the plain run bit for bit), so that
  # `park` can keep it between sessions; about 5 hours of a core. Before b_tied in its lane.
  "c_dry_as_built|fd2dc55|out/ensembles/c_dry_as_built|scenarios/results/c_dry_as_built.toml --members 1 --seed 1 --jobs 1 --threads 1"
  # Do tie rods keep B's walls up (session 66; scenarios/results/README.md, "Tie rods")? B
  # dry tied and B dry on one program, the first with rods (dcb7acf: each member's rods made
  # snug in its own pose), the seed of the other ensembles: B dry's own (be8e1f2) predates
  # three changes of the contact geometry. Hours of a core a member (B dry's took 7.4 on
  # be8e1f2's program, whose narrowphase was slower); queued after C.
  "b_tied|dcb7acf|out/ensembles/b_dry_tied_explicit|scenarios/nishida_b_kobe_dry_tied.toml --members 5 --seed 1 --jobs 1 --threads 1"
  "b_dry_ref|dcb7acf|out/ensembles/b_dry_explicit_dcb7acf|scenarios/nishida_b_kobe_dry.toml --members 5 --seed 1 --jobs 1 --threads 1"
  # Model F, the last of the study's rows still a single run (session 78): dry and with
  # mortar, five members each, the seed of the other ensembles, on 2a8ffb4's program (the
  # first with the ground's velocities set aside within a step, 1fd08db). F's single runs
  # stand far from collapse (crown drop 0.2 mm, no stone falls), so five members bound how
  # likely a stone falls, where one run's interval is 0-0.79. About 1.5 hours of a quiet
  # core a member (2.35 million steps at about 500 a second).
  "f_dry|2a8ffb4|out/ensembles/f_dry_explicit|scenarios/nishida_f_kobe_dry.toml --members 5 --seed 1 --jobs 1 --threads 1"
  # F dry's five finished in session 90; its member 4 left the second core to F with mortar's
  # last member, on two threads from there (a member's key leaves the thread count out).
  "f_mortar|2a8ffb4|out/ensembles/f_mortar_explicit|scenarios/nishida_f_kobe_mortar.toml --members 5 --seed 1 --jobs 1 --threads 2"
  # Both F ensembles finished in session 90: F with mortar collapses in 5 of 5 where its single
  # run (5acb07b) lost no stone. The same program with the stones as drawn (no construction
  # tolerance) says whether the program or the placement turned it, as c_dry_as_built did.
  "f_mortar_as_built|2a8ffb4|out/ensembles/f_mortar_as_built|scenarios/results/f_mortar_as_built.toml --members 1 --seed 1 --jobs 1 --threads 2"
)

# A run's summary says so; an ensemble's ensemble.json and a probe's probe.json count the
# members that finished (they are written also when some were interrupted), a share
# (--member-range FROM:TO in the job's arguments, $2) those of its range.
finished() {
  local table share=""
  [[ ${2:-} =~ --member-range\ ([0-9]+):([0-9]+) ]] && share=$((BASH_REMATCH[2] - BASH_REMATCH[1]))
  for table in "$1/ensemble.json" "$1/probe.json"; do
    if [[ -f $table ]]; then
      python3 -c "import json, sys; j = json.load(open(sys.argv[1])); sys.exit(j['finished'] != int(sys.argv[2] or j['members']))" "$table" "$share"
      return
    fi
  done
  [[ -f $1/summary.json ]] && grep -q '"finished": true' "$1/summary.json"
}

# How far a job under way has shaken: each run's (each member's) seconds of shaking, wall
# hours so far and the hours left at that pace, from its summary.json (a finished one's
# fallen stones); a run still settling (no summary yet) by the last row of its history.csv.
progress() {
  python3 - "$1" << 'PY'
import json, pathlib, sys
runs = sorted({p.parent for pattern in ("**/summary.json", "**/history.csv") for p in pathlib.Path(sys.argv[1]).glob(pattern)})
parts = []
for run in runs:
    if not (run / "summary.json").exists():
        rows = (run / "history.csv").read_text().splitlines()
        try:  # the last row may be half written
            parts.append(f"{run.name}: settling, {float(rows[-1].split(',')[0]):.2f} s")
        except (IndexError, ValueError):
            pass
        continue
    try:
        s = json.loads((run / "summary.json").read_text())
    except ValueError:
        continue
    wall = s.get("wall_s", 0)
    if s.get("finished"):
        state = f"done ({s.get('fallen_stones')} fallen), {wall / 3600:.1f} h"
    else:
        shaken, duration = s.get("shaking_time_s", 0), s.get("settings", {}).get("duration_s", 0)
        state = f"{shaken:.2f} s shaken, {wall / 3600:.1f} h"
        if shaken > 0 and duration > shaken:  # at its pace so far, settling included
            state += f", about {wall / shaken * (duration - shaken) / 3600:.1f} h to go"
    parts.append(f"{run.name}: {state}")
print(": " + "; ".join(parts) if parts else "")
PY
}

# Finished ensemble members are kept in the repository, in kept/NAME/member_NNN/ (NAME: the
# job's folder name): inputs.key, summary.json and history.csv (xz), what the ensemble's tables
# are made of. A new checkout copies them back before the job goes on. A member's key holds the
# program's fingerprint, its bytes' hash: kept/NAME/program.sha256 says which bytes made them,
# and neither direction mixes programs (a frozen program with other bytes, from another
# compiler, would run the kept members again).
kept=scenarios/results/ensembles/members
same_program() {  # kept folder, program: whether the program made the kept members (or none are kept)
  [[ ! -f $1/program.sha256 ]] || [[ $(sha256sum < "$2" | cut -d' ' -f1) == "$(cat "$1/program.sha256")" ]] ||
    { echo "long_runs.sh: $2 is not the program that made $1" >&2; return 1; }
}
save_members() {  # out folder, program
  local name member dest
  name=$(basename "$1")
  same_program "$kept/$name" "$2" || return 1
  for member in "$1"/member_*/; do
    [[ -f $member/inputs.key && -f $member/summary.json ]] || continue
    dest=$kept/$name/$(basename "$member")
    [[ -f $dest/inputs.key ]] && cmp -s "$dest/inputs.key" "$member/inputs.key" && continue
    mkdir -p "$dest"
    cp "$member/inputs.key" "$member/summary.json" "$dest/"
    xz -9 -c "$member/history.csv" > "$dest/history.csv.xz"
    rm -rf "${parked:?}/$name/$(basename "$member")"
    echo "kept $dest"
  done
  # A parked folder whose members are all kept goes too: only its program's hash was left.
  compgen -G "$parked/$name/member_*" > /dev/null || rm -rf "${parked:?}/$name"
  [[ -d $kept/$name ]] && sha256sum < "$2" | cut -d' ' -f1 > "$kept/$name/program.sha256"
  return 0
}
restore_members() {  # out folder, program
  local name member dest
  name=$(basename "$1")
  same_program "$kept/$name" "$2" || return 1
  for member in "$kept/$name"/member_*/; do
    [[ -d $member ]] || continue
    dest=$1/$(basename "$member")
    [[ -f $dest/inputs.key ]] && continue
    mkdir -p "$dest"
    cp "$member/inputs.key" "$member/summary.json" "$dest/"
    xz -dc "$member/history.csv.xz" > "$dest/history.csv"
  done
}

# A member under way is parked in the repository at a session's end (`long_runs.sh park`),
# in parked/NAME/member_NNN/: started.key and checkpoint.bin (xz, a few MB), so that a new
# checkout goes on from its checkpoint instead of from the start: a member is hours of a core,
# more than a session gives it. Its frames before the checkpoint are not parked (hundreds of
# MB): its .pvd lists them and ParaView misses them; the ensemble's tables need only the
# summary and history.csv, which the checkpoint holds. A parked member leaves when it is kept.
parked=scenarios/results/ensembles/parked
park_members() {  # out folder, program
  local name member dest
  name=$(basename "$1")
  for member in "$1"/member_*/; do
    [[ -f $member/started.key && -f $member/checkpoint.bin ]] || continue
    dest=$parked/$name/$(basename "$member")
    [[ -f $dest/checkpoint.bin.xz ]] && xz -dc "$dest/checkpoint.bin.xz" | cmp -s - "$member/checkpoint.bin" && continue
    mkdir -p "$dest"
    cp "$member/started.key" "$dest/"
    xz -6 -T1 -c "$member/checkpoint.bin" > "$dest/checkpoint.bin.xz.tmp"
    mv "$dest/checkpoint.bin.xz.tmp" "$dest/checkpoint.bin.xz"
    sha256sum < "$2" | cut -d' ' -f1 > "$parked/$name/program.sha256"
    echo "parked $dest ($(du -h "$dest/checkpoint.bin.xz" | cut -f1))"
  done
}
unpark_members() {  # out folder, program
  local name member dest
  name=$(basename "$1")
  # Another program cannot resume them: its members start again.
  same_program "$parked/$name" "$2" || return 0
  for member in "$parked/$name"/member_*/; do
    [[ -d $member ]] || continue
    dest=$1/$(basename "$member")
    [[ -f $dest/started.key || -f $dest/inputs.key ]] && continue  # under way here, or kept
    mkdir -p "$dest"
    xz -dc "$member/checkpoint.bin.xz" > "$dest/checkpoint.bin"
    cp "$member/started.key" "$dest/"
    echo "$(date -u +%FT%TZ) $dest: goes on from its parked checkpoint"
  done
}

# Several lanes run one after the other in one process, so that a core freed by a lane's
# last job goes on to the next lane's: `bash scripts/long_runs.sh b_mortar b_mortar_c e_dry`.
if (($# > 1)); then
  for lane in "$@"; do bash "$root/scripts/long_runs.sh" "$lane" || true; done
  exit 0
fi
lane=${1:-list}
if [[ $lane != list && $lane != save && $lane != park ]]; then
  # One process per lane: two would write the same folders.
  mkdir -p out
  exec 9> "out/long_runs_$lane.lock"
  flock -n 9 || { echo "lane $lane is already running (out/long_runs_$lane.lock)" >&2; exit 1; }
fi
for job in "${jobs[@]}"; do
  IFS='|' read -r job_lane commit out args <<< "$job"
  if [[ $lane == list ]]; then
    state="not started"
    if finished "$out" "$args"; then state=finished; elif [[ -e $out ]]; then state="under way$(progress "$out")"
    elif [[ -d $parked/$(basename "$out") ]]; then state="parked: $(cd "$parked/$(basename "$out")" && echo member_*)"
    elif compgen -G "$kept/$(basename "$out")/member_*" > /dev/null; then  # a new checkout's out/ is empty
      state="kept: $(cd "$kept/$(basename "$out")" && echo member_*)"; fi
    printf '%-10s %s  %-40s %s\n' "$job_lane" "$commit" "$out" "$state"
    continue
  fi
  if [[ $lane == save ]]; then
    [[ -d $out ]] && save_members "$out" "$(bash scripts/frozen_binary.sh "$commit")"
    continue
  fi
  if [[ $lane == park ]]; then
    [[ -d $out ]] && park_members "$out" "$(bash scripts/frozen_binary.sh "$commit")"
    continue
  fi
  [[ $job_lane == "$lane" ]] || continue
  bin=$(bash scripts/frozen_binary.sh "$commit")
  restore_members "$out" "$bin"
  unpark_members "$out" "$bin"
  # shellcheck disable=SC2086  # the arguments are words
  if [[ $args == *--members* || $args == *--probe* ]]; then
    # An ensemble or a probe keeps its finished members and resumes the others from their
    # checkpoints (the same arguments: they make the members' keys).
    echo "$(date -u +%FT%TZ) $out: members"
    "$bin" run $args --out "$out"
  elif finished "$out" "$args"; then
    echo "$(date -u +%FT%TZ) $out: finished"
  elif [[ -f $out/checkpoint.bin ]]; then
    echo "$(date -u +%FT%TZ) $out: resumed"
    "$bin" run --resume "$out" --checkpoint-wall 300 --quiet
  else
    echo "$(date -u +%FT%TZ) $out: started"
    "$bin" run $args --out "$out" --checkpoint-wall 300 --quiet
  fi
done
exit
}
