#!/usr/bin/python3
"""What the mortar of a bridge would have to carry, from a run whose bonds cannot break
(mortar_pa set far above any stress, so every joint originally in contact stays linear):
for each contact frame, the stone-stone sub-contacts originally in contact, their tension
and shear utilisation against a given strength (f_t = c, MODEL.md section 3):
sigma / f_t and tau / (c - sigma tan(phi)), and how many of them are at or past 1 (those
a bond of that strength would lose), by height band.

    /usr/bin/python3 scripts/bond_demand.py RUN_DIR [--strength 2e5] [--from 0] [--to 1e9]

Times are the run's (settling included). Ground joints (soil, never bonded) are left out.
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from run_outputs import PART, cell_array, frames, point_array, read_vtu  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", type=Path)
    p.add_argument("--strength", type=float, default=2e5, help="f_t = c, Pa")
    p.add_argument("--friction-deg", type=float, default=33.23, help="stone-stone friction angle")
    p.add_argument("--from", dest="t0", type=float, default=0.0)
    p.add_argument("--to", dest="t1", type=float, default=1e9)
    p.add_argument("--bands", type=float, nargs="+", default=[0, 1.5, 3, 4.5, 100], help="height band edges, m")
    a = p.parse_args()
    tan_phi = math.tan(math.radians(a.friction_deg))

    blocks = read_vtu(frames(a.run)[0][1])
    part, block_id = cell_array(blocks, "part"), cell_array(blocks, "block_id")
    ground = set(block_id[part == PART["ground"]].tolist())

    bands = a.bands
    print(f"strength {a.strength:.3g} Pa; per frame: stone-stone sub-contacts originally in contact, "
          f"the share at or past their strength (tension or shear), the median and 99th percentile utilisation, "
          f"and the share past strength by height band {bands}")
    for t, vtu in frames(a.run, "contacts"):
        if t < a.t0 or t > a.t1:
            continue
        g = read_vtu(vtu)
        original = point_array(g, "original") == 1
        ba, bb = point_array(g, "block_a"), point_array(g, "block_b")
        stone = original & ~np.isin(ba, list(ground)) & ~np.isin(bb, list(ground))
        sigma = point_array(g, "normal_stress_pa")[stone]
        tau = point_array(g, "shear_stress_pa")[stone]
        z = vtk_to_numpy(g.GetPoints().GetData())[stone, 2]
        room = a.strength - sigma * tan_phi
        shear_use = np.where(room > 0, tau / np.maximum(room, 1e-30), np.inf)
        use = np.maximum(sigma / a.strength, shear_use)
        past = use >= 1
        by_band = []
        for lo, hi in zip(bands[:-1], bands[1:]):
            inside = (z >= lo) & (z < hi)
            by_band.append(f"{100 * past[inside].mean():5.1f}" if inside.any() else "   - ")
        finite = use[np.isfinite(use)]
        print(f"{t:6.2f} s  {stone.sum():6d} points  past {100 * past.mean():5.1f} %  "
              f"median {np.median(finite):5.2f}  p99 {np.percentile(finite, 99):6.2f}  bands % " + " ".join(by_band), flush=True)


if __name__ == "__main__":
    main()
