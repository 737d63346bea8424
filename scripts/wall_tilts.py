#!/usr/bin/python3
"""Out-of-plane tilt of a bridge's spandrel walls through a run, from its .vtu frames: for
each frame (every STEP s of shaking), the mean rotation about x (the bridge's axis) of the
wall stones whose centre starts above Z_MIN m, for the wall on each side (y < 0, y > 0),
in mrad (negative: the top moves towards +y), and the stones fallen by then. Several runs
side by side, one CSV row per time:

    /usr/bin/python3 scripts/wall_tilts.py OUT.csv RUN_DIR [RUN_DIR ...] [--step 0.25] [--z-min 3]

A stone's rotation is the least-squares rotation about x of its vertices' displacements
about their mean (small angles; a fallen stone is left out).
"""
import argparse
import csv
import math
import sys
from pathlib import Path

from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from run_outputs import PART, cell_array, frames, point_array, read_vtu, settle_end_s  # noqa: E402


def wall_tilts(vtu, z_min):
    """(mean tilt of the y < 0 wall, of the y > 0 wall) in mrad, and the stones fallen."""
    grid = read_vtu(vtu)
    moved = point_array(grid, "displacement")
    points = vtk_to_numpy(grid.GetPoints().GetData())
    part, fallen = cell_array(grid, "part"), cell_array(grid, "fallen")
    sides = {-1: [], 1: []}
    for c in range(grid.GetNumberOfCells()):
        if part[c] != PART["wall"] or fallen[c]:
            continue
        ids = grid.GetCell(c).GetPointIds()
        idx = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
        start = points[idx] - moved[idx]
        centre = start.mean(axis=0)
        if centre[2] < z_min:
            continue
        d = moved[idx] - moved[idx].mean(axis=0)
        r = start - centre
        angle = (d[:, 2] * r[:, 1] - d[:, 1] * r[:, 2]).sum() / (r[:, 1] ** 2 + r[:, 2] ** 2).sum()
        sides[1 if centre[1] > 0 else -1].append(angle)
    mean = [1000 * sum(a) / len(a) if a else math.nan for a in (sides[-1], sides[1])]
    return mean, int(fallen.sum())


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out")
    p.add_argument("runs", nargs="+", type=Path)
    p.add_argument("--step", type=float, default=0.25)
    p.add_argument("--z-min", type=float, default=3.0)
    a = p.parse_args()
    series = {run: (frames(run), settle_end_s(run)) for run in a.runs}
    end = max(s[-1][0] - t0 for s, t0 in series.values())
    header = ["shaking_s"] + [f"{run.name}_{c}" for run in a.runs for c in ("minus_y_mrad", "plus_y_mrad", "fallen")]
    rows = []
    for k in range(int(end / a.step + 1e-9) + 1):
        t = k * a.step
        row = [f"{t:.2f}"]
        for run, (s, t0) in series.items():
            time, vtu = min(s, key=lambda f: abs(f[0] - t0 - t))
            if abs(time - t0 - t) > 0.5 * a.step:
                row += ["", "", ""]
                continue
            (minus, plus), fallen = wall_tilts(vtu, a.z_min)
            row += [f"{minus:.1f}", f"{plus:.1f}", str(fallen)]
        rows.append(row)
    with open(a.out, "w", newline="") as f:
        csv.writer(f).writerows([header] + rows)
    print(f"wall_tilts: {len(rows)} times x {len(a.runs)} runs in {a.out}")


if __name__ == "__main__":
    main()
