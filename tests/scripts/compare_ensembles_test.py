#!/usr/bin/python3
"""scripts/compare_ensembles.py's exact tests against hand arithmetic, and its table from
two small ensembles written here (member folders with summary.json and history.csv, one
history kept as history.csv.xz), the same with one of them as an ensemble.csv; the
members' median curve by hand, and the figure written; the rods' rows, and a side stopped
at its collapses, whose cut-short outcomes get no p-value."""
import json
import lzma
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import compare_ensembles as c  # noqa: E402


def close(a, b):
    return abs(a - b) < 1e-12


# Fisher: 2 of 3 against 0 of 3, two yeses in all: A holds 0, 1 or 2 of them with
# probability 3/15, 9/15, 3/15; the observed 2 and the as unlikely 0 give 0.4.
assert close(c.fisher_p(2, 3, 0, 3), 0.4), c.fisher_p(2, 3, 0, 3)
assert close(c.fisher_p(5, 5, 0, 5), 2 / 252), c.fisher_p(5, 5, 0, 5)  # 1 / C(10, 5), both tails
assert close(c.fisher_p(1, 2, 1, 2), 1.0)
# Rank sum: A the three smallest of six: 1 of C(6, 3) = 20 splits each tail.
assert close(c.rank_sum_p([1, 2, 3], [4, 5, 6]), 2 / 20)
assert close(c.rank_sum_p([1, 2, 3, 4, 5], [6, 7, 8, 9, 10]), 2 / 252)
assert close(c.rank_sum_p([1, 1, 2], [1, 2, 2]), 1.0)  # ties: mid-ranks, A's sum is the mean
assert c.mid_ranks([5, 1, 5, 3]) == [3.5, 1, 3.5, 2]
# The median curve: members read at each 0.1 s within all their frames (0.05-0.2 s), between
# frames by linear interpolation. At 0.1 s: 1, 3 (half way from 2 to 4) and 10 -> 3; at
# 0.2 s: 2, 5, 20 -> 5.
grid, middle = c.median_curve([([0.0, 0.1, 0.2, 0.3], [0, 1, 2, 3]), ([0.05, 0.15, 0.25], [2, 4, 6]),
                               ([0.0, 0.2], [0, 20])], 0.1)
assert close(grid[0], 0.1) and close(grid[1], 0.2) and len(grid) == 2, grid
assert all(close(x, y) for x, y in zip(middle, [3, 5])), middle


def write_member(folder, fallen, ring, opening, fall_frame):
    folder.mkdir(parents=True)
    summary = {"finished": True, "interrupted": False, "settle_time_s": 0.5, "collapse": ring > 0,
               "fallen_stones": fallen, "fallen_ring_stones": ring, "first_opening_s": opening,
               "largest_crown_drop_m": 0.01 * fallen, "joints_cracked": 100 + fallen}
    (folder / "summary.json").write_text(json.dumps(summary))
    rows = ["time_s,phase,block7_dz_m,fallen_stones"] + [
        f"{0.5 + 0.1 * i},shake,{-0.001 * i},{fallen if i >= fall_frame else 0}" for i in range(10)]
    (folder / "history.csv").write_text("\n".join(rows) + "\n")


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    for m, (fallen, ring) in enumerate([(0, 0), (3, 0), (9, 2)]):
        write_member(tmp / "a" / f"member_{m:03d}", fallen, ring, 1.0 + m, 4)
    for m, (fallen, ring) in enumerate([(20, 5), (30, 6), (40, 7)]):
        write_member(tmp / "b" / f"member_{m:03d}", fallen, ring, 4.0 + m, 2)
    history = tmp / "b" / "member_001" / "history.csv"  # kept as scenarios/results keeps members
    with lzma.open(history.with_suffix(".csv.xz"), "wt") as xz:
        xz.write(history.read_text())
    history.unlink()
    (tmp / "b" / "member_003").mkdir()  # a member not finished: left out
    table = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "a"),
                            str(tmp / "b"), "--labels", "A", "B", "--figure", str(tmp / "members.png")],
                           check=True, capture_output=True, text=True).stdout
    assert (tmp / "members.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "| A (3 members) | B (3 members) |" in table, table
    assert "| any stone falls | 2 of 3 | 3 of 3 | 1.000 (Fisher) |" in table, table
    assert "| stones fallen | 3 (0 to 9) | 30 (20 to 40) | 0.100 (rank sum) |" in table, table
    assert "| first fall [s] | 0.40 (0.40 to 0.40) | 0.20 (0.20 to 0.20) |" in table, table
    # B as the ensemble.csv the program writes (a row per finished member; yes/no, empty
    # where none): the same table.
    columns = ["member", "interrupted", "settle_time_s", "first_opening_s", "collapse", "fallen_stones",
               "fallen_ring_stones", "joints_cracked", "largest_crown_drop_m", "first_fall_s"]
    rows = [",".join(columns)] + [f"{m},no,0.5,{4.0 + m},yes,{fallen},{ring},{100 + fallen},{0.01 * fallen},0.2"
                                  for m, (fallen, ring) in enumerate([(20, 5), (30, 6), (40, 7)])]
    rows.append("3,yes,0.5,,no,0,0,0,0,")  # interrupted: left out
    (tmp / "b.csv").write_text("\n".join(rows) + "\n")
    from_csv = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "a"),
                               str(tmp / "b.csv"), "--labels", "A", "B"], check=True, capture_output=True,
                              text=True).stdout
    assert from_csv == table, from_csv + "\n" + table
    # B in two shares (--member-range in two folders): the same members, the same table.
    (tmp / "b2").mkdir()
    (tmp / "b" / "member_002").rename(tmp / "b2" / "member_002")
    shares = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "a"),
                             f"{tmp / 'b'}+{tmp / 'b2'}", "--labels", "A", "B"], check=True, capture_output=True,
                            text=True).stdout
    assert shares == table, shares + "\n" + table
    assert "tie rod" not in table, table  # neither side has rods: no rods' rows
    assert "how they fail" not in table, table  # no member says how it fails (a program before the modes)
    # How they fail: A's members say "wall first (across)" twice and "no stone fell" once, B's
    # (as its ensemble.csv's failure_mode column) "ring first (along)" thrice: the most common
    # mode of both, "ring first (along)", 0 of 3 against 3 of 3: Fisher's p 2 / C(6, 3) = 0.1.
    # The ring's hinges likewise: A's members 2, 3 and 4 at most at once, B's 5, 6 and 7: the rank
    # sum puts A's three lowest, 1 of C(6, 3) = 20 splits each tail: p 0.1.
    assert "most ring hinges" not in table, table  # no member counts them (a program before the hinges)
    for m, mode in enumerate(["no stone fell", "wall first (across)", "wall first (across)"]):
        summary_file = tmp / "a" / f"member_{m:03d}" / "summary.json"
        summary = json.loads(summary_file.read_text())
        summary_file.write_text(json.dumps(dict(summary, failure_mode=mode, most_ring_hinges=2 + m)))
    with_modes = (tmp / "b.csv").read_text().splitlines()
    with_modes = [with_modes[0] + ",failure_mode,most_ring_hinges"] + [
        row + f",ring first (along),{5 + m if m < 3 else ''}" for m, row in enumerate(with_modes[1:])]
    (tmp / "b_modes.csv").write_text("\n".join(with_modes) + "\n")
    modes = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "a"),
                            str(tmp / "b_modes.csv"), "--labels", "A", "B"], check=True, capture_output=True,
                           text=True).stdout
    assert ("| how they fail | wall first (across): 2; no stone fell: 1 | ring first (along): 3 | "
            "0.100 (Fisher, ring first (along)) |") in modes, modes
    assert "| most ring hinges at once | 3 (2 to 4) | 6 (5 to 7) | 0.100 (rank sum) |" in modes, modes

    # Tied members: T's summaries as the B tied lane's program (dcb7acf) writes them (the
    # rods' demand in "ties"), U's as an ensemble.csv of today's columns (one without rods'
    # columns filled: a member of a scenario without rods). T: rods yield in 2 of 3, peaks
    # 120, 150, 180 kN; U: 0 of 2, peaks 90 and 100 kN: the rank sum puts U's two lowest, 2 of
    # C(5, 2) = 10 splits as far from the mean; Fisher, 2 of 3 against 0 of 2: T holds 0, 1 or 2
    # of the two yeses with probability 1/10, 6/10, 3/10, and 2 and 0 are as unlikely: 0.4.
    for m, (yielded, peak) in enumerate([(0, 120e3), (1, 150e3), (2, 180e3)]):
        folder = tmp / "t" / f"member_{m:03d}"
        write_member(folder, 0, 0, 1.0, 99)
        summary = json.loads((folder / "summary.json").read_text())
        summary["ties"] = {"count": 12, "yielded": yielded, "peak_tension_n": peak}
        (folder / "summary.json").write_text(json.dumps(summary))
    columns = ["member", "interrupted", "settle_time_s", "first_opening_s", "collapse", "fallen_stones",
               "fallen_ring_stones", "joints_cracked", "largest_crown_drop_m", "first_fall_s", "tie_rods",
               "ties_yielded", "peak_tie_tension_n"]
    (tmp / "u.csv").write_text("\n".join([",".join(columns), "0,no,0.5,1,no,0,0,100,0,,12,0,90000",
                                          "1,no,0.5,1,no,0,0,100,0,,12,0,100000", "2,no,0.5,1,no,0,0,100,0,,,,"]) + "\n")
    tied = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "t"),
                           str(tmp / "u.csv"), "--labels", "T", "U"], check=True, capture_output=True,
                          text=True).stdout
    assert "| a tie rod yields | 2 of 3 | 0 of 2 | 0.400 (Fisher) |" in tied, tied
    assert "| largest rod tension [kN] | 150 (120 to 180) | 95 (90 to 100) | 0.200 (rank sum) |" in tied, tied
    untied = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "t"),
                             str(tmp / "a"), "--labels", "T", "A"], check=True, capture_output=True, text=True).stdout
    assert "| a tie rod yields | 2 of 3 | no rods | (a side has no rods) |" in untied, untied
    assert "| largest rod tension [kN] | 150 (120 to 180) | no rods | (a side has no rods) |" in untied, untied
    # S: A's members again, those that collapsed (member 2) stopped there: the rows the rest of a
    # collapse adds to give no p-value, the whole-run outcomes keep theirs, and a line says so.
    for m, (fallen, ring) in enumerate([(0, 0), (3, 0), (9, 2)]):
        write_member(tmp / "s" / f"member_{m:03d}", fallen, ring, 1.0 + m, 4)
    summary = json.loads((tmp / "s" / "member_002" / "summary.json").read_text())
    (tmp / "s" / "member_002" / "summary.json").write_text(json.dumps(dict(summary, stopped_early=True)))
    cut = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "s"),
                          str(tmp / "b"), "--labels", "S", "B"], check=True, capture_output=True, text=True).stdout
    assert "| stones fallen | 3 (0 to 9) | 25 (20 to 30) | (a side stopped at its collapses) |" in cut, cut  # B: 2 left
    assert "| a ring stone falls | 1 of 3 | 2 of 2 | (a side stopped at its collapses) |" in cut, cut
    assert "| any stone falls | 2 of 3 | 2 of 2 | 1.000 (Fisher) |" in cut, cut
    assert "| first opening [s] |" in cut and cut.count("(rank sum)") == 2, cut  # first opening and first fall
    assert "S: its members that collapsed stopped there" in cut and "B: its" not in cut, cut
    # S as its ensemble.csv (stopped_early, yes/no): the same table.
    columns = ["member", "interrupted", "settle_time_s", "first_opening_s", "collapse", "fallen_stones",
               "fallen_ring_stones", "joints_cracked", "largest_crown_drop_m", "first_fall_s", "stopped_early"]
    rows = [",".join(columns)] + [f"{m},no,0.5,{1.0 + m},{'yes' if ring else 'no'},{fallen},{ring},{100 + fallen},"
                                  f"{0.01 * fallen},{0.4 if fallen else ''},{'yes' if m == 2 else 'no'}"
                                  for m, (fallen, ring) in enumerate([(0, 0), (3, 0), (9, 2)])]
    (tmp / "s.csv").write_text("\n".join(rows) + "\n")
    cut_csv = subprocess.run([sys.executable, str(ROOT / "scripts" / "compare_ensembles.py"), str(tmp / "s.csv"),
                              str(tmp / "b"), "--labels", "S", "B"], check=True, capture_output=True, text=True).stdout
    assert cut_csv == cut, cut_csv + "\n" + cut
print("compare_ensembles: exact tests, table and median curve as computed by hand, the rods' rows; the figure written")
