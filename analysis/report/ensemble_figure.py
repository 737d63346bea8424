#!/usr/bin/python3
"""An ensemble's members through the shaking (`ishibashi run --members N`): every member's
crown unit (vertical, relative to the ground) and stones fallen against the time of
shaking, thin, and their median at each frame bold, under the ensemble's probabilities
(ensemble.json). One PNG in the ensemble's folder:

    /usr/bin/python3 analysis/report/ensemble_figure.py FOLDER [TITLE]   (FOLDER: member_NNN/, ensemble.json)

writes FOLDER/ensemble.png; `ishibashi run --members N` calls it at its end (`--no-report`:
not). scripts/compare_ensembles.py draws two ensembles on one figure with these functions.
"""
import bisect
import csv
import json
import lzma
import math
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from run_outputs import save_figure  # noqa: E402

COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple")


def history_rows(folder):
    """A member folder's history.csv rows (from history.csv.xz where that is what is kept)."""
    plain = folder / "history.csv"
    text = plain.read_text() if plain.exists() else lzma.open(folder / "history.csv.xz", "rt").read()
    return list(csv.DictReader(text.splitlines()))


def first_fall_s(rows, settle_time_s):
    """Seconds of shaking at the first frame with a fallen stone (None: none fell)."""
    for row in rows:
        if row["phase"] == "shake" and int(row["fallen_stones"]) > 0:
            return float(row["time_s"]) - settle_time_s
    return None


def shaking_series(rows, settle_time_s):
    """(time of shaking [s], crown unit's dz [mm], stones fallen) at each frame of the shaking;
    the crown's None where the history has no monitored unit (a model without an arch ring
    and no [monitor] blocks), the whole None without a frame of shaking."""
    shake = [r for r in rows if r["phase"] == "shake"]
    if not shake:
        return None
    crown = next((k for k in rows[0] if re.fullmatch(r"block\d+_dz_m", k)), None)
    return ([float(r["time_s"]) - settle_time_s for r in shake],
            [1000 * float(r[crown]) for r in shake] if crown else None, [int(r["fallen_stones"]) for r in shake])


def median(values):
    values = sorted(values)
    middle = len(values) // 2
    return values[middle] if len(values) % 2 else (values[middle - 1] + values[middle]) / 2


def median_curve(curves, frame_s):
    """The members' median at every multiple of frame_s (s of shaking) within all their frames; each
    member's (times, values) read at a frame by linear interpolation (members settle for
    different times, so their frames fall at slightly different times of shaking)."""
    def at(times, values, t):
        k = max(1, min(len(times) - 1, bisect.bisect_left(times, t)))
        w = (t - times[k - 1]) / (times[k] - times[k - 1])
        return values[k - 1] + w * (values[k] - values[k - 1])
    start = max(times[0] for times, _ in curves)
    end = min(times[-1] for times, _ in curves)
    grid = [i * frame_s for i in range(math.ceil(start / frame_s - 1e-9), int(end / frame_s + 1e-9) + 1)]
    return grid, [median([at(times, values, t) for times, values in curves]) for t in grid]


def finished_members(ensemble):
    """The summaries of an ensemble folder's finished members, each with its first fall and,
    where its history has the crown unit, its series."""
    found = []
    for folder in sorted(Path(ensemble).glob("member_*")):
        summary_file = folder / "summary.json"
        if not summary_file.exists():
            continue
        s = json.load(open(summary_file))
        if not s.get("finished") or s.get("interrupted"):
            continue
        rows = history_rows(folder)
        s["first_fall_s"] = first_fall_s(rows, s["settle_time_s"])
        if series := shaking_series(rows, s["settle_time_s"]):
            s["series"] = series
        found.append(s)
    return found


def draw(ensembles, path, title=None):
    """[(label, members)] on one figure: each ensemble in its colour, its members thin and
    their median bold; the crown unit above, the stones fallen below."""
    import matplotlib
    matplotlib.use("Agg")  # headless
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    for colour, (label, found) in zip(COLOURS, ensembles):
        series = [s["series"] for s in found if "series" in s]
        if not series:
            raise SystemExit(f"{label}: the figure needs its members' histories (member folders, not an ensemble.csv)")
        times = series[0][0]
        frame_s = (times[-1] - times[0]) / max(len(times) - 1, 1)  # the members' output interval
        for a, column in zip(axes, (1, 2)):
            curves = [(one[0], one[column]) for one in series if one[column] is not None]
            if not curves:
                continue
            for curve in curves:
                a.plot(*curve, lw=0.6, alpha=0.5, color=colour)
            grid, middle = median_curve(curves, frame_s)
            a.plot(grid, middle, lw=1.8, color=colour,
                   label=f"{label}: {len(curves)} member{'' if len(curves) == 1 else 's'} (median bold)")
    if not axes[0].lines:
        axes[0].text(0.5, 0.5, "no monitored unit: the model has no arch ring ([monitor] blocks names one)",
                     ha="center", va="center", transform=axes[0].transAxes, fontsize=9)
    axes[0].set_ylabel("crown unit dz [mm]")
    axes[1].set_ylabel("stones fallen")
    axes[1].set_xlabel("time of shaking [s]")
    axes[0].set_title("Every member: the crown unit, vertical, relative to the ground; the stones fallen", fontsize=9)
    for a in axes:
        a.grid(alpha=0.3)
    axes[0 if axes[0].lines else 1].legend(fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path


def probabilities(ensemble):
    """ensemble.json's outcomes in a line: collapse, any stone, a ring stone, k of n [95 %];
    "" where the folder has none (a share of an ensemble run with --member-range)."""
    if not (Path(ensemble) / "ensemble.json").exists():
        return ""
    j = json.load(open(Path(ensemble) / "ensemble.json"))
    def share(key, name):
        o = j[key]  # its "members": those in which it happened, of the finished ones
        return f"{name} {o['members']} of {j['finished']} [{o['lo']:.2f}-{o['hi']:.2f}]"
    stopped = j.get("settings", {}).get("stop_at") == "collapse"  # older ensembles: no such key
    return (", ".join([share("collapse", "collapse"), share("stones_fall", "a stone falls"),
                       share("ring_stones_fall", "a ring stone falls")]) + " (95 % intervals)"
            + ("; each collapse stopped there" if stopped else ""))


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    folder = Path(sys.argv[1])
    found = finished_members(folder)
    if not found:
        sys.exit(f"ensemble_figure.py: {folder} has no finished member (member_NNN/summary.json with finished true)")
    title = sys.argv[2] if len(sys.argv) == 3 else folder.name
    draw([(title, found)], folder / "ensemble.png", f"{title}\n{probabilities(folder)}".strip())


if __name__ == "__main__":
    main()
