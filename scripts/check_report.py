#!/usr/bin/python3
"""Checks a study report's animations as a reader gets them: one GIF per run with a frame
for each output frame of its shaking (at most report.ANIMATION_FRAMES), the size the report
draws, at most a few MB, and played inline by report.html.

    /usr/bin/python3 scripts/check_report.py OUT        (OUT: the study's output folder)
"""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "analysis" / "report"))
from report import ANIMATION_FRAMES  # noqa: E402
from run_outputs import read_rows  # noqa: E402

MAX_BYTES = 5 * 1024 * 1024
out = Path(sys.argv[1])
failures = []
html = (out / "report.html").read_text()
runs = read_rows(out / "runs.csv")
for run in runs:
    name = run["scenario"]
    t0, shaking = float(run["settle_time_s"]), float(run["shaking_time_s"])
    times = [float(d.get("timestep")) for d in ET.parse(out / "runs" / name / "blocks.pvd").getroot().iter("DataSet")]
    expected = min(ANIMATION_FRAMES, sum(1 for t in times if t0 - 1e-9 <= t <= t0 + shaking + 1e-9))
    gif = out / "figures" / f"animation_{name}.gif"
    if not gif.exists():
        failures.append(f"{name}: no {gif.name}")
        continue
    with Image.open(gif) as image:
        frames, size = image.n_frames, image.size
    if frames != expected:
        failures.append(f"{name}: {frames} frames in the animation, {expected} output frames of shaking")
    if size != (800, 288):
        failures.append(f"{name}: animation of {size[0]} x {size[1]} pixels, not 800 x 288")
    if gif.stat().st_size > MAX_BYTES:
        failures.append(f"{name}: animation of {gif.stat().st_size} bytes, more than {MAX_BYTES}")
    if f"alt='animation_{name}' src='data:image/gif;base64," not in html:
        failures.append(f"{name}: report.html does not play its animation inline")
    print(f"{name}: {frames} frames, {size[0]} x {size[1]} pixels, {gif.stat().st_size / 1e6:.2f} MB")
if not runs:
    failures.append("no runs in runs.csv")
if failures:
    sys.exit("check_report: FAILED\n  " + "\n  ".join(failures))
print("check_report: every run's animation is in the report")
