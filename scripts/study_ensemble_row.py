#!/usr/bin/env python3
"""An ensemble's row of scenarios/results/study_ensembles.csv (issue 48 item 5), written in
place of that model and variant's row (the others kept, rows sorted):
   study_ensemble_row.py ENSEMBLE_DIR MODEL VARIANT DAMPING COMMIT [CSV]
ENSEMBLE_DIR holds the ensemble.json of `ishibashi run --members N`, or is several folders
joined by '+', the shares of one ensemble run by `--member-range` (their ensemble.csv rows
pooled); MODEL a-f, VARIANT dry|mortar, DAMPING study|implicit|capped, COMMIT the program
that ran it (the shares' programs joined by '+').
   study_ensemble_row.py --single-runs STUDY_RUNS_CSV [CSV]
gives each run of the study that has no ensemble row yet a row of its single run
(scenarios/results/study_runs.csv: members 1, its outcome's Wilson interval of one sample),
so that the table has a row per run and says which are single runs."""
import csv
import json
import math
import sys
from pathlib import Path

COLUMNS = ["model", "variant", "members", "p_collapse", "p_collapse_lo", "p_collapse_hi", "p_stones_fall",
           "p_stones_fall_lo", "p_stones_fall_hi", "p_ring_stones_fall", "p_ring_stones_fall_lo",
           "p_ring_stones_fall_hi", "fallen_median", "fallen_min", "fallen_max", "first_opening_median_s", "damping",
           "commit"]
DEFAULT_CSV = Path(__file__).resolve().parent.parent / "scenarios" / "results" / "study_ensembles.csv"


def row_of(ensemble, model, variant, damping, commit):
    row = {"model": model, "variant": variant, "members": ensemble["finished"], "damping": damping, "commit": commit}
    for key, name in (("collapse", "p_collapse"), ("stones_fall", "p_stones_fall"),
                      ("ring_stones_fall", "p_ring_stones_fall")):
        p = ensemble[key]
        row[name], row[name + "_lo"], row[name + "_hi"] = (f"{p[k]:.3f}" for k in ("p", "lo", "hi"))
    fallen = ensemble["fallen_stones"]
    for k in ("median", "min", "max"):
        row["fallen_" + k] = "" if fallen[k] is None else f"{fallen[k]:g}"
    opening = ensemble["first_opening_s"]["median"]
    row["first_opening_median_s"] = "" if opening is None else f"{opening:.3f}"
    return row


def wilson(successes, n, z=1.959963984540054):
    """The 95 % Wilson score interval of a proportion (as analysis/batch/member_runs.cpp)."""
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return p, max(0.0, centre - half), min(1.0, centre + half)


def median(values):
    """As analysis/batch/member_runs.cpp: the middle value, or the mean of the two middle ones."""
    v = sorted(values)
    n = len(v)
    return None if n == 0 else v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def pooled_shares(folders):
    """An ensemble.json's outcomes from the ensemble.csv rows of every share (finished members)."""
    rows = [row for folder in folders for row in csv.DictReader(open(Path(folder) / "ensemble.csv"))
            if row["interrupted"] != "yes"]
    n = len(rows)
    if n == 0:
        sys.exit("+".join(folders) + ": no finished member in any share's ensemble.csv")
    ensemble = {"finished": n}
    for key, happened in (("collapse", lambda x: x["collapse"] == "yes"),
                          ("stones_fall", lambda x: int(x["fallen_stones"]) > 0),
                          ("ring_stones_fall", lambda x: int(x["fallen_ring_stones"]) > 0)):
        p, lo, hi = wilson(sum(happened(x) for x in rows), n)
        ensemble[key] = {"p": p, "lo": lo, "hi": hi}
    fallen = [int(x["fallen_stones"]) for x in rows]
    ensemble["fallen_stones"] = {"median": median(fallen), "min": min(fallen), "max": max(fallen)}
    ensemble["first_opening_s"] = {"median": median([float(x["first_opening_s"]) for x in rows
                                                     if x["first_opening_s"] != ""])}
    return ensemble


def single_run_row(run):
    """A study run's row as an ensemble of one (study_runs.csv's columns)."""
    row = {"model": run["model"], "variant": run["variant"], "members": 1, "damping": "study", "commit": run["commit"]}
    fallen = int(run["fallen_stones"])
    for name, happened in (("p_collapse", run["collapse"] == "1"), ("p_stones_fall", fallen > 0),
                           ("p_ring_stones_fall", int(run["fallen_ring_stones"]) > 0)):
        row[name], row[name + "_lo"], row[name + "_hi"] = (f"{x:.3f}" for x in wilson(int(happened), 1))
    row["fallen_median"] = row["fallen_min"] = row["fallen_max"] = str(fallen)
    row["first_opening_median_s"] = run["first_opening_s"]
    return row


def write_rows(table, rows):
    rows.sort(key=lambda r: (r["model"], r["variant"]))
    with table.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


def main(argv):
    if len(argv) in (3, 4) and argv[1] == "--single-runs":
        table = Path(argv[3]) if len(argv) == 4 else DEFAULT_CSV
        rows = list(csv.DictReader(table.open())) if table.exists() else []
        have = {(r["model"], r["variant"]) for r in rows}
        added = [single_run_row(run) for run in csv.DictReader(open(argv[2])) if (run["model"], run["variant"]) not in have]
        write_rows(table, rows + added)
        print(f"{table}: {len(added)} single runs added")
        return
    if len(argv) not in (6, 7) or argv[3] not in ("dry", "mortar") or argv[2] not in "abcdef" or len(argv[2]) != 1:
        sys.exit(__doc__)
    folder, model, variant, damping, commit = argv[1:6]
    table = Path(argv[6]) if len(argv) == 7 else DEFAULT_CSV
    shares = folder.split("+")
    for share in shares:
        source = Path(share) / ("ensemble.json" if len(shares) == 1 else "ensemble.csv")
        if not source.exists():
            sys.exit(f"{source}: missing (run `ishibashi run SCENARIO --members N --out {share}` first)")
    ensemble = json.loads((Path(folder) / "ensemble.json").read_text()) if len(shares) == 1 else pooled_shares(shares)
    new = row_of(ensemble, model, variant, damping, commit)
    rows = list(csv.DictReader(table.open())) if table.exists() else []
    write_rows(table, [r for r in rows if (r["model"], r["variant"]) != (model, variant)] + [new])
    print(f"{table}: {model} {variant}, {new['members']} members")


if __name__ == "__main__":
    main(sys.argv)
