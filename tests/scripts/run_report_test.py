#!/usr/bin/python3
"""analysis/report/run_report.py: the verdict names the tie rods' demand where the run has
rods and not where it has none (or comes from a program before the rods' columns), and says
when a sweep stopped the run at failure; a
run with rods gets a panel of their tension: drawn from a history of two frames, the figure
is taller by that panel. report.py's runs table gives a run's rods in a cell of their own."""
import json
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "analysis" / "report"))
import run_report as r  # noqa: E402

plain = {"shaking_time_s": 3.0, "fallen_stones": 0, "joints_cracked": 2, "joints": 9, "first_opening_s": 0.5,
         "energy_balance_error_relative": 1e-4}
assert "tie rods" not in r.verdict(plain), r.verdict(plain)
assert "tie rods" not in r.verdict(dict(plain, tie_rods=0, ties_yielded=None, peak_tie_tension_n=None))
tied = dict(plain, tie_rods=12, ties_yielded=2, peak_tie_tension_n=166250.0,
            ties={"yield_force_by_rod_n": [166104.0] * 12, "peak_tension_by_rod_n": [1.0] * 12})
assert "; 2 of 12 tie rods yielded, peak tension 166 kN;" in r.verdict(tied), r.verdict(tied)
# A sweep's run stopped at failure: on its crown drop alone it has not collapsed, and must not
# read "stands".
assert r.verdict(plain).startswith("stands after 3.00 s"), r.verdict(plain)
stopped = dict(plain, stopped_early=True)
assert r.verdict(stopped).startswith("failed (the sweep's criteria), stopped there, after 3.00 s"), r.verdict(stopped)
assert r.verdict(dict(stopped, collapse=True)).startswith("collapse, stopped there, after"), r.verdict(stopped)

# How it fails: summary.json's sentence under the bridge's panel where stones fell, none where
# none did or the run is older than the sentence.
fell = dict(plain, fallen_stones=3, how_it_fails={"text": "wall stones from 5.20 s of shaking (3)"})
assert r.how_it_fails(fell) == "\nhow it fails: wall stones from 5.20 s of shaking (3)", r.how_it_fails(fell)
assert r.how_it_fails(dict(fell, fallen_stones=0)) == "" and r.how_it_fails(plain) == ""
# A ring that hinged but lost no stone: said too.
hinged = dict(plain, fallen_stones=0, most_ring_hinges=3, how_it_fails={"text": "no stone fell; ring hinges from 2.10 s"})
assert r.how_it_fails(hinged) == "\nhow it fails: no stone fell; ring hinges from 2.10 s", r.how_it_fails(hinged)
assert r.how_it_fails(dict(hinged, most_ring_hinges=0)) == ""

columns = ["time_s", "phase", "gravitational_j", "largest_tie_tension_n", "ring_hinges"] + list(r.ENERGY_TERMS) + \
    [k for k, _ in r.COUNTS]
columns += [f"ground_a{axis}_m_s2" for axis in "xyz"]
heights = []
with tempfile.TemporaryDirectory() as tmp:
    for summary in (plain, dict(tied, how_it_fails={"ring_hinges": {"most": 0}})):  # a ring: its hinges' axis too
        folder = Path(tmp) / str(len(heights))
        folder.mkdir()
        (folder / "summary.json").write_text(json.dumps(summary))
        rows = [",".join(columns)]
        for time, phase, tension in ((0.0, "settle", 0.0), (0.1, "shake", 9e4), (0.2, "shake", 1.2e5)):
            values = {"time_s": time, "phase": phase, "largest_tie_tension_n": tension}
            rows.append(",".join(str(values.get(c, 0)) for c in columns))
        (folder / "history.csv").write_text("\n".join(rows) + "\n")
        png = r.draw(folder, "test")
        heights.append(int.from_bytes(png.read_bytes()[20:24], "big"))  # the PNG's IHDR height
assert heights[1] > heights[0] * 1.1, heights
print("run_report: verdicts and the rods' panel as expected", heights)

# The study report's runs table: a run with rods, one without, one from before the columns.
import report  # noqa: E402

assert report.tie_rods_cell({"tie_rods": "12", "ties_yielded": "2", "peak_tie_tension_n": "166250"}) == "2 of 12 yielded, 166 kN"
assert report.tie_rods_cell({"tie_rods": "0", "ties_yielded": "", "peak_tie_tension_n": ""}) == "-"
assert report.tie_rods_cell({"fallen_stones": "3"}) == "-"
print("report: the runs table's tie rods cell as expected")
