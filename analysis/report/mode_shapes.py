#!/usr/bin/python3
"""Pictures of a modal analysis: the first mode of each axis (the first with more than 5 %
effective mass along it, as `modal` and the study's tables take it), the blocks deformed
by the mode and drawn over the undeformed outline, from the front (looking along +y) and
from above, coloured by the displacement's size. One PNG per analysis folder:

    /usr/bin/python3 analysis/report/mode_shapes.py FOLDER [TITLE]   (FOLDER: modes.csv, modes.vtu)

writes FOLDER/mode_shapes.png. `ishibashi modal` calls it; the study's report draws one per
frequency analysis. A mode's scale is arbitrary (mass-normalised): the largest displacement
is drawn as a tenth of the model's largest dimension.
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run_outputs import read_rows, read_vtu, save_figure, surface  # noqa: E402

EFFECTIVE_MASS_SHARE = 0.05  # a first mode along an axis carries more than this of the mass
VIEWS = (("the front", 0, -90), ("above", 90, -90))  # (from where, elevation, azimuth), degrees
DRAWN_SCALE = 0.1  # the largest displacement drawn, as a share of the model's largest dimension


def first_modes(folder):
    """[(axis letter, mode number, frequency Hz)] of the first mode along x, y and z."""
    rows = read_rows(Path(folder) / "modes.csv")
    found = []
    for axis in "xyz":
        for r in rows:
            if float(r[f"effective_mass_{axis}"]) > EFFECTIVE_MASS_SHARE:
                found.append((axis, int(r["mode"]), float(r["frequency_hz"])))
                break
    return found


def mode_surface(grid, modes):
    """The faces of the blocks other than the ground slab: each face's corners (m) and, per
    mode number, its corners' displacements; and the model's largest dimension (m)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    poly, points, _, corners = surface(grid)
    shapes = {k: vtk_to_numpy(poly.GetPointData().GetArray(f"mode_{k}")) for k in modes}
    used = points[sorted({int(c) for face in corners for c in face})] if corners else points
    size = float((used.max(axis=0) - used.min(axis=0)).max()) if len(used) else 1.0
    return [points[c] for c in corners], {k: [d[c] for c in corners] for k, d in shapes.items()}, size


def mode_shape_figure(folder, title, path=None):
    """FOLDER/mode_shapes.png (or `path`): a row per first mode, a column per view."""
    folder = Path(folder)
    modes = first_modes(folder)
    if not modes or not (folder / "modes.vtu").exists():
        return None
    faces, shapes, size = mode_surface(read_vtu(folder / "modes.vtu"), [k for _, k, _ in modes])
    fig = plt.figure(figsize=(4.2 * len(VIEWS), 2.8 * len(modes)))
    for row, (axis, k, hz) in enumerate(modes):
        moved = shapes[k]
        largest = max((math.sqrt(float((d ** 2).sum(axis=1).max())) for d in moved), default=0.0)
        scale = DRAWN_SCALE * size / largest if largest > 0 else 0.0
        deformed = [f + scale * d for f, d in zip(faces, moved)]
        amount = [math.sqrt(float((d ** 2).sum(axis=1).mean())) / largest if largest > 0 else 0.0 for d in moved]
        colours = [plt.cm.viridis(a) for a in amount]
        for column, (view, elevation, azimuth) in enumerate(VIEWS):
            a = fig.add_subplot(len(modes), len(VIEWS), row * len(VIEWS) + column + 1, projection="3d")
            a.add_collection3d(Poly3DCollection(faces, facecolors=(0, 0, 0, 0), edgecolors=(0.6, 0.6, 0.6, 0.35),
                                                linewidths=0.2))
            a.add_collection3d(Poly3DCollection(deformed, facecolors=colours, edgecolors=(0, 0, 0, 0.3), linewidths=0.2))
            everything = [p for f in faces + deformed for p in f]
            lo = [min(p[i] for p in everything) for i in range(3)]
            hi = [max(p[i] for p in everything) for i in range(3)]
            a.set_xlim(lo[0], hi[0])
            a.set_ylim(lo[1], hi[1])
            a.set_zlim(lo[2], hi[2])
            a.set_box_aspect([max(hi[i] - lo[i], 1e-3) for i in range(3)])
            a.view_init(elev=elevation, azim=azimuth)
            a.set_axis_off()
            a.set_title(f"mode {k}, first along {axis}: {hz:.2f} Hz, from {view}", fontsize=8)
    fig.suptitle(f"{title}: first modes (grey: undeformed)", fontsize=10)
    fig.tight_layout()
    path = Path(path) if path else folder / "mode_shapes.png"
    save_figure(fig, path, dpi=90)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: mode_shapes.py FOLDER [TITLE]")
    folder = Path(sys.argv[1])
    path = mode_shape_figure(folder, sys.argv[2] if len(sys.argv) == 3 else folder.name)
    if path is None:
        sys.exit(f"mode_shapes.py: {folder} has no modes.csv with a first mode, or no modes.vtu")
    print(f"mode shapes: {path}")


if __name__ == "__main__":
    main()
