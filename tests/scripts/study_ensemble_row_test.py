#!/usr/bin/python3
"""scripts/study_ensemble_row.py: the Wilson interval against hand arithmetic, and a study's
single runs given rows as ensembles of one beside an ensemble's row, which they never replace."""
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import study_ensemble_row as r  # noqa: E402

# All of n: [n / (n + z^2), 1]; none of n: [0, z^2 / (n + z^2)]; one run: n = 1, z = 1.96.
lo_one = 1 / (1 + 1.959963984540054 ** 2)  # 0.20655
p, lo, hi = r.wilson(1, 1)
assert (p, hi) == (1.0, 1.0) and abs(lo - lo_one) < 1e-12, (p, lo, hi)
p, lo, hi = r.wilson(0, 1)
assert (p, lo) == (0.0, 0.0) and abs(hi - (1 - lo_one)) < 1e-12, (p, lo, hi)
p, lo, hi = r.wilson(3, 10)  # as tests/analysis/ensemble_test.cpp works it by hand: 0.10779-0.60323
assert abs(lo - 0.10779) < 1e-4 and abs(hi - 0.60322) < 1e-4, (lo, hi)

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    runs = tmp / "study_runs.csv"
    runs.write_text("model,variant,collapse,fallen_stones,fallen_ring_stones,first_opening_s,first_fall_s,"
                    "largest_crown_drop_m,energy_balance_relative,dt_s,wall_s,commit\n"
                    "a,dry,1,57,57,3.309,7.251,0.1339,6.81e-05,8.3e-06,146,5acb07b\n"
                    "d,mortar,0,3,0,0.980,9.850,0.0084,-1.46e-04,5.2e-06,8176,5acb07b\n")
    table = tmp / "study_ensembles.csv"
    table.write_text(",".join(r.COLUMNS) + "\n" + "a,dry,8,1.000,0.676,1.000,1.000,0.676,1.000,1.000,0.676,1.000,"
                     "105,31,113,3.205,study,1ffd156\n")
    for _ in range(2):  # a second call adds nothing
        subprocess.run([sys.executable, str(ROOT / "scripts" / "study_ensemble_row.py"), "--single-runs", str(runs),
                        str(table)], check=True, capture_output=True)
    rows = list(csv.DictReader(table.open()))
    assert [(x["model"], x["variant"], x["members"]) for x in rows] == [("a", "dry", "8"), ("d", "mortar", "1")], rows
    d = rows[1]
    # D with mortar lost 3 stones, none of the ring, and did not collapse.
    assert (d["p_collapse"], d["p_collapse_lo"], d["p_collapse_hi"]) == ("0.000", "0.000", "0.793"), d
    assert (d["p_stones_fall"], d["p_stones_fall_lo"], d["p_stones_fall_hi"]) == ("1.000", "0.207", "1.000"), d
    assert d["p_ring_stones_fall"] == "0.000" and d["fallen_median"] == d["fallen_min"] == d["fallen_max"] == "3", d
    assert (d["first_opening_median_s"], d["damping"], d["commit"]) == ("0.980", "study", "5acb07b"), d
    # One ensemble in two shares (--member-range in two folders): their ensemble.csv rows
    # pooled. Five members: 3 collapse (as B dry's row: 0.231-0.882), 4 lose stones
    # (Wilson 4 of 5 by hand: 0.376-0.964), fallen 0, 3, 50, 100, 329 (median 50), four
    # openings 1.5, 2.0, 2.7, 3.0 (median 2.35); an interrupted row is left out.
    header = "member,seed,interrupted,first_opening_s,collapse,fallen_stones,fallen_ring_stones,state_hash\n"
    for share, lines in (("s1", ["0,1,no,2.7,yes,329,29,ab", "1,1,no,,no,0,0,cd", "9,1,yes,,no,0,0,ef"]),
                         ("s2", ["2,1,no,1.5,yes,100,5,01", "3,1,no,2.0,no,3,0,23", "4,1,no,3.0,yes,50,2,45"])):
        (tmp / share).mkdir()
        (tmp / share / "ensemble.csv").write_text(header + "\n".join(lines) + "\n")
    subprocess.run([sys.executable, str(ROOT / "scripts" / "study_ensemble_row.py"), f"{tmp / 's1'}+{tmp / 's2'}", "b",
                    "mortar", "study", "5406021+fd2dc55", str(table)], check=True, capture_output=True)
    b = [x for x in csv.DictReader(table.open()) if x["model"] == "b"][0]
    assert (b["members"], b["p_collapse"], b["p_collapse_lo"], b["p_collapse_hi"]) == ("5", "0.600", "0.231", "0.882"), b
    assert (b["p_stones_fall"], b["p_stones_fall_lo"], b["p_stones_fall_hi"]) == ("0.800", "0.376", "0.964"), b
    assert (b["p_ring_stones_fall"], b["fallen_median"], b["fallen_min"], b["fallen_max"]) == ("0.600", "50", "0", "329"), b
    assert (b["first_opening_median_s"], b["commit"]) == ("2.350", "5406021+fd2dc55"), b
print("study_ensemble_row: all checks passed")
