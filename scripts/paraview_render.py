# Opens a run's blocks.pvd and contacts.pvd (and ties.pvd, where it has one) in ParaView (pvbatch), checks that every
# frame loads with the cells, points and arrays the README promises, and renders the
# last frame of each to a PNG, and the contacts' force_n as arrows (force_chains.png). Exits
# non-zero on any failure.
#   pvbatch paraview_render.py RUN_DIR PNG_DIR
import os
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, GetActiveViewOrCreate, Glyph, Hide, PVDReader, ResetCamera, SaveScreenshot, Show)

run_dir, png_dir = sys.argv[1], sys.argv[2]
expected = {
    "blocks": ("CELLS", ["displacement_relative_to_ground", "displacement", "velocity", "fallen", "part"]),
    "contacts": ("POINTS", ["state", "force_n", "opening_m", "slip_m", "bond_damage", "bond_utilisation", "joint_opening_m", "joint_slip_m",
                            "joint_cracked"]),
}
if os.path.exists(os.path.join(run_dir, "ties.pvd")):  # a model with tie rods: a line each
    expected["ties"] = ("CELLS", ["tension_n", "peak_tension_n", "plastic_elongation_m", "yielded", "tie_id"])
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1280, 720]
failures = []
for name, (association, arrays) in expected.items():
    reader = PVDReader(FileName=os.path.join(run_dir, name + ".pvd"))
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    for t in times:
        reader.UpdatePipeline(t)
        info = reader.GetDataInformation()
        count = info.GetNumberOfCells() if association == "CELLS" else info.GetNumberOfPoints()
        if count == 0:
            failures.append("%s at t = %g: no %s" % (name, t, association.lower()))
        attributes = reader.CellData if association == "CELLS" else reader.PointData
        missing = [a for a in arrays if a not in attributes.keys()]
        if missing:
            failures.append("%s at t = %g: arrays %s missing" % (name, t, ", ".join(missing)))
    view.ViewTime = times[-1]
    reader.UpdatePipeline(times[-1])
    display = Show(reader, view)
    ColorBy(display, (association, arrays[0]))
    display.RescaleTransferFunctionToDataRange(False, True)
    if name == "contacts":
        display.SetRepresentationType("Points")
        display.PointSize = 3
    # From the side of the bridge (-y), a little above: the arch and what fell.
    view.CameraPosition = [0.0, -60.0, 20.0]
    view.CameraFocalPoint = [0.0, 0.0, 2.0]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    ResetCamera()
    view.OrientationAxesVisibility = 1
    display.SetScalarBarVisibility(view, True)
    png = os.path.join(png_dir, name + ".png")
    SaveScreenshot(png, view, ImageResolution=[1280, 720])
    print("%s: %d frames, last frame %d %s, rendered to %s" % (name, len(times), count, association.lower(), png))
    if name == "contacts":  # the force chains: an arrow per point along force_n, scaled by it
        arrows = Glyph(Input=reader, GlyphType="Arrow")
        arrows.OrientationArray = ["POINTS", "force_n"]
        arrows.ScaleArray = ["POINTS", "force_n"]
        arrows.GlyphMode = "All Points"
        largest = reader.PointData["force_n"].GetRange(-1)[1] or 1.0  # the largest magnitude
        arrows.ScaleFactor = 1.0 / largest  # the largest force 1 m long
        Hide(reader, view)
        glyphs = Show(arrows, view)
        ColorBy(glyphs, ("POINTS", "force_n", "Magnitude"))
        glyphs.RescaleTransferFunctionToDataRange(False, True)
        glyphs.SetScalarBarVisibility(view, True)
        arrows.UpdatePipeline(times[-1])
        if arrows.GetDataInformation().GetNumberOfPoints() == 0:
            failures.append("contacts: the force_n glyphs drew nothing")
        SaveScreenshot(os.path.join(png_dir, "force_chains.png"), view, ImageResolution=[1280, 720])
        Hide(arrows, view)
    Hide(reader, view)

if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("ParaView read every frame")
