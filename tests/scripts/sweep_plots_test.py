#!/usr/bin/python3
"""analysis/report/sweep_plots.py: ties.png is drawn for a sweep whose scenarios have tie rods
(one dry, one tied: only the tied one's runs carry rods), and not for one without rods or
from a program before the rods' columns."""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "analysis" / "report" / "sweep_plots.py"


def write(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def sweep(folder, with_rods_columns):
    folder.mkdir()
    runs = []
    for scenario, rods in (("b_dry", 0), ("b_tied", 12)):
        for level, pga in enumerate((0.3, 0.6, 0.9)):
            run = {"scenario": scenario, "record": "kobe", "level": level, "member": 0, "pga_g": pga,
                   "failed": int(pga > 0.7), "largest_crown_drop_m": 0.01 * (level + 1)}
            if with_rods_columns:
                run.update(tie_rods=rods, ties_yielded=(int(pga > 0.5) if rods else ""),
                           peak_tie_tension_n=(1e5 * pga * 2 if rods else ""))
            runs.append(run)
    write(folder / "sweep.csv", runs)
    write(folder / "fragility_fit.csv", [{"scenario": s, "median_g": 0.75, "beta": 0.2, "degenerate": 0, "median_is": "fit",
                                          "highest_survival_g": 0.6, "lowest_failure_g": 0.9,
                                          "failures": 1, "outcomes": 3} for s in ("b_dry", "b_tied")])
    write(folder / "fragility.csv", [{"scenario": s, "pga_g": 0.5, "failure_probability": 0.2} for s in ("b_dry", "b_tied")])
    done = subprocess.run([sys.executable, str(SCRIPT), str(folder)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


with tempfile.TemporaryDirectory() as tmp:
    said = sweep(Path(tmp) / "tied", True)
    assert (Path(tmp) / "tied" / "ties.png").exists() and "ties.png" in said, said
    said = sweep(Path(tmp) / "older", False)
    assert not (Path(tmp) / "older" / "ties.png").exists() and "ties.png" not in said, said
    assert (Path(tmp) / "older" / "fragility.png").exists()
print("sweep_plots: ties.png only where scenarios have rods")
