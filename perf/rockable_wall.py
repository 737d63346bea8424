#!/usr/bin/env python3
"""Writes wall_benchmark's wall (1,534 cubes of 0.64 m in two leaves of running bond,
30 / 29 stones per course, 26 courses, on a fixed base) as an input for Rockable, the
public sphero-polyhedral DEM code, for the side-by-side of perf/results/README.md.
Nothing of Rockable is in this project: build it from its own source to run this.
    [VERLET_STEPS=250] python3 perf/rockable_wall.py OUT_DIR [STEPS] [STEPS_PER_REPORT]
writes OUT_DIR/input.txt and OUT_DIR/shapes.shp; then `rockable -j THREADS input.txt`
in OUT_DIR, and perf.txt there holds simulated seconds per wall second per report.

Same dt (4e-5 s), stone (0.64 m, 1,880 kg/m^3, friction 33.23 deg) and layout as
wall_benchmark. Rockable's stones are sphero-polyhedra: the cube's corners sit 0.02 m
inside and a 0.02 m sphere sweeps them, so the outer faces are where ishibashi's are.
Its contact law is one linear spring per vertex-face / edge-edge point (no areas), so
the stiffness is set per point (1e9 N/m, about ishibashi's face stiffness of 9e9 N/m
shared by its points) with restitution^2 0.1; only the cost per step is compared, not
the physics. VERLET_STEPS: steps between Rockable's neighbour-list updates."""
import math
import os
import sys

STONE, RADIUS = 0.64, 0.02  # m: cube edge, Rockable's sweeping sphere
COURSES, STONES, LEAVES = 26, 30, 2
DT = 4e-5
VERLET_STEPS = int(os.environ.get("VERLET_STEPS", 250))  # steps between its neighbour-list updates


def shape(name, half):
    """A box of half-sizes `half` (m) as a Rockable shape: its corners moved in by RADIUS."""
    hx, hy, hz = (h - RADIUS for h in half)
    corners = [(sx * hx, sy * hy, sz * hz) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    edges = [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]  # outward
    a, b, c = (2 * h for h in half)
    lines = ["<", f"name {name}", f"radius {RADIUS}", "preCompDone y", f"nv {len(corners)}"]
    lines += [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in corners]
    lines += [f"ne {len(edges)}"] + [f"{i} {j}" for i, j in edges]
    lines += [f"nf {len(faces)}"] + ["4 " + " ".join(map(str, f)) for f in faces]
    lines += [f"obb.extent {half[0]} {half[1]} {half[2]}", "obb.e1 1 0 0", "obb.e2 0 1 0", "obb.e3 0 0 1",
              "obb.center 0 0 0", f"volume {a * b * c:.9g}",
              f"I/m {(b * b + c * c) / 12:.9g} {(a * a + c * c) / 12:.9g} {(a * a + b * b) / 12:.9g}", ">", ""]
    return "\n".join(lines)


def main():
    out = sys.argv[1]
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    per_report = int(sys.argv[3]) if len(sys.argv) > 3 else 200
    os.makedirs(out, exist_ok=True)
    length, depth = STONES * STONE, LEAVES * STONE
    base_half = (0.5 * length + STONE, 0.5 * depth + STONE, 0.25)
    with open(os.path.join(out, "shapes.shp"), "w") as f:
        f.write(shape("Base", base_half) + shape("Stone", (0.5 * STONE,) * 3))
    bodies = [("Base", (0.5 * length, 0.5 * depth, -0.25))]  # the first nDriven bodies do not move
    for course in range(COURSES):
        odd = course % 2 == 1
        for leaf in range(LEAVES):
            for k in range(STONES - 1 if odd else STONES):
                bodies.append(("Stone", ((k + 0.5 + (0.5 if odd else 0)) * STONE, (leaf + 0.5) * STONE,
                                         (course + 0.5) * STONE)))
    mu = math.tan(math.radians(33.23))
    head = f"""Rockable 21-08-2022
t 0
tmax {steps * DT:.9g}
dt {DT}
interVerlet {VERLET_STEPS * DT:.9g}
interConf {per_report * DT:.9g}
DVerlet 0.02
dVerlet 0.01
density 0 1880
density 1 1880
gravity 0 0 -9.81
forceLaw Default
knContact 0 0 1e9
en2Contact 0 0 0.1
ktContact 0 0 1e9
muContact 0 0 {mu:.6f}
knContact 0 1 1e9
en2Contact 0 1 0.1
ktContact 0 1 1e9
muContact 0 1 {mu:.6f}
iconf 0
nDriven 1
shapeFile shapes.shp
Particles {len(bodies)}
"""
    rows = [f"{name} {1 if name == 'Base' else 0} 0 1   {x:.6f} {y:.6f} {z:.6f}   0 0 0   0 0 0   1 0 0 0   0 0 0   0 0 0"
            for name, (x, y, z) in bodies]
    with open(os.path.join(out, "input.txt"), "w") as f:
        f.write(head + "\n".join(rows) + "\n")
    print(f"{len(bodies)} bodies, {steps} steps of {DT} s, a report every {per_report} steps")


if __name__ == "__main__":
    main()
