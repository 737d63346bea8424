#!/usr/bin/python3
"""The report of a study made by `ishibashi study`: report.md and a standalone
report.html (figures embedded) with the frequency and run tables, and PNG figures in
figures/: the ground motion's three components, the crown unit's vertical displacement
of every run on one page, the impulse spectra, the energy terms, snapshots of each
run at the study's snapshot times and an animated GIF of each run beside its ground
motion (rendered headless from the runs' .vtu files; Pillow writes the GIF).

    /usr/bin/python3 analysis/report/report.py OUT        (OUT: the study's output folder)

Needs Debian's python3-matplotlib and python3-vtk9 (scripts/setup.sh installs them).
"""
import base64
import csv
import html
import json
import math
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless: no display needed
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from mode_shapes import mode_shape_figure  # noqa: E402  (beside this file)
from run_outputs import frames, read_rows, read_vtu, save_figure, surface  # noqa: E402

G = 9.80665  # m/s^2


def number(text, default=math.nan):
    try:
        return float(text)
    except (TypeError, ValueError):
        return default


def columns(rows, *names):
    return [[number(r[n]) for r in rows] for n in names]


def model_letter(scenario):
    """nishida_a_kobe_dry -> 'nishida_a' (the runs of one model share a panel)."""
    parts = scenario.split("_")
    return "_".join(parts[:2]) if len(parts) > 2 else scenario


def save(fig, path):
    save_figure(fig, path)
    plt.close(fig)
    return path


def panels(n, height):
    """A figure of n panels in two columns (one when n is 1); the panels in order."""
    cols = 2 if n > 1 else 1
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(10, height * rows), squeeze=False)
    for a in list(axes.flat)[n:]:
        a.set_visible(False)
    return fig, list(axes.flat)[:n]


def finish_panel(a, title, xlabel, ylabel):
    a.set_title(title, fontsize=9)
    a.set_xlabel(xlabel)
    a.set_ylabel(ylabel)
    a.grid(alpha=0.3)


def ground_motion_figure(out, runs, figures):
    if not runs:
        return None
    first = runs[0]["scenario"]
    rows = read_rows(out / "runs" / first / "ground_motion.csv")
    if not rows:
        return None
    t, ax, ay, az = columns(rows, "time_s", "ax_m_s2", "ay_m_s2", "az_m_s2")
    fig, axes = plt.subplots(3, 1, figsize=(9, 6), sharex=True)
    for a, values, name in zip(axes, (ax, ay, az), ("x (EW)", "y (NS)", "z (UD)")):
        a.plot(t, [v / G for v in values], lw=0.7, color="k")
        a.set_ylabel(f"{name} [g]")
        a.grid(alpha=0.3)
    axes[0].set_title(f"Ground acceleration as applied ({first} and every run of the same record)")
    axes[-1].set_xlabel("time of shaking [s]")
    return save(fig, figures / "ground_motion.png")


def run_folder(out, run, member=None):
    """Where a run's series and history are: its folder, or for an ensemble (a study with
    members) its member of the most common outcome (or `member`)."""
    member = member or run.get("typical_member", "")
    return out / "runs" / run["scenario"] / member if member else out / "runs" / run["scenario"]


def members_of(out, run):
    """The folders of an ensemble's members (none for a single run)."""
    if number(run.get("members", "1"), 1) < 2:
        return []
    return sorted(p for p in (out / "runs" / run["scenario"]).glob("member_*") if p.is_dir())


def stopped_at_collapse(out, runs):
    """Whether any run (or member of one) ended at its collapse (`--stop-at collapse`)."""
    for r in runs:
        for folder in members_of(out, r) or [run_folder(out, r)]:
            summary = folder / "summary.json"
            if summary.exists() and json.load(open(summary)).get("stopped_early"):
                return True
    return False


def shaking_rows(folder):
    """History rows of the shaking in a run's folder, with the time counted from its start."""
    rows = read_rows(folder / "history.csv")
    shake = [r for r in rows if r["phase"] != "settle"]
    settled = [r for r in rows if r["phase"] == "settle"]
    t0 = number(settled[-1]["time_s"]) if settled else 0.0
    return shake, t0


def crown_figure(out, runs, figures):
    groups = {}
    for r in runs:
        groups.setdefault(model_letter(r["scenario"]), []).append(r)
    if not groups:
        return None
    fig, axes = panels(len(groups), 2.6)
    for a, (model, members) in zip(axes, groups.items()):
        for r in members:
            key = f"block{r['monitored_block']}_dz_m"
            colour = None
            for k, folder in enumerate([run_folder(out, r)] + members_of(out, r)):
                shake, t0 = shaking_rows(folder)
                if not shake or key not in shake[0]:
                    continue
                t = [number(x["time_s"]) - t0 for x in shake]
                dz = [1000 * number(x[key]) for x in shake]
                if k == 0:  # the run, or the ensemble's most common outcome; then every member, thin
                    label = r["scenario"].replace(model + "_", "")
                    if members_of(out, r):
                        label += f" ({r['members']} members, most common outcome bold)"
                    colour = a.plot(t, dz, lw=1.2, label=label)[0].get_color()
                else:
                    a.plot(t, dz, lw=0.5, alpha=0.45, color=colour)
        finish_panel(a, f"{model}: crown unit, vertical, relative to the ground", "time of shaking [s]", "dz [mm]")
        a.legend(fontsize=7)
    fig.tight_layout()
    return save(fig, figures / "crown_displacement.png")


def bond_utilisation_figure(out, runs, figures):
    """Each mortar run's bond utilisation through the shaking (members thin): how close its
    mortar came to cracking, and when; none without mortar runs."""
    curves = []
    for r in runs:
        for k, folder in enumerate([run_folder(out, r)] + members_of(out, r)):
            shake, t0 = shaking_rows(folder)
            if shake and any(x.get("bond_utilisation") for x in shake):
                t = [number(x["time_s"]) - t0 for x in shake]
                curves.append((r["scenario"], k, t, [number(x["bond_utilisation"]) for x in shake]))
    if not curves:
        return None
    names = list(dict.fromkeys(c[0] for c in curves))
    fig, axes = panels(len(names), 2.6)
    for a, name in zip(axes, names):
        for _, k, t, u in (c for c in curves if c[0] == name):
            a.plot(t, u, lw=1.2 if k == 0 else 0.5, alpha=1 if k == 0 else 0.45, color="C3")
        a.axhline(1.0, color="k", ls="--", lw=0.7)
        a.set_ylim(0, 1.1)
        finish_panel(a, f"{name}: the largest share of its strength a bond carries (1: it breaks; none left: no line)",
                     "time of shaking [s]", "bond utilisation")
    fig.tight_layout()
    return save(fig, figures / "bond_utilisation.png")


def spectra_figure(out, frequencies, figures):
    if not frequencies:
        return None
    fig, axes = panels(len(frequencies), 2.8)
    for a, f in zip(axes, frequencies):
        folder = out / "frequencies" / f.get("folder", f["file"])  # older tables: one folder per model
        top = 0.0
        for axis, colour in zip("xyz", ("C0", "C1", "C2")):
            for spectrum in sorted(folder.glob(f"spectrum_{axis}{axis}_block*.csv")):
                hz, amplitude = columns(read_rows(spectrum), "frequency_hz", "amplitude_m")
                a.semilogy(hz, amplitude, lw=0.8, color=colour, label=f"{axis} step, {axis} response")
                top = max(top, max(amplitude))
            mode = number(f[f"mode_{axis}_hz"])
            if mode > 0:
                a.axvline(mode, color=colour, ls="--", lw=0.7)
        for step, colour in zip("xy", ("C0", "C1")):  # the vertical response to the horizontal steps
            for spectrum in sorted(folder.glob(f"spectrum_{step}z_block*.csv")):
                hz, amplitude = columns(read_rows(spectrum), "frequency_hz", "amplitude_m")
                a.semilogy(hz, amplitude, lw=0.6, ls=":", color=colour, label=f"{step} step, z response")
        a.set_xlim(0, 120)
        if top > 0:
            a.set_ylim(top * 1e-5, top * 3)
        finish_panel(a, f"{f['model']}, {f['joint_rule']} rule (dashed: first modes by modal analysis)", "frequency [Hz]",
                     "amplitude [m]")
        a.legend(fontsize=7)
    fig.tight_layout()
    return save(fig, figures / "impulse_spectra.png")


def energy_figure(out, runs, figures):
    if not runs:
        return None
    terms = ("kinetic_j", "elastic_j", "damping_j", "friction_j", "bond_j", "ground_work_j", "balance_error_j")
    fig, axes = panels(len(runs), 2.6)
    for a, r in zip(axes, runs):
        shake, t0 = shaking_rows(run_folder(out, r))
        if not shake:
            continue
        t = [number(x["time_s"]) - t0 for x in shake]
        for term in terms:
            a.plot(t, [number(x[term]) / 1000 for x in shake], lw=0.9, label=term[:-2].replace("_", " "))
        balance_pct = 100 * number(r["energy_balance_error_relative"])
        finish_panel(a, f"{r['scenario']}: energy balance {balance_pct:.3f} %", "time of shaking [s]", "kJ")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    return save(fig, figures / "energy.png")


def block_faces(vtu):
    """The faces of the blocks other than the ground slab, as polygons, with each face's
    displacement relative to the ground (m), whether its block has fallen, and how many
    stones have."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    grid = read_vtu(vtu)
    if grid.GetNumberOfCells() == 0:
        raise RuntimeError(f"{vtu}: VTK read no blocks")
    poly, points, keep, corners = surface(grid)
    moved = vtk_to_numpy(poly.GetCellData().GetArray("displacement_relative_to_ground"))
    faces = [points[c] for c in corners]
    moved = [math.sqrt(float(moved[i] @ moved[i])) for i in keep]
    fallen = vtk_to_numpy(poly.GetCellData().GetArray("fallen"))
    stones = int(vtk_to_numpy(grid.GetCellData().GetArray("fallen")).sum())
    return faces, moved, [bool(fallen[i]) for i in keep], stones


def snapshot_figure(out, run, shaking_s, figures, limits, member=None, what=""):
    """The run (or its `member`, `what` it shows) after shaking_s of shaking."""
    folder = run_folder(out, run, member)
    series = frames(folder)
    times = run if not member else {k: str(v) for k, v in json.load(open(folder / "summary.json")).items()}
    shaking = number(times["shaking_time_s"], 0.0)
    if not series or shaking_s > shaking + 0.01:  # within a frame of the end
        return None
    t0 = number(times["settle_time_s"], 0.0)
    time, vtu = min(series, key=lambda f: abs(f[0] - (t0 + shaking_s)))
    faces, moved, _, _ = block_faces(vtu)
    fig = plt.figure(figsize=(9, 4.5))
    a = fig.add_subplot(projection="3d")
    top = max(max(moved), 1e-3)
    colours = plt.cm.viridis([min(m / top, 1.0) for m in moved])
    a.add_collection3d(Poly3DCollection(faces, facecolors=colours, edgecolors=(0, 0, 0, 0.25), linewidths=0.2))
    lo, hi = limits
    a.set_xlim(lo[0], hi[0])
    a.set_ylim(lo[1], hi[1])
    a.set_zlim(lo[2], hi[2])
    a.set_box_aspect([max(hi[i] - lo[i], 1e-3) for i in range(3)])
    a.view_init(elev=12, azim=-75)
    a.set_axis_off()
    mappable = plt.cm.ScalarMappable(cmap="viridis", norm=plt.Normalize(0, 1000 * top))
    fig.colorbar(mappable, ax=a, shrink=0.6, label="displacement relative to the ground [mm]")
    a.set_title(f"{run['scenario']}{what} after {time - t0:.2f} s of shaking", fontsize=10)
    return save(fig, figures / f"snapshot_{run['scenario']}{'_' + member if member else ''}_{shaking_s:g}s.png")


ANIMATION_FRAMES = 40  # at most, spread over the shaking: a few MB per run


def animation_frames(series, t0, shaking):
    """Up to ANIMATION_FRAMES of a run's frames, evenly over its shaking."""
    shaking_frames = [f for f in series if f[0] >= t0 - 1e-9 and f[0] <= t0 + shaking + 1e-9]
    if len(shaking_frames) <= ANIMATION_FRAMES:
        return shaking_frames
    step = (len(shaking_frames) - 1) / (ANIMATION_FRAMES - 1)
    return [shaking_frames[round(k * step)] for k in range(ANIMATION_FRAMES)]


def colour_scale_and_side(scenes):
    """One colour scale for a run, the 99th percentile of its standing stones' displacements
    over its frames (a stone in flight, not yet counted fallen, would squash the largest), and
    the side it is seen from: where more stones have fallen by the end (an out-of-plane
    collapse)."""
    standing = sorted(m for _, moved, fallen, _ in scenes for m, f in zip(moved, fallen) if not f)
    top = max(standing[int(0.99 * (len(standing) - 1))] if standing else 0.0, 1e-3)
    last_faces, _, last_fallen, _ = scenes[-1]
    fallen_y = [float(f[:, 1].mean()) for f, gone in zip(last_faces, last_fallen) if gone]
    return top, 75 if fallen_y and sum(fallen_y) > 0 else -75


def ground_motion_panels(fig, motion, shaking):
    """The ground motion's three components beside the bridge; returns their time cursors."""
    ground = [fig.add_axes([0.68, 0.68 - 0.28 * k, 0.3, 0.22]) for k in range(3)]
    t, *acc = columns(motion, "time_s", "ax_m_s2", "ay_m_s2", "az_m_s2") if motion else ([], [], [], [])
    cursors = []
    for a, values, name in zip(ground, acc, ("x", "y", "z")):
        a.plot(t, [v / G for v in values], lw=0.5, color="k")
        a.set_ylabel(f"{name} [g]", fontsize=8)
        a.tick_params(labelsize=7)
        a.set_xlim(0, max(shaking, 1e-3))
        cursors.append(a.axvline(0, color="tab:red", lw=1.2))
    ground[-1].set_xlabel("time of shaking [s]", fontsize=8)
    return cursors


def draw_bridge(axes, faces, moved, fallen, top, limits, azimuth):
    """One frame of the bridge: faces coloured by displacement (fallen stones red)."""
    lo, hi = limits
    axes.cla()
    colours = [(0.85, 0.1, 0.1, 1.0) if f else plt.cm.viridis(min(m / top, 1.0)) for m, f in zip(moved, fallen)]
    axes.add_collection3d(Poly3DCollection(faces, facecolors=colours, edgecolors=(0, 0, 0, 0.25), linewidths=0.2))
    axes.set_xlim(lo[0], hi[0])
    axes.set_ylim(lo[1], hi[1])
    axes.set_zlim(lo[2], hi[2])
    axes.set_box_aspect([max(hi[i] - lo[i], 1e-3) for i in range(3)])
    axes.view_init(elev=12, azim=azimuth)
    axes.set_axis_off()


def animation(out, run, figures, limits):
    """The run as an animated GIF: the bridge (coloured by displacement relative to the
    ground on one scale for the whole run, fallen stones red) beside the ground motion
    with a cursor at the frame's time."""
    from matplotlib.animation import PillowWriter

    folder = run_folder(out, run)
    t0, shaking = number(run["settle_time_s"], 0.0), number(run["shaking_time_s"], 0.0)
    chosen = animation_frames(frames(folder), t0, shaking)
    if len(chosen) < 2:
        return None
    scenes = [block_faces(vtu) for _, vtu in chosen]
    top, azimuth = colour_scale_and_side(scenes)
    fig = plt.figure(figsize=(10, 3.6))
    bridge = fig.add_axes([0.0, 0.0, 0.6, 0.9], projection="3d")
    title = fig.text(0.02, 0.95, "", fontsize=9)
    mappable = plt.cm.ScalarMappable(cmap="viridis", norm=plt.Normalize(0, 1000 * top))
    fig.colorbar(mappable, ax=bridge, shrink=0.6, pad=0.0, label="displacement relative to the ground [mm]")
    cursors = ground_motion_panels(fig, read_rows(out / "runs" / run["scenario"] / "ground_motion.csv"), shaking)
    path = figures / f"animation_{run['scenario']}.gif"
    writer = PillowWriter(fps=8)
    with writer.saving(fig, path, dpi=80):
        for (time, _), (faces, moved, fallen, stones) in zip(chosen, scenes):
            draw_bridge(bridge, faces, moved, fallen, top, limits, azimuth)
            title.set_text(f"{run['scenario']}: {time - t0:.2f} s of shaking, {stones} stones fallen")
            for c in cursors:
                c.set_xdata([time - t0, time - t0])
            writer.grab_frame()
    plt.close(fig)
    return path


def model_limits(out, run):
    """Bounds of the model in its first frame, with room for stones that fall out."""
    series = frames(run_folder(out, run))
    faces = block_faces(series[0][1])[0]
    xs = [p for f in faces for p in f]
    lo = [min(p[i] for p in xs) for i in range(3)]
    hi = [max(p[i] for p in xs) for i in range(3)]
    return lo, hi


def table_md(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def table_html(header, rows):
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def vertical_share(folder, step):
    """The largest amplitude of the vertical response to a horizontal step against that of
    the step's own response, at the block read in z (the face unit beside the crown)."""
    for vertical in folder.glob(f"spectrum_{step}z_block*.csv"):
        own = vertical.with_name(vertical.name.replace(f"_{step}z_", f"_{step}{step}_"))
        if own.exists():
            return max(columns(read_rows(vertical), "amplitude_m")[0]) / max(
                max(columns(read_rows(own), "amplitude_m")[0]), 1e-300)
    return 0.0


def study_frequency_rows(out, frequencies, reference):
    """Ours beside the study's first frequencies, per model the study gives: the impulse
    response's first clear peak (the study's method) where it ran, else the modal one;
    for z also the vertical response to the x and the y step at the face unit beside the
    crown (the study's z may be either)."""
    rows = []
    for f in frequencies:
        theirs = reference.get(Path(f["file"]).stem)
        if theirs is None:
            continue
        row = [f["model"], f["joint_rule"]]
        for axis, study_hz in zip("xyz", theirs):
            ours = number(f[f"impulse_{axis}_hz"])
            if not ours > 0:
                ours = number(f[f"mode_{axis}_hz"])
            row += [fmt(ours), f"{study_hz:g}", fmt(ours / study_hz, 2) if ours > 0 else "-"]
        folder = out / "frequencies" / f.get("folder", f["file"])
        for step in "xy":
            ours = number(f.get(f"impulse_{step}z_hz"))
            # A reading under 1 % of the step's own response is noise, not a mode.
            share = vertical_share(folder, step)
            if share < 0.01:
                row += [f"none ({100 * share:.2g} % of {step})", "-"]
            else:
                row += [fmt(ours), fmt(ours / theirs[2], 2) if ours > 0 else "-"]
        rows.append(row)
    return rows


def fmt(value, digits=3, scale=1.0):
    v = number(value)
    return "-" if math.isnan(v) else f"{v * scale:.{digits}f}"


def read_study(out):
    """The study's tables in its output folder (study.csv, runs.csv, frequencies.csv, jobs.csv,
    reference.csv), as the report uses them."""
    if not (out / "study.csv").exists():
        sys.exit(f"report.py: {out}/study.csv not found: run `ishibashi study` first")
    about = {row[0]: row[1] for row in csv.reader(open(out / "study.csv")) if len(row) >= 2}
    reference = read_rows(out / "reference.csv")
    study_file = about.get("study_file", "")
    return {
        "name": about.get("name", "Study"),
        # relative to the report, so that the folder reads the same wherever it is moved
        "study_file": os.path.relpath(study_file, out.resolve()) if study_file else "",
        "snapshot_times": [float(t) for t in about.get("snapshot_times_s", "").split()],
        "runs": read_rows(out / "runs.csv"),
        "frequencies": read_rows(out / "frequencies.csv"),
        "jobs": read_rows(out / "jobs.csv"),
        "study_hz": {r["key"]: [number(r[f"{a}_hz"]) for a in "xyz"] for r in reference if r["kind"] == "frequencies"},
        "study_says": {r["key"]: r["says"] for r in reference if r["kind"] == "says"},
        "study_outcome": {r["key"]: r["says"] for r in reference if r["kind"] == "outcome"},
    }


def frequency_sections(out, study, figures):
    """(title, text, table (header, rows) or None, figure paths) of the frequency analyses."""
    frequencies = study["frequencies"]
    freq_rows = []
    for f in frequencies:
        row = [f["model"], f["subdivision"], f["joint_rule"]]
        for axis in "xyz":
            mode, peak = number(f[f"mode_{axis}_hz"]), number(f[f"impulse_{axis}_hz"])
            row += [fmt(mode), fmt(peak), "-" if not (mode > 0 and peak > 0) else f"{100 * (peak / mode - 1):+.2f} %"]
        freq_rows.append(row)
    sections = [("Natural frequencies",
                 "First mode with more than 5 % effective mass per axis (modal analysis, joints held linear) "
                 "and the first clear peak of the impulse response of the crown unit along the same axis.",
                 (["model", "subdivision", "joint rule", "x modes [Hz]", "x impulse [Hz]", "x diff",
                   "y modes [Hz]", "y impulse [Hz]", "y diff", "z modes [Hz]", "z impulse [Hz]", "z diff"], freq_rows),
                 [spectra_figure(out, frequencies, figures)])]
    shapes = [mode_shape_figure(out / "frequencies" / f.get("folder", f["file"]), f"{f['model']}, {f['joint_rule']} rule",
                                figures / f"mode_shapes_{f.get('folder', f['file'])}.png") for f in frequencies]
    sections.append(("Mode shapes", "The first mode along x, y and z of each analysis (the first with more than 5 % "
                     "effective mass along it), deformed (coloured by the displacement's size, the largest drawn as a "
                     "tenth of the model's size) over the undeformed blocks, from the front and from above.",
                     None, shapes))
    against = study_frequency_rows(out, frequencies, study["study_hz"])
    if against:
        sections.append(("Natural frequencies against the study",
                         "Ours (the impulse response's first clear peak, the study's method, where it ran; else the "
                         "modal analysis) beside the first natural frequencies the study reports, and their ratio; "
                         "z also as the vertical response to the x and the y step of the face unit beside the crown, "
                         "off the bridge's symmetry planes (the crown itself barely moves vertically in a horizontal "
                         "mode; 'none' where the response is under 1 % of the step's own there).",
                         (["model", "joint rule", "x ours [Hz]", "x study [Hz]", "x ratio", "y ours [Hz]",
                           "y study [Hz]", "y ratio", "z ours [Hz]", "z study [Hz]", "z ratio", "z of x step [Hz]",
                           "ratio", "z of y step [Hz]", "ratio"], against), []))
    return sections


def probability(r, what, complement=False):
    """'p [lo-hi]' of runs.csv's p_<what>, or of its complement."""
    p, lo, hi = (number(r.get(f"p_{what}{end}", "")) for end in ("", "_lo", "_hi"))
    if math.isnan(p):
        return "-"
    if complement:
        p, lo, hi = 1 - p, 1 - hi, 1 - lo
    return f"{p:.2f} [{lo:.2f}-{hi:.2f}]"


def ensemble_columns(r, study_outcome):
    """An ensemble's columns of the runs table (dashes for a single run): its members, the
    probabilities with their 95 % Wilson intervals, and that of the study's own outcome
    ('collapse', 'stands' or 'no_stone_falls' in the study file's [reference.outcome])."""
    of_study = {"collapse": probability(r, "collapse"), "stands": probability(r, "collapse", True),
                "no_stone_falls": probability(r, "stones_fall", True)}.get(study_outcome, "-")
    if of_study != "-":
        of_study = f"{study_outcome.replace('_', ' ')}: {of_study}"
    fallen = f"{r['fallen_min']}-{r['fallen_max']}" if r.get("fallen_min", "") != "" else "-"
    return [r.get("members", "1"), probability(r, "collapse"), probability(r, "stones_fall"), fallen, of_study]


def tie_rods_cell(r):
    """A run's tie rods as the runs' table gives them: how many yielded and the largest
    tension any reached; "-" for a run without rods (or from a program before their columns)."""
    rods = r.get("tie_rods") or "0"
    if rods == "0":
        return "-"
    return f"{r['ties_yielded']} of {rods} yielded, {number(r['peak_tie_tension_n']) / 1000:.3g} kN"


def how_it_fails_cell(out, r):
    """How a run fails (its summary.json's sentence; an ensemble's most common outcome's
    member's, then how many members fail each way): which parts lost stones, from when, and
    which way they fell; "-" for a run from a program before the sentence."""
    summary = run_folder(out, r) / "summary.json"
    if not summary.exists():
        return "-"
    text = json.load(open(summary)).get("how_it_fails", {}).get("text", "-")
    ensemble = out / "runs" / r["scenario"] / "ensemble.json"
    if members_of(out, r) and ensemble.exists():
        modes = json.load(open(ensemble)).get("failure_modes", {})
        if modes:
            text += " (members: " + "; ".join(f"{mode} {n}" for mode, n in modes.items()) + ")"
    return text


def run_sections(out, study, figures):
    """The seismic runs' table and figures, their snapshots and animations."""
    runs = study["runs"]
    if not runs:  # a study of frequencies alone has none
        return []
    run_rows = [[r["scenario"], r["settled"], fmt(r["shaking_time_s"], 2),
                 "none" if r["first_opening_s"] == "" else fmt(r["first_opening_s"], 3),
                 fmt(r.get("bond_utilisation_peak"), 2),
                 fmt(r["largest_crown_drop_m"], 1, 1000), r["fallen_stones"], r["collapse"],
                 f"{r['joints_cracked']} / {r['joints']}", fmt(r["energy_balance_error_relative"], 3, 100),
                 fmt(r["wall_s"], 0), how_it_fails_cell(out, r), study["study_says"].get(r["scenario"], "")]
                for r in runs]
    ensembles = any(members_of(out, r) for r in runs)
    tied = any(tie_rods_cell(r) != "-" for r in runs)
    for row, r in zip(run_rows, runs):
        row[-2:-2] = (ensemble_columns(r, study["study_outcome"].get(r["scenario"], "")) if ensembles else []) + \
            ([tie_rods_cell(r)] if tied else [])
    sections = [("Seismic runs",
                 "Settled under gravity, then shaken. First opening: seconds of shaking until a joint first "
                 "opened by more than 1 mm (or lost its bond). Mortar used: until then, the largest share of "
                 "its strength an intact bond carried (1: a bond breaks; - without mortar; the figure of each mortar run "
                 "gives it through the shaking, each frame the largest since the frame before). Crown drop: the largest downward displacement "
                 "of the crown unit relative to the ground. Energy balance: the fraction of the energy "
                 "exchanged (ground work, dashpots, friction, bonds) that the balance misses. How it fails: which "
                 "parts lost stones, from when (the first frame that found one fallen), on which side of the bridge, "
                 "and which way they fell (x along the span: in plane; y across: out of plane); for an ensemble, how "
                 "many members fail each way (the part that lost stones first and the way most went). Study says: what "
                 "the published study reports of that run, where the study file gives it (the study's time axis "
                 "runs 3.8 s behind the record: its 4.0 s is the record's 7.8 s, 3.8 s of shaking from 4.0 s)."
                 + (" A run of several members is an ensemble (members that differ by the construction "
                    "tolerance, README: Ensembles): its columns up to wall time are its most common outcome's member "
                    "(of the verdict most members share, the median number of fallen stones), then the "
                    "probabilities with their 95 % Wilson intervals, and that of the study's own verdict." if ensembles
                    else "")
                 + (" Tie rods: how many of the run's rods yielded, and the largest tension any reached." if tied else "")
                 + (" Runs that collapsed ended there (--stop-at collapse): their shaking time, crown drop and "
                    "stones fallen are those of the frame that found the collapse; the debris after it was not run."
                    if stopped_at_collapse(out, runs) else ""),
                 (["scenario", "settled", "shaking [s]", "first opening [s]", "mortar used", "crown drop [mm]",
                   "stones fallen", "collapse", "joints cracked", "energy balance [%]", "wall [s]"]
                  + (["members", "p collapse [95 %]", "p a stone falls [95 %]", "stones fallen (range)",
                      "p of the study's outcome here"] if ensembles else [])
                  + (["tie rods"] if tied else []) + ["how it fails", "study says"],
                  run_rows),
                 [ground_motion_figure(out, runs, figures), crown_figure(out, runs, figures),
                  bond_utilisation_figure(out, runs, figures), energy_figure(out, runs, figures)])]
    snapshots, animations = [], []
    for r in runs:
        if not frames(run_folder(out, r)):
            continue
        limits = model_limits(out, r)
        limits = ([limits[0][0], limits[0][1], limits[0][2] - 1.0], limits[1])
        for t in study["snapshot_times"]:
            snapshots.append(snapshot_figure(out, r, t, figures, limits))
        if members_of(out, r):  # the ensemble's worst outcome at its end
            worst = r["worst_member"]
            snapshots.append(snapshot_figure(out, r, number(r["shaking_time_s"], 0.0), figures, limits, worst,
                                             f", the worst of {r['members']} members ({worst})"))
        animations.append(animation(out, r, figures, limits))
    sections.append(("Snapshots", "Each run at the study's snapshot times, coloured by each block's displacement "
                     "relative to the ground (open view.pvsm in ParaView for the whole series).", None, snapshots))
    sections.append(("Animations", f"Each run through its shaking ({ANIMATION_FRAMES} frames at most), coloured by "
                     "displacement relative to the ground on one scale for the run (the 99th percentile of its "
                     "standing stones' displacements), fallen stones red, seen from the side where more stones "
                     "fell, beside the ground motion with the frame's time.",
                     None, animations))
    return sections


def write_report(out, study, sections):
    """report.md (figures beside it in figures/) and report.html (figures embedded)."""
    title = study["name"]
    md = [f"# {title}", "", f"Study file: `{study['study_file']}`. Made by `ishibashi study`; "
          f"{len(study['runs'])} runs, {len(study['frequencies'])} frequency analyses.", ""]
    page = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>",
            "<style>body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}"
            "table{border-collapse:collapse;font-size:90%}td,th{border:1px solid #999;padding:2px 6px}"
            "img{max-width:100%}</style></head><body>", f"<h1>{html.escape(title)}</h1>",
            f"<p>Study file: <code>{html.escape(study['study_file'])}</code>.</p>"]
    for name, text, table, figs in sections:
        md += [f"## {name}", "", text, ""]
        page += [f"<h2>{html.escape(name)}</h2>", f"<p>{html.escape(text)}</p>"]
        if table:
            md += [table_md(*table), ""]
            page.append(table_html(*table))
        for fig in figs:
            if fig is None:
                continue
            md += [f"![{fig.stem}](figures/{fig.name})", ""]
            data = base64.b64encode(fig.read_bytes()).decode()
            kind = "gif" if fig.suffix == ".gif" else "png"
            page.append(f"<p><img alt='{fig.stem}' src='data:image/{kind};base64,{data}'></p>")
    page.append("</body></html>")
    (out / "report.md").write_text("\n".join(md) + "\n")
    (out / "report.html").write_text("\n".join(page) + "\n")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: report.py STUDY_OUTPUT_FOLDER")
    out = Path(sys.argv[1])
    study = read_study(out)
    figures = out / "figures"
    figures.mkdir(exist_ok=True)
    sections = frequency_sections(out, study, figures) + run_sections(out, study, figures)
    failed = [j for j in study["jobs"] if j["status"] == "failed"]
    if failed:
        sections.append(("Failed jobs", "", (["kind", "input", "error"],
                                             [[j["kind"], j["input"], j["error"]] for j in failed]), []))
    write_report(out, study, sections)
    count = sum(1 for s in sections for f in s[3] if f is not None)
    print(f"report: {out / 'report.md'}, {out / 'report.html'}, {count} figures in {figures}")


if __name__ == "__main__":
    main()
