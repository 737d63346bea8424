#!/usr/bin/python3
"""A seismic run at a glance, from its history.csv, summary.json and last frame: the bridge
at the end (coloured by displacement relative to the ground, fallen stones red), then
through the shaking the ground's acceleration as applied, the monitored units'
displacement relative to the ground, the joints open, cracked and slipped, the stones
fallen and the ring's hinges, the energy terms and, where the model has tie rods, their
largest tension against their yield force, under a title with the verdict. One PNG in the run's folder:

    /usr/bin/python3 analysis/report/run_report.py FOLDER [TITLE]   (FOLDER: history.csv, summary.json)

writes FOLDER/report.png. `ishibashi run` calls it when the run ends (`--no-report`: not);
ParaView shows the same run in 3D (FOLDER/view.pvsm).
"""
import re
import sys
import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from report import G, block_faces, draw_bridge, number  # noqa: E402
from run_outputs import frames, read_rows, read_summary, save_figure  # noqa: E402

ENERGY_TERMS = ("kinetic_j", "elastic_j", "damping_j", "friction_j", "bond_j", "ground_work_j", "balance_error_j")
COUNTS = (("joints_open", "joints open"), ("joints_cracked", "joints cracked"), ("joints_slipped", "joints slipped"),
          ("fallen_stones", "stones fallen"))


def verdict(summary):
    """The run's outcome in a line: collapse or not (or failed, where a sweep stopped it),
    stones fallen, first opening, balance."""
    state = "interrupted" if summary.get("interrupted") else "collapse" if summary.get("collapse") else "stands"
    if summary.get("stopped_early"):  # ended at its collapse, or where a sweep's criteria were met
        state = ("collapse" if summary.get("collapse") else "failed (the sweep's criteria)") + ", stopped there,"
    opening = summary.get("first_opening_s")
    rods = summary.get("tie_rods") or 0  # older runs: no such key
    return (f"{state} after {summary.get('shaking_time_s', 0):.2f} s of shaking: {summary.get('fallen_stones', 0)} stones "
            f"fallen, {summary.get('joints_cracked', 0)} of {summary.get('joints', 0)} joints cracked, first opening "
            + ("none" if opening is None else f"{opening:.3f} s")
            + (f"; {summary['ties_yielded']} of {rods} tie rods yielded, peak tension "
               f"{summary['peak_tie_tension_n'] / 1000:.3g} kN" if rods else "")
            + f"; energy balance {100 * summary.get('energy_balance_error_relative', 0):.3f} %")


def tie_rods(a, t, shake, summary):
    """The largest tension of any rod through the shaking against the smallest yield force."""
    a.plot(t, [number(r["largest_tie_tension_n"]) / 1000 for r in shake], lw=0.9, label="largest rod tension (at the frames)")
    forces = summary.get("ties", {}).get("yield_force_by_rod_n") or []
    if forces:
        a.axhline(min(forces) / 1000, color="C3", ls="--", lw=0.9, label="smallest yield force f_y A")
    a.set_ylabel("tension [kN]")
    a.set_title(f"tie rods: {summary['ties_yielded']} of {summary['tie_rods']} yielded, peak tension "
                f"{summary['peak_tie_tension_n'] / 1000:.3g} kN (between frames too)", fontsize=9)


def how_it_fails(summary):
    """summary.json's sentence of which parts lost stones, from when, which way they fell
    and where the ring hinged, wrapped for a panel's title; empty where no stone fell and
    the ring never hinged (or an older run)."""
    text = summary.get("how_it_fails", {}).get("text", "")
    if not text or not (summary.get("fallen_stones") or summary.get("most_ring_hinges")):
        return ""
    return "\n" + textwrap.fill("how it fails: " + text, 150)


def bridge_at_the_end(axes, folder, shaken_s, summary):
    """The last frame's blocks in 3D on the first frame's bounds (a stone that fell far is
    cut off), coloured by displacement relative to the ground, fallen stones red, and how
    the run fails."""
    series = frames(folder)
    if not series:
        axes.set_axis_off()
        return
    first = [p for face in block_faces(series[0][1])[0] for p in face]
    lo = [min(p[i] for p in first) for i in range(3)]
    hi = [max(p[i] for p in first) for i in range(3)]
    faces, moved, fallen, stones = block_faces(series[-1][1])
    top = max([m for m, f in zip(moved, fallen) if not f] + [1e-3])
    draw_bridge(axes, faces, moved, fallen, top, (lo, hi), -75)
    axes.set_box_aspect([max(hi[i] - lo[i], 1e-3) for i in range(3)], zoom=1.5)  # the panel is wide: fill it
    axes.set_title(f"the bridge at the end ({shaken_s:.2f} s of shaking): displacement relative to the ground up to "
                   f"{1000 * top:.0f} mm (yellow), {stones} fallen stones red{how_it_fails(summary)}", fontsize=9)


def draw(folder, title):
    folder = Path(folder)
    summary = read_summary(folder)
    rows = read_rows(folder / "history.csv")
    if not rows:
        sys.exit(f"run_report.py: {folder / 'history.csv'} has no rows: nothing to draw")
    settled = [r for r in rows if r["phase"] == "settle"]
    shake = [r for r in rows if r["phase"] != "settle"]
    if not shake:  # stopped while settling: the settling is the run
        shake, t0 = rows, 0.0
    else:
        t0 = number(settled[-1]["time_s"]) if settled else 0.0
        shake = settled[-1:] + shake  # from the settled state, time 0 of the shaking: a short run's one frame draws too
    t = [number(r["time_s"]) - t0 for r in shake]
    rods = bool(summary.get("tie_rods")) and "largest_tie_tension_n" in shake[0]
    panels = 5 + rods
    fig = plt.figure(figsize=(10, 3 * panels))
    grid = fig.add_gridspec(panels, 1, height_ratios=(1.6,) + (1,) * (panels - 1))
    bridge_at_the_end(fig.add_subplot(grid[0], projection="3d"), folder, t[-1], summary)
    axes = [fig.add_subplot(grid[1])]
    axes += [fig.add_subplot(grid[k], sharex=axes[0]) for k in range(2, panels)]
    if rods:
        tie_rods(axes[4], t, shake, summary)

    a = axes[0]
    for axis in "xyz":
        a.plot(t, [number(r[f"ground_a{axis}_m_s2"]) / G for r in shake], lw=0.7, label=axis)
    a.set_ylabel("ground acceleration [g]")
    a.set_title("the ground's acceleration as applied, sampled at the frames (output_interval_s: its peaks may fall "
                "between them; the run's header gives them)", fontsize=9)

    a = axes[1]
    monitors = sorted({m.group(1) for key in shake[0] for m in [re.fullmatch(r"block(\d+)_dx_m", key)] if m}, key=int)
    for block in monitors:
        for axis, style in zip("xyz", ("-", "--", ":")):
            a.plot(t, [1000 * number(r[f"block{block}_d{axis}_m"]) for r in shake], lw=0.9, ls=style,
                   label=f"block {block}, {axis}")
    a.set_ylabel("displacement [mm]")
    a.set_title("monitored units (the crown's unless [monitor] says), relative to the ground" if monitors
                else "no unit monitored ([monitor] blocks names some)", fontsize=9)

    a = axes[2]
    for key, label in COUNTS:
        a.plot(t, [number(r[key]) for r in shake], lw=1.0, label=label)
    a.set_ylabel("count")
    a.set_title("joints (cracked: opened by more than 1 mm or bond broken, for good) and fallen stones", fontsize=9)
    hinges = None
    if "ring_hinges" in shake[0] and summary.get("how_it_fails", {}).get("ring_hinges"):  # a ring (older runs: none)
        # A handful against hundreds of joints: on an axis of its own.
        hinges = a.twinx()
        hinges.plot(t, [number(r["ring_hinges"]) for r in shake], lw=1.0, color="C6", label="ring hinges (right axis)")
        hinges.set_ylabel("ring hinges")
        hinges.set_ylim(bottom=0)
        a.set_title("joints (cracked: opened by more than 1 mm or bond broken, for good), fallen stones and the ring's "
                    "hinges (sections open at one edge by 1/100 of their depth, more than the sections beside them)",
                    fontsize=9)

    a = axes[3]
    potential0 = number(shake[0]["gravitational_j"])  # a potential: its change is what the others balance
    a.plot(t, [(number(r["gravitational_j"]) - potential0) / 1000 for r in shake], lw=0.9, label="gravitational (change, the ground's own sinking too)")
    # The tie rods' yielding, where a run's rods yielded (older runs have no such column).
    yielded = ("tie_yield_j",) if any(number(r.get("tie_yield_j") or 0) for r in shake) else ()
    # The energy re-clipped contacts made, where they made any (older runs have no such column).
    reclipped = ("reclip_j",) if any(number(r.get("reclip_j") or 0) for r in shake) else ()
    for term in ENERGY_TERMS + yielded + reclipped:
        a.plot(t, [number(r[term]) / 1000 for r in shake], lw=0.9, label=term[:-2].replace("_", " "))
    a.set_ylabel("energy [kJ]")
    a.set_title("energy (dissipated and ground work since the start; balance error: what the terms leave unexplained)",
                fontsize=9)
    axes[-1].set_xlabel("time of shaking [s]" if settled and shake is not rows else "time [s]")

    for a in axes:
        a.grid(alpha=0.3)
        if a.get_lines():
            a.legend(fontsize=7, loc="best", ncol=4)
    if hinges:
        hinges.legend(fontsize=7, loc="upper left")
    fig.suptitle(f"{title}\n{verdict(summary)}", fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    path = save_figure(fig, folder / "report.png", dpi=100)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    folder = Path(sys.argv[1])
    title = sys.argv[2] if len(sys.argv) == 3 else folder.name
    draw(folder, title)


if __name__ == "__main__":
    main()
