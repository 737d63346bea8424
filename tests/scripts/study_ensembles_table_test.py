#!/usr/bin/python3
"""scripts/study_ensembles_table.py: the probability of the study's own outcome against hand
arithmetic (a 'stands' verdict is the complement of collapse, its interval mirrored; 'no
stone falls' that of any stone falling), a run the study gives no verdict for, and the
fallen stones of an ensemble against a single run."""
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COLUMNS = ("model,variant,members,p_collapse,p_collapse_lo,p_collapse_hi,p_stones_fall,p_stones_fall_lo,"
           "p_stones_fall_hi,p_ring_stones_fall,p_ring_stones_fall_lo,p_ring_stones_fall_hi,fallen_median,fallen_min,"
           "fallen_max,first_opening_median_s,damping,commit")

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    (tmp / "ensembles.csv").write_text("\n".join([
        COLUMNS,
        "b,dry,5,0.600,0.231,0.882,1.000,0.566,1.000,0.400,0.118,0.769,131,27,183,2.585,study,be8e1f2",
        "b,mortar,5,1.000,0.566,1.000,0.800,0.376,0.964,1.000,0.566,1.000,321,192,466,2.699,implicit,fd2dc55",
        "f,dry,1,0.000,0.000,0.793,0.000,0.000,0.793,0.000,0.000,0.793,0,0,0,3.322,study,5acb07b"]) + "\n")
    (tmp / "study.toml").write_text('[reference.says]\nnishida_b_kobe_dry = "stands"\n'
                                    'nishida_b_kobe_mortar = "no stone falls"\n'
                                    '[reference.outcome]\nnishida_b_kobe_dry = "stands"\n'
                                    'nishida_b_kobe_mortar = "no_stone_falls"\n')
    out = subprocess.run([sys.executable, str(ROOT / "scripts" / "study_ensembles_table.py"), str(tmp / "ensembles.csv"),
                          str(tmp / "study.toml")], check=True, capture_output=True, text=True).stdout
    lines = out.splitlines()
    assert len(lines) == 5, out
    # B dry stands with 1 - 0.60 = 0.40, its interval [1 - 0.882, 1 - 0.231].
    assert lines[2] == ("| B dry | 5 | explicit | be8e1f2 | 0.60 [0.23-0.88] | 1.00 [0.57-1.00] | 0.40 [0.12-0.77] | "
                        "131 (27-183) | 2.585 | stands | stands: 0.40 [0.12-0.77] |"), lines[2]
    # B with mortar: no stone falls with 1 - 0.80 = 0.20 [1 - 0.964, 1 - 0.376].
    assert lines[3].endswith("| 321 (192-466) | 2.699 | no stone falls | no stone falls: 0.20 [0.04-0.62] |"), lines[3]
    assert "| fast path | fd2dc55 |" in lines[3], lines[3]
    # F dry: a single run (its fallen stones without a range) and no verdict of the study.
    assert lines[4] == ("| F dry | 1 | explicit | 5acb07b | 0.00 [0.00-0.79] | 0.00 [0.00-0.79] | 0.00 [0.00-0.79] | "
                        "0 | 3.322 |  | - |"), lines[4]
print("study_ensembles_table: the study's outcome's probability as computed by hand")
