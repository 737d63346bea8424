#!/usr/bin/python3
"""How a bridge's mortar fails, frame by frame, from a run's contact frames: for each frame
between FROM and TO s of shaking, the joints that lost bonded sub-contacts since the frame
before, where they are (x, y, z of a point of the joint), the three commonest interfaces
(parts of the two blocks; bed: a horizontal joint, head: a vertical one), and the median
of their bonds' largest tension and shear utilisation in the frame before,
sigma / f_t and tau / (c - sigma tan phi) (f_t = c = 0.2 MPa, phi = 33.23 degrees).

    /usr/bin/python3 scripts/bond_cascade.py RUN_DIR FROM TO

Frames closer than the run's 0.05 s default show the path (a run with output_interval_s =
0.005: scenarios/results/README.md).
"""
import collections
import os
import sys
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy as v2n

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from run_outputs import PART_NAME, cell_array, point_array, read_rows, read_vtu  # noqa: E402

base = sys.argv[1]
rows = read_rows(base + '/history.csv')
settled = [float(r['time_s']) for r in rows if r['phase'] == 'settle']
interval = float(rows[1]['time_s']) - float(rows[0]['time_s'])
t0_frame = int(round(settled[-1] / interval)) if settled else 0  # the frame where shaking began
part = cell_array(read_vtu(base + '/blocks_000000.vtu'), 'part')
names = PART_NAME
ft = 2e5; c = 2e5; tanphi = np.tan(np.radians(33.23))
def per_pair(i):
    o = read_vtu(f'{base}/contacts_{i:06d}.vtu'); g = lambda n: point_array(o, n)
    p, st, s, t, a, b, n = v2n(o.GetPoints().GetData()), g('state'), g('normal_stress_pa'), g('shear_stress_pa'), g('block_a'), g('block_b'), g('normal')
    d = {}
    for k in np.nonzero(st == 0)[0]:
        key = (a[k], b[k]); ut = s[k] / ft; us = t[k] / (c - s[k] * tanphi)
        cnt, mt, ms, P, hz = d.get(key, (0, -9, -9, p[k], abs(n[k, 2]) > 0.7))
        d[key] = (cnt + 1, max(mt, ut), max(ms, us), P, hz)
    return d
start, end = [int(round(float(x) / interval)) + t0_frame for x in sys.argv[2:4]]
prev = per_pair(start - 1)
total = 0
for i in range(start, end + 1):
    if not os.path.exists(f'{base}/contacts_{i:06d}.vtu'): break
    cur = per_pair(i)
    ev = []
    for key, (cnt, mt, ms, P, hz) in prev.items():
        if cur.get(key, (0,))[0] >= cnt: continue
        pa, pb = sorted((names.get(part[key[0]], '?'), names.get(part[key[1]], '?')))
        ev.append((pa + '-' + pb + ('/bed' if hz else '/head'), P, mt, ms))
    total += len(ev)
    if ev:
        P = np.array([e[1] for e in ev]); by = collections.Counter(e[0] for e in ev).most_common(3)
        print(f"{(i - t0_frame) * interval:6.3f} {len(ev):5d} (total {total:6d}) x {P[:,0].min():+6.1f}..{P[:,0].max():+6.1f} y {P[:,1].min():+5.1f}..{P[:,1].max():+5.1f} z {P[:,2].min():4.1f}..{P[:,2].max():4.1f}  util t {np.median([e[2] for e in ev]):+.2f} s {np.median([e[3] for e in ev]):.2f}  {by}")
    prev = cur
