# Loads a run's view.pvsm in ParaView (pvbatch) as a user would after moving the run's
# folder: files looked up in the state file's folder. Checks that the standing stones,
# the cracked joints and the colour scale come out as the state says, renders the last
# frame to view.png, and exits non-zero on any failure.
#   pvbatch paraview_state_check.py RUN_DIR PNG_DIR
import os
import sys

from paraview.simple import FindSource, GetActiveView, GetAnimationScene, GetSources, LoadState, SaveScreenshot

run_dir, png_dir = os.path.abspath(sys.argv[1]), sys.argv[2]
state = os.path.join(run_dir, "view.pvsm")
LoadState(state, data_directory=run_dir)
failures = []
names = sorted(name for name, _ in GetSources().keys())
tied = os.path.exists(os.path.join(run_dir, "ties.pvd"))
for wanted in ("blocks.pvd", "contacts.pvd", "standing stones", "fallen stones", "cracked joints") + (("ties.pvd",) if tied else ()):
    if wanted not in names:
        failures.append("view.pvsm has no source '%s' (it has %s)" % (wanted, ", ".join(names)))
scene = GetAnimationScene()
blocks = FindSource("blocks.pvd")
times = list(blocks.TimestepValues) if blocks and blocks.TimestepValues else []
if not times or abs(scene.StartTime - times[0]) > 1e-9 or abs(scene.EndTime - times[-1]) > 1e-9:
    failures.append("the animation runs %g to %g s, the series %s" % (scene.StartTime, scene.EndTime, times[:1] + times[-1:]))
if abs(scene.AnimationTime - scene.StartTime) > 1e-9:
    failures.append("the state opens at %g s, not at the first frame" % scene.AnimationTime)
scene.AnimationTime = scene.EndTime
counts = {}
for name in ("standing stones", "fallen stones", "cracked joints") + (("ties.pvd",) if tied else ()):
    source = FindSource(name)
    if source:
        source.UpdatePipeline(scene.EndTime)
        counts[name] = source.GetDataInformation().GetNumberOfCells()
# Every array the state thresholds or colours by, among those the run wrote.
for reader, data, arrays in (("blocks.pvd", "CellData", ("part", "fallen", "displacement_relative_to_ground")),
                             ("contacts.pvd", "PointData", ("joint_cracked",))) + (
                                 (("ties.pvd", "CellData", ("tension_n",)),) if tied else ()):
    source = FindSource(reader)
    written = getattr(source, data).keys() if source else []
    for array in arrays:
        if array not in written:
            failures.append("%s: the state uses %s, which the run did not write" % (reader, array))
shown = counts.get("standing stones", 0) + counts.get("fallen stones", 0)
if shown == 0:
    failures.append("no stones shown at the last frame")
blocks = FindSource("blocks.pvd")
blocks.UpdatePipeline(scene.EndTime)
# A generated bridge's ground slab (part 0) is hidden; an imported model has no slab (its
# blocks are all part 6, its fixed ones included) and shows every block.
has_slab = "part" in blocks.CellData.keys() and blocks.CellData["part"].GetRange()[0] == 0
if has_slab and shown >= blocks.GetDataInformation().GetNumberOfCells():
    failures.append("the ground slab is not hidden (%d of %d blocks shown)" % (shown, blocks.GetDataInformation().GetNumberOfCells()))
png = os.path.join(png_dir, "view.png")
SaveScreenshot(png, GetActiveView(), ImageResolution=[1280, 720])
print("view.pvsm: %d frames from %g to %g s; at the last: %s; rendered to %s" % (
    len(times), scene.StartTime, scene.EndTime, ", ".join("%d %s" % (n, k) for k, n in counts.items()), png))
if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
