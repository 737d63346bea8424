#!/usr/bin/python3
"""Two ensembles of one scenario (`ishibashi run --members N`), outcome by outcome: do
their distributions differ beyond sampling error? For a scheme against another (issue 45
item 3: the implicit dashpots against the explicit reference, a solve's tolerance against
a tighter one), each ensemble's members drawn alike.

    scripts/compare_ensembles.py ENSEMBLE_A ENSEMBLE_B [--labels "name A" "name B"] [--figure PNG]

An ENSEMBLE is the ensemble's folder: each member folder's summary.json (finished members
only, so an ensemble still running can be compared so far) and its history.csv (or
history.csv.xz, as scenarios/results/ensembles/members/ keeps it) for the first fall; or
its ensemble.csv, a row per finished member (what scenarios/results keeps
of an ensemble whose folders are gone); or several of these joined by '+', the shares of
one ensemble run by `--member-range` in different folders. Prints a Markdown
table: per outcome, each ensemble's median and range (counts for the yes/no outcomes),
and the two-sided p-value of an exact test that both come from one distribution:
Fisher's for the yes/no outcomes, the permutation distribution of the rank sum
(Mann-Whitney, ties at mid-ranks) for the numbers. With five members a side the smallest
p a rank test can give is 0.008; a large p says the members cannot tell the two apart,
not that they agree.

Where either ensemble's members have tie rods, two more rows give the rods' demand: how
many members had a rod yield (of those with rods) and each member's largest rod tension.
A side without rods says so, so that B tied against B dry reads as one bridge with a
retrofit against the same bridge without.

A side whose members were stopped at their collapse (`--stop-at collapse`: their
summary.json says "stopped_early", and so does ensemble.csv's column of that name) has the
outcomes that the rest of a collapse adds to (stones and ring stones fallen, whether a ring
stone falls, the crown drop, the joints cracked, the rods' demand) only as far as each
collapse: those rows give no p-value, and a line under the table says which side stopped.
Collapse, whether any stone falls, the first opening and the first fall are whole-run
outcomes either way.

Where members say how they fail (summary.json's and ensemble.csv's `failure_mode`: the part
whose stones fell first and the way most went, "wall first (across)"), a row counts each side's members by mode, with Fisher's p for the most common
mode of both sides together (members of programs before the modes are left out of it).

Where members count the ring's hinges (`most_ring_hinges`: the most at once before a ring
stone fell), a row gives each side's median and range with the rank sum's p.

`--figure PNG` draws every member's crown unit (vertical, relative to the ground) and
stones fallen against the time of shaking, each ensemble in its colour, its members thin
and their median at each frame bold (member folders with histories only).
"""
import argparse
import csv
import itertools
import math
import sys
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "analysis" / "report"))
from ensemble_figure import draw, finished_members, median, median_curve  # noqa: E402,F401  (median_curve: tests)

NUMBERS = [("fallen_stones", "stones fallen", "{:g}"), ("fallen_ring_stones", "ring stones fallen", "{:g}"),
           ("first_opening_s", "first opening [s]", "{:.3f}"), ("first_fall_s", "first fall [s]", "{:.2f}"),
           ("largest_crown_drop_m", "largest crown drop [m]", "{:.3g}"), ("joints_cracked", "joints cracked", "{:g}")]
YES_NO = [("collapse", "collapse", lambda s: bool(s["collapse"])),
          ("stones_fall", "any stone falls", lambda s: s["fallen_stones"] > 0),
          ("ring_stones_fall", "a ring stone falls", lambda s: s["fallen_ring_stones"] > 0)]


# The outcomes a run stopped at its collapse has only as far as the collapse.
AT_COLLAPSE = {"fallen_stones", "fallen_ring_stones", "ring_stones_fall", "largest_crown_drop_m", "joints_cracked",
               "most_ring_hinges"}  # hinges count until a ring stone falls: a wall's collapse may stop them sooner
CUT_SHORT = "(a side stopped at its collapses)"


def with_ties_columns(summary):
    """The summary with the rods' demand as the result's columns name it (tie_rods,
    ties_yielded, peak_tie_tension_n) and in kN; a summary from a program before those
    columns (dcb7acf, the B tied lane's) holds them in its "ties" object, and a run
    without rods has none: 0 rods."""
    old = summary.get("ties")
    if summary.get("tie_rods") is None and isinstance(old, dict) and "count" in old:
        summary.update(tie_rods=old["count"], ties_yielded=old["yielded"], peak_tie_tension_n=old["peak_tension_n"])
    summary["tie_rods"] = int(summary.get("tie_rods") or 0)
    if summary["tie_rods"]:
        summary["peak_tie_tension_kn"] = summary["peak_tie_tension_n"] / 1000
    return summary


def csv_value(text):
    """An ensemble.csv field as summary.json has it: yes/no as booleans, empty as None."""
    if text in ("yes", "no"):
        return text == "yes"
    if text == "":
        return None
    try:
        return float(text)
    except ValueError:
        return text


def members(spec):
    """The finished members' summaries, each with its first fall, of every share in SPEC."""
    return [with_ties_columns(s) for share in spec.split("+") for s in share_members(Path(share))]


def share_members(ensemble):
    if ensemble.suffix == ".csv":
        rows = [{k: csv_value(v) for k, v in row.items()} for row in csv.DictReader(open(ensemble))]
        return [r for r in rows if not r.get("interrupted")]
    return finished_members(ensemble)


def fisher_p(yes_a, n_a, yes_b, n_b):
    """Two-sided Fisher exact test of yes_a of n_a against yes_b of n_b."""
    yes, n = yes_a + yes_b, n_a + n_b

    def probability(k):  # k of the yeses in A, the margins fixed
        return math.comb(n_a, k) * math.comb(n_b, yes - k) / math.comb(n, yes)

    observed = probability(yes_a)
    return min(1.0, sum(probability(k) for k in range(max(0, yes - n_b), min(yes, n_a) + 1)
                        if probability(k) <= observed * (1 + 1e-9)))


def mid_ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    ranks = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return ranks


def rank_sum_p(a, b):
    """Two-sided exact permutation p of A's rank sum (every split of the pooled members)."""
    ranks = mid_ranks(a + b)
    n = len(ranks)
    expected = len(a) * (n + 1) / 2
    observed = abs(sum(ranks[: len(a)]) - expected)
    splits = extreme = 0
    for chosen in itertools.combinations(range(n), len(a)):
        splits += 1
        extreme += abs(sum(ranks[i] for i in chosen) - expected) >= observed - 1e-9
    return extreme / splits


def spread(values, form):
    if not values:
        return "none"
    return f"{form.format(median(values))} ({form.format(min(values))} to {form.format(max(values))})"


def print_modes_row(runs):
    """How each side's members fail, counted by mode, and Fisher's p for the most common mode."""
    modes = [[s["failure_mode"] for s in r if s.get("failure_mode")] for r in runs]  # older programs: none
    if not any(modes):
        return
    counts = [Counter(m) for m in modes]
    cells = ["; ".join(f"{mode}: {n}" for mode, n in c.most_common()) or "none said" for c in counts]
    if all(modes):
        common = (counts[0] + counts[1]).most_common(1)[0][0]
        p = f"{fisher_p(counts[0][common], len(modes[0]), counts[1][common], len(modes[1])):.3f} (Fisher, {common})"
    else:
        p = "(a side says none)"
    print(f"| how they fail | {cells[0]} | {cells[1]} | {p} |")


def print_ties_rows(tied, cut_short):
    """The rods' rows, over each side's members with rods ("no rods" for a side without)."""
    both = all(tied)
    yes = [sum(s["ties_yielded"] > 0 for s in r) for r in tied]
    cells = [f"{y} of {len(r)}" if r else "no rods" for y, r in zip(yes, tied)]
    p = (CUT_SHORT if cut_short else f"{fisher_p(yes[0], len(tied[0]), yes[1], len(tied[1])):.3f} (Fisher)") if both \
        else "(a side has no rods)"
    print(f"| a tie rod yields | {cells[0]} | {cells[1]} | {p} |")
    peaks = [[s["peak_tie_tension_kn"] for s in r] for r in tied]
    cells = [spread(v, "{:.0f}") if v else "no rods" for v in peaks]
    p = (CUT_SHORT if cut_short else f"{rank_sum_p(*peaks):.3f} (rank sum)") if both else "(a side has no rods)"
    print(f"| largest rod tension [kN] | {cells[0]} | {cells[1]} | {p} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("ensembles", nargs=2, help="a folder or ensemble.csv, or shares joined by '+'")
    parser.add_argument("--labels", nargs=2, default=None, help="the two ensembles' names (default: their folders')")
    parser.add_argument("--figure", default=None, help="PNG: every member's crown unit and stones fallen against time")
    o = parser.parse_args()
    labels = o.labels or ["+".join(Path(e).stem if e.endswith(".csv") else Path(e).name for e in spec.split("+"))
                          for spec in o.ensembles]
    runs = [members(e) for e in o.ensembles]
    for label, ensemble, found in zip(labels, o.ensembles, runs):
        if not found:
            raise SystemExit(f"{ensemble}: no finished member (member_NNN/summary.json with finished true, or a row of "
                             "an ensemble.csv)")
    def count(n):
        return f"{n} member" + ("" if n == 1 else "s")

    stopped = [any(s.get("stopped_early") for s in r) for r in runs]
    cut_short = any(stopped)
    print(f"| outcome | {labels[0]} ({count(len(runs[0]))}) | {labels[1]} ({count(len(runs[1]))}) | exact p |")
    print("|---|---|---|---|")
    for key, name, test in YES_NO:
        yes = [sum(test(s) for s in r) for r in runs]
        p = CUT_SHORT if cut_short and key in AT_COLLAPSE else \
            f"{fisher_p(yes[0], len(runs[0]), yes[1], len(runs[1])):.3f} (Fisher)"
        print(f"| {name} | {yes[0]} of {len(runs[0])} | {yes[1]} of {len(runs[1])} | {p} |")
    for key, name, form in NUMBERS:
        values = [[s[key] for s in r if s.get(key) is not None] for r in runs]
        p = CUT_SHORT if cut_short and key in AT_COLLAPSE else \
            f"{rank_sum_p(*values):.3f} (rank sum)" if all(values) else "(a side has none)"
        print(f"| {name} | {spread(values[0], form)} | {spread(values[1], form)} | {p} |")
    hinges = [[s["most_ring_hinges"] for s in r if s.get("most_ring_hinges") is not None] for r in runs]
    if any(hinges):  # older programs, and models without a ring, count none
        p = CUT_SHORT if cut_short else f"{rank_sum_p(*hinges):.3f} (rank sum)" if all(hinges) else "(a side has none)"
        print(f"| most ring hinges at once | {spread(hinges[0], '{:g}')} | {spread(hinges[1], '{:g}')} | {p} |")
    print_modes_row(runs)
    tied = [[s for s in r if s["tie_rods"] > 0] for r in runs]
    if any(tied):
        print_ties_rows(tied, cut_short)
    for label, side_stopped in zip(labels, stopped):
        if side_stopped:
            print(f"\n{label}: its members that collapsed stopped there (--stop-at collapse), so its stones fallen, "
                  "crown drop, joints cracked and rods' demand are those at each collapse.")
    if o.figure:
        draw(list(zip(labels, runs)), o.figure)


if __name__ == "__main__":
    main()
