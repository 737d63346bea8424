#!/usr/bin/python3
"""How near a bridge's spandrel walls come to toppling out of plane, from a run's .vtu
frames: for each frame and each wall (y < 0, y > 0), how far its top course has moved
outwards (away from the bridge's axis) relative to its bottom course (the lean) and
relative to the top of the fill or soil column beside it (the gap), in m and as a share of
the wall's thickness t. A rigid leaf of height H and thickness t rocking about its outer
toe tips over when its top has moved about t outwards, so lean / t is how far the wall has
gone towards toppling as one leaf, and gap / t how far it has parted from the fill.

    /usr/bin/python3 scripts/wall_lean.py OUT.csv RUN_DIR [--every 1]

Prints each wall's largest lean and gap and when they happened.
"""
import argparse
import csv
import sys
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from run_outputs import PART, cell_array, frames, point_array, read_vtu  # noqa: E402


def read(vtu):
    grid = read_vtu(vtu)
    moved = point_array(grid, "displacement")
    points = vtk_to_numpy(grid.GetPoints().GetData())
    cells = grid.GetCells()
    offsets = vtk_to_numpy(cells.GetOffsetsArray())
    connectivity = vtk_to_numpy(cells.GetConnectivityArray())
    part, fallen = cell_array(grid, "part"), cell_array(grid, "fallen")
    blocks = []
    for c in range(grid.GetNumberOfCells()):
        idx = connectivity[offsets[c]:offsets[c + 1]]
        start = points[idx] - moved[idx]
        blocks.append((part[c], bool(fallen[c]), start, moved[idx].mean(axis=0)))
    return blocks


def groups(blocks):
    """Per side: block indices of the wall's top and bottom courses, of the fill column's top
    beside it, and the wall's thickness (from the first frame)."""
    out = {}
    for side in (-1, 1):
        wall = [i for i, b in enumerate(blocks) if b[0] == PART["wall"] and side * b[2][:, 1].mean() > 0]
        fill = [i for i, b in enumerate(blocks) if b[0] in (PART["fill"], PART["soil"]) and side * b[2][:, 1].mean() > 0]
        if not wall:
            continue
        z = {i: blocks[i][2][:, 2].mean() for i in wall + fill}
        stone = min(np.ptp(blocks[i][2][:, 2]) for i in wall)
        z_top, z_bottom = max(z[i] for i in wall), min(z[i] for i in wall)
        inner = max((side * blocks[i][2][:, 1].mean() for i in fill), default=None)
        out[side] = {
            "top": [i for i in wall if z[i] > z_top - 0.5 * stone],
            "bottom": [i for i in wall if z[i] < z_bottom + 0.5 * stone],
            "fill_top": [i for i in fill if abs(side * blocks[i][2][:, 1].mean() - inner) < 1e-6 and z[i] > z_top - 0.5 * stone],
            "thickness": float(np.median([np.ptp(blocks[i][2][:, 1]) for i in wall])),
        }
    return out


def outward(blocks, ids, side):
    """Mean outward y displacement of the blocks among ids still standing (m)."""
    d = [side * blocks[i][3][1] for i in ids if not blocks[i][1]]
    return float(np.mean(d)) if d else float("nan")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out")
    p.add_argument("run", type=Path)
    p.add_argument("--every", type=int, default=1, help="use every n-th frame")
    a = p.parse_args()
    series = frames(a.run)[:: a.every]
    sides = groups(read(series[0][1]))
    rows, largest = [], {}
    for time, vtu in series:
        blocks = read(vtu)
        row = [f"{time:.3f}"]
        for side, g in sides.items():
            top = outward(blocks, g["top"], side)
            lean = top - outward(blocks, g["bottom"], side)
            gap = top - outward(blocks, g["fill_top"], side)
            row += [f"{lean:.4f}", f"{gap:.4f}"]
            for what, value in (("lean", lean), ("gap", gap)):
                if value == value and value > largest.get((side, what), (-1e9, 0))[0]:
                    largest[(side, what)] = (value, time)
        rows.append(row)
    header = ["time_s"] + [f"{'minus' if s < 0 else 'plus'}_y_{w}_m" for s in sides for w in ("lean", "gap")]
    with open(a.out, "w", newline="") as f:
        csv.writer(f).writerows([header] + rows)
    for side, g in sides.items():
        t = g["thickness"]
        text = ", ".join(f"largest {w} {largest[(side, w)][0]:.3f} m = {largest[(side, w)][0] / t:.2f} t at {largest[(side, w)][1]:.2f} s"
                         for w in ("lean", "gap") if (side, w) in largest)
        print(f"{'-' if side < 0 else '+'}y wall (t = {t:.2f} m, top course {len(g['top'])} stones): {text}")
    print(f"wall_lean: {len(rows)} frames in {a.out} (times are the run's, settling included)")


if __name__ == "__main__":
    main()
