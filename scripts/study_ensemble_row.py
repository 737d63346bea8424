#!/usr/bin/env python3
"""An ensemble's row of scenarios/results/study_ensembles.csv (issue 48 item 5), written in
place of that model and variant's row (the others kept, rows sorted):
   study_ensemble_row.py ENSEMBLE_DIR MODEL VARIANT DAMPING COMMIT [CSV]
ENSEMBLE_DIR holds the ensemble.json of `ishibashi run --members N`; MODEL a-f, VARIANT
dry|mortar, DAMPING study|implicit|capped, COMMIT the program that ran it."""
import csv
import json
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


def main(argv):
    if len(argv) not in (6, 7) or argv[3] not in ("dry", "mortar") or argv[2] not in "abcdef" or len(argv[2]) != 1:
        sys.exit(__doc__)
    folder, model, variant, damping, commit = argv[1:6]
    table = Path(argv[6]) if len(argv) == 7 else DEFAULT_CSV
    source = Path(folder) / "ensemble.json"
    if not source.exists():
        sys.exit(f"{source}: no ensemble.json (run `ishibashi run SCENARIO --members N --out {folder}` first)")
    new = row_of(json.loads(source.read_text()), model, variant, damping, commit)
    rows = list(csv.DictReader(table.open())) if table.exists() else []
    rows = [r for r in rows if (r["model"], r["variant"]) != (model, variant)] + [new]
    rows.sort(key=lambda r: (r["model"], r["variant"]))
    with table.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    print(f"{table}: {model} {variant}, {new['members']} members")


if __name__ == "__main__":
    main(sys.argv)
