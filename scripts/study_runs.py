#!/usr/bin/python3
"""The run table of a study (issue 27's columns), one row per finished run, from each run's
summary.json, history.csv and last blocks frame:

    /usr/bin/python3 scripts/study_runs.py STUDY_OUT COMMIT > scenarios/results/study_runs.csv

model (a-f), variant (dry|mortar), collapse (0|1), fallen_stones, fallen_ring_stones,
first_opening_s, first_fall_s (seconds of shaking; empty if none), largest_crown_drop_m,
energy_balance_relative, dt_s, wall_s, commit (of the program that ran the study).
"""
import csv
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from run_outputs import PART, cell_array, frames, read_rows, read_summary, read_vtu  # noqa: E402


def fallen_ring_stones(run):
    grid = read_vtu(frames(run)[-1][1])
    return int(((cell_array(grid, "part") == PART["ring"]) & (cell_array(grid, "fallen") != 0)).sum())


def first_fall_s(run, settle_time_s):
    for row in read_rows(run / "history.csv"):
        if row["phase"] != "settle" and int(row["fallen_stones"]) > 0:
            return f"{float(row['time_s']) - settle_time_s:.3f}"
    return ""


def main():
    out, commit = Path(sys.argv[1]), sys.argv[2]
    writer = csv.writer(sys.stdout, lineterminator="\n")
    writer.writerow(["model", "variant", "collapse", "fallen_stones", "fallen_ring_stones", "first_opening_s", "first_fall_s",
                     "largest_crown_drop_m", "energy_balance_relative", "dt_s", "wall_s", "commit"])
    for run in sorted((out / "runs").iterdir()):
        if not (run / "row.csv").exists():  # not finished
            continue
        s = read_summary(run)
        name = run.name.split("_")  # nishida_<model>_kobe_<variant>
        opening = s["first_opening_s"]
        writer.writerow([name[1], name[3], int(s["collapse"]), s["fallen_stones"], fallen_ring_stones(run),
                         "" if opening is None or opening < 0 else f"{opening:.3f}", first_fall_s(run, s["settle_time_s"]),
                         f"{s['largest_crown_drop_m']:.4f}", f"{s['energy_balance_error_relative']:.2e}",
                         f"{s['dt_s']:.4e}", f"{s['wall_s']:.0f}", commit])


if __name__ == "__main__":
    main()
