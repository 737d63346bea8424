#!/usr/bin/python3
"""analysis/report/ensemble_figure.py: the title's outcomes read as ensemble.json gives them
(each probability's "members" are those in which it happened, of "finished"), and the
figure of members whose histories have no monitored unit (a model without an arch ring, as
models/examples' stack of three) drawn with its stones fallen, not refused."""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "analysis" / "report"))
import ensemble_figure as f  # noqa: E402

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    outcome = {"finished": 5,
               "collapse": {"p": 0.8, "lo": 0.38, "hi": 0.96, "members": 4},
               "stones_fall": {"p": 1.0, "lo": 0.57, "hi": 1.0, "members": 5},
               "ring_stones_fall": {"p": 0.6, "lo": 0.23, "hi": 0.88, "members": 3}}
    (tmp / "ensemble.json").write_text(json.dumps(outcome))
    line = f.probabilities(tmp)
    for expected in ("collapse 4 of 5 [0.38-0.96]", "a stone falls 5 of 5", "a ring stone falls 3 of 5"):
        assert expected in line, line

    for m in range(2):  # members without a block<N>_dz_m column
        folder = tmp / f"member_{m:03d}"
        folder.mkdir()
        (folder / "summary.json").write_text(json.dumps({"finished": True, "interrupted": False, "settle_time_s": 0.5}))
        rows = ["time_s,phase,fallen_stones", "0.25,settle,0"] + [f"{0.5 + 0.1 * i},shake,{i // 5 * m}" for i in range(10)]
        (folder / "history.csv").write_text("\n".join(rows) + "\n")
    found = f.finished_members(tmp)
    assert len(found) == 2 and all(s["series"][1] is None for s in found), found
    assert found[1]["series"][2] == [0] * 5 + [1] * 5, found[1]["series"]
    assert found[1]["first_fall_s"] is not None and abs(found[1]["first_fall_s"] - 0.5) < 1e-12, found[1]
    done = subprocess.run([sys.executable, str(ROOT / "analysis/report/ensemble_figure.py"), str(tmp), "no crown"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp / "ensemble.png").read_bytes()[:4] == b"\x89PNG"
print("ensemble_figure: titles and a model without a crown unit as expected")
