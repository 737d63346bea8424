#!/usr/bin/python3
"""Runs of one scenario against a reference run, through time: the monitored (crown) unit's
displacement, the joints cracked and the largest opening at chosen seconds of shaking,
the first opening and the bond utilisation's peak until then (how close the mortar came
to cracking), from each run folder's history.csv and summary.json. For
convergence studies (a step against a smaller one, a scheme against another) on the
quantities that are not chaotic before the structure cracks.

    scripts/compare_histories.py REFERENCE RUN [RUN ...] [--at 1,2,3,3.5] [--column NAME]

Prints a Markdown table: per run, the crown unit's displacement (the length of its
dx, dy, dz relative to the ground) at each time, or history.csv's column NAME there
(bond_utilisation, joints_open, ...), and its difference from the reference's as a share
of it, then the joints cracked and the first opening.
"""
import argparse
import csv
import json
import math
from pathlib import Path


def shaking_rows(folder):
    """(seconds of shaking, row) of history.csv's shaking frames."""
    settle = json.load(open(folder / "summary.json"))["settle_time_s"]
    rows = [r for r in csv.DictReader(open(folder / "history.csv")) if r["phase"] == "shake"]
    return [(float(r["time_s"]) - settle, r) for r in rows]


def at(rows, t):
    """The frame nearest t seconds of shaking (None beyond the run's end)."""
    if not rows or t > rows[-1][0] + 0.03:
        return None
    return min(rows, key=lambda r: abs(r[0] - t))[1]


def crown(row):
    keys = [k for k in row if k.startswith("block") and k.endswith("_dx_m")]
    if not keys:
        return math.nan
    block = keys[0][: -len("_dx_m")]
    return math.sqrt(sum(float(row[f"{block}_d{a}_m"]) ** 2 for a in "xyz"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("reference", type=Path)
    parser.add_argument("runs", type=Path, nargs="+")
    parser.add_argument("--at", default="1,2,3,3.5", help="seconds of shaking, comma-separated")
    parser.add_argument("--column", help="history.csv's column to compare at those times (default: the crown's displacement)")
    o = parser.parse_args()
    times = [float(t) for t in o.at.split(",")]
    reference = shaking_rows(o.reference)
    if o.column and o.column not in reference[0][1]:
        parser.error(f"{o.reference}/history.csv has no column {o.column}: it has {', '.join(reference[0][1])}")
    quantity = (lambda row: float(row[o.column] or "nan")) if o.column else crown
    name = o.column or "crown [m]"
    header = ["run"] + [f"{name} at {t:g} s / diff" for t in times] + [
        f"joints cracked at {times[-1]:g} s", "first opening [s]", "bond utilisation peak"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for folder in [o.reference] + o.runs:
        rows = shaking_rows(folder)
        cells = [folder.name]
        for t in times:
            row, ref = at(rows, t), at(reference, t)
            if row is None:
                cells.append("-")
                continue
            value = quantity(row)
            diff = "" if folder == o.reference or ref is None else f" / {100 * (value / quantity(ref) - 1):+.1f} %"
            cells.append(f"{value:.3g}{diff}")
        last = at(rows, times[-1])
        cells.append(last["joints_cracked"] if last else "-")
        summary = json.load(open(folder / "summary.json"))
        opening = summary.get("first_opening_s")
        cells.append("none" if opening is None or opening < 0 else f"{opening:.3f}")
        peak = summary.get("bond_utilisation_peak")  # programs before it, and dry runs: none
        cells.append("-" if peak is None else f"{peak:.3f}")
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
