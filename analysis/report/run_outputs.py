"""Readers of the program's outputs, shared by the report (report.py beside this file) and
the scripts (which put this folder on their path): summary.json and the tables (runs.csv,
sweep.csv, history.csv, ...) under the names the program writes now (analysis/run/
run_result.cpp, run_recorder.cpp), whatever program wrote them, and the ParaView series."""
import csv
import json
import os
import xml.etree.ElementTree as ET
from pathlib import Path

# The generator's part numbers (geometry/bridge.h, enum Part; the cell array "part" of
# blocks_*.vtu). Checked against the C++ enum by BridgeParts.PythonReadersKnowEveryPart.
PART = {"ground": 0, "ring": 1, "wall": 2, "fill": 3, "soil": 4, "side_wall": 5, "imported": 6}
PART_NAME = {number: name for name, number in PART.items()}

# Names of earlier programs -> today's.
RENAMED = {
    "first_opening_time_s": "first_opening_s", "wall_time_s": "wall_s",  # summary.json
    "shaking_s": "shaking_time_s",  # runs.csv, sweep.csv
    "open_joints": "joints_open", "cracked_joints": "joints_cracked", "slipped_joints": "joints_slipped",  # history.csv
    "fallen_blocks": "fallen_stones", "left_model_blocks": "blocks_left_model",
}


def _today(row):
    for old, new in RENAMED.items():
        if old in row:
            row.setdefault(new, row.pop(old))
    if "energy_balance_pct" in row:  # a percentage then, a fraction now
        pct = row.pop("energy_balance_pct")
        try:
            row.setdefault("energy_balance_error_relative", repr(float(pct) / 100))
        except (TypeError, ValueError):
            row.setdefault("energy_balance_error_relative", pct)
    return row


def read_summary(run):
    """A run folder's summary.json as a dict (first_opening_s is None when no joint opened)."""
    return _today(json.loads((Path(run) / "summary.json").read_text()))


def save_figure(fig, path, dpi=110):
    """Writes a matplotlib figure to `path` whole or not at all (a temporary name, then a
    rename, as the program writes its files) and returns the path."""
    path = Path(path)
    temporary = path.with_name(f"{path.stem}.tmp{os.getpid()}{path.suffix}")
    try:
        fig.savefig(temporary, dpi=dpi, bbox_inches="tight")
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


def read_rows(path):
    """A CSV table's rows as dicts; no rows when the file does not exist."""
    path = Path(path)
    if not path.exists():
        return []
    with open(path, newline="") as f:
        return [_today(row) for row in csv.DictReader(f)]


def settle_end_s(run):
    """When a run's shaking began: the time of its last settling row in history.csv."""
    settled = [float(r["time_s"]) for r in read_rows(Path(run) / "history.csv") if r["phase"] == "settle"]
    return settled[-1] if settled else 0.0


def frames(run, series="blocks"):
    """(time s, .vtu path) of each frame of a run's series ("blocks" or "contacts")."""
    pvd = Path(run) / f"{series}.pvd"
    if not pvd.exists():
        return []
    return [(float(d.get("timestep")), pvd.parent / d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]


def read_vtu(path):
    """A .vtu file (vtkUnstructuredGrid), read with Debian's VTK."""
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def cell_array(grid, name):
    """A cell array of a grid as numpy (blocks: part, fallen, block_id, displacement, ...)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(grid.GetCellData().GetArray(name))


def point_array(grid, name):
    """A point array of a grid as numpy (contacts: joint_cracked, normal_stress_pa, ...)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(grid.GetPointData().GetArray(name))


def surface(grid):
    """A grid's block faces as VTK's surface filter gives them: the polydata (its cell data
    is the blocks', per face), its points as numpy (m), and each face's corner indices,
    the ground slab's faces left out."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersGeometry import vtkDataSetSurfaceFilter

    faces = vtkDataSetSurfaceFilter()
    faces.SetInputData(grid)
    faces.Update()
    poly = faces.GetOutput()
    points = vtk_to_numpy(poly.GetPoints().GetData())
    offsets = vtk_to_numpy(poly.GetPolys().GetOffsetsArray())
    connectivity = vtk_to_numpy(poly.GetPolys().GetConnectivityArray())
    part = poly.GetCellData().GetArray("part")  # absent from modes.vtu of programs before 2026-11
    kept = [i for i in range(len(offsets) - 1) if part is None or part.GetValue(i) != PART["ground"]]
    return poly, points, kept, [connectivity[offsets[i]:offsets[i + 1]] for i in kept]
