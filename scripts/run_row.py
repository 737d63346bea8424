#!/usr/bin/env python3
"""One CSV row of what a run's outputs say (for scripts/energy_table.sh):
   run_row.py RUN_DIR NAME OPTIONS START DURATION  (--header: the header line)
the energy balance error (of the energy exchanged) at the end and before the first stone
fell, the first opening, the crown unit's drop relative to the ground 3 s into the shaking
and at most, the cracked joints, fallen stones, blocks that left the model, collapse."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from run_outputs import read_rows, read_summary  # noqa: E402

HEADER = ("scenario,options,start_s,duration_s,dt_s,balance_error_pct,balance_error_before_first_fall_pct,"
          "first_opening_s,crown_drop_3s_m,crown_drop_max_m,joints_cracked,fallen_stones,blocks_left_model,collapse,wall_s")
if sys.argv[1] == "--header":
    print(HEADER)
    sys.exit(0)
out, name, options, start, duration = sys.argv[1:6]
s = read_summary(out)
rows = read_rows(out + "/history.csv")


def exchanged(r):
    return sum(abs(float(r.get(k) or 0)) for k in ("ground_work_j", "damping_j", "friction_j", "bond_j", "tie_yield_j"))


before = [r for r in rows if int(r["fallen_stones"]) == 0][-1]
early = 100 * float(before["balance_error_j"]) / max(exchanged(before), 1e-30)
dz = "block%d_dz_m" % s["monitored_block"]
settled = float([r for r in rows if r["phase"] == "settle"][-1][dz])
at3 = [r for r in rows if r["phase"] == "shake" and float(r["time_s"]) <= s["settle_time_s"] + 3.0 + 1e-9]
drop3 = settled - float(at3[-1][dz]) if at3 else float("nan")
print("%s,%s,%s,%s,%.4g,%.3f,%.3f,%s,%.4f,%.4f,%d,%d,%d,%s,%.0f" % (
    name, options, start, duration, s["dt_s"], 100 * s["energy_balance_error_relative"], early,
    "none" if s["first_opening_s"] is None else "%.3f" % s["first_opening_s"],
    drop3, s["largest_crown_drop_m"], s["joints_cracked"], s["fallen_stones"], s["blocks_left_model"],
    "yes" if s["collapse"] else "no", s["wall_s"]))
