# One CSV fragment from `ishibashi run --profile`'s output: steps/s, then the work us a step
# of pose, narrowphase, contact law, gather, damping solve (0 without implicit dashpots) and
# integrate, then the regroups, then the share of the solve's wall time that the caller ran
# alone (its serial parts, %; 0 without implicit dashpots). Used by perf/cracked_ab.sh,
# perf/window_ab.sh and perf/device_cracked.sh.
# With explicit dashpots the gather and integrate are one pass ("gather+integrate", since
# session 72 "gather+integrate+pose" and the pose on a run's first step alone): its work
# goes in the gather column, integrate's is 0. Since session 74 the narrowphase and contact
# law share a pass ("narrowphase+contact law", its two parts on the rows below it), and are
# separate stages only on a capped run's rebuild steps: each column adds both. Since session
# 75 the implicit solve's first pass gathers the forces ("gather+damping solve"): its gather
# is in the solve's column, the gather column 0.
/^pose/ {pose = $5}
/^narrowphase / {narrowphase += $5}
/^contact law/ {law += $6}
/^  narrowphase part/ {narrowphase += $3}
/^  contact law part/ {law += $4}
/^gather / {gather = $5}
/^gather\+integrate/ {gather = $5; integrate = 0}
/^(gather\+)?damping solve/ {solve = $6; solve_serial = $11}
/^integrate( |\+pose)/ {integrate = $5}
/steps\/s/ {
  for (i = 1; i <= NF; ++i) {
    if ($i == "steps/s,") rate = $(i - 1)
    if ($i == "regroups") {regroups = $(i + 1); gsub(",", "", regroups)}
  }
}
END {printf "%s,%s,%s,%s,%s,%s,%s,%s,%s", rate, pose, narrowphase, law, gather, (solve == "" ? 0 : solve), integrate, regroups,
  (solve_serial == "" ? 0 : solve_serial)}
