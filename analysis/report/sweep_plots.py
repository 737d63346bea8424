#!/usr/bin/python3
"""Figures of a sweep made by `ishibashi sweep`: ida.png (per scenario and record, the
crown drop against the PGA the record was scaled to; failures marked) and fragility.png
(per scenario, the fraction of runs that failed at each level and the fitted lognormal
curve; several scenarios, e.g. dry and with mortar, on one figure) and, where scenarios
have tie rods, ties.png (per run, the largest tension any rod reached against the PGA; red
rings: a rod yielded).

    /usr/bin/python3 analysis/report/sweep_plots.py OUT     (OUT: the sweep's output folder)
"""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

from run_outputs import read_rows, save_figure  # noqa: E402  (beside this file)

STYLES = ["-", "--", ":", "-."]


def median_text(fit):
    """A fit's median as fragility_fit.csv gives it: fitted, or where a degenerate fit's outcomes
    put it (programs before median_is: "degenerate")."""
    g = lambda key: f"{float(fit[key]):.3g} g"  # noqa: E731
    kind = fit.get("median_is", "fit" if fit["degenerate"] == "0" else "degenerate")
    return {"fit": f"median {g('median_g')}, beta {float(fit['beta']):.3f}",
            "above": f"no curve: median above {g('highest_survival_g')}",
            "below": f"no curve: median below {g('lowest_failure_g')}",
            "between": f"step: median between {g('highest_survival_g')} and {g('lowest_failure_g')}",
            "at": f"step: median at {g('median_g')}, where failures and survivals mix",
            "none": "no run yet"}.get(kind, f"median {g('median_g')} (degenerate)")


def tie_demand(out, runs, scenarios):
    """ties.png for the scenarios with tie rods (sweep.csv's tie_rods; tables from before the
    rods' columns have none): None when no scenario has rods."""
    tied = [r for r in runs if (r.get("tie_rods") or "0") != "0"]
    if not tied:
        return None
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, scenario in enumerate(scenarios):
        points = sorted((float(r["pga_g"]), float(r["peak_tie_tension_n"]) / 1000, int(r["ties_yielded"]) > 0)
                        for r in tied if r["scenario"] == scenario)
        if not points:
            continue
        yielded = [p for p in points if p[2]]
        ax.plot([p[0] for p in points], [p[1] for p in points], "o", color=f"C{k}",
                label=f"{scenario}: a rod yielded in {len(yielded)} of {len(points)} runs")
        ax.plot([p[0] for p in yielded], [p[1] for p in yielded], "o", mfc="none", mec="red", ms=11, mew=1.5)
    ax.set_xlabel("PGA, larger horizontal component [g]")
    ax.set_ylabel("largest tension any rod reached [kN]")
    ax.set_title("Tie rods' demand (red rings: a rod yielded)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    path = save_figure(fig, out / "ties.png")
    plt.close(fig)
    return path


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: sweep_plots.py SWEEP_OUTPUT_FOLDER")
    out = Path(sys.argv[1])
    runs = read_rows(out / "sweep.csv")
    for r in runs:
        r.setdefault("member", "0")  # tables of sweeps before members had none
    if not runs:
        sys.exit(f"sweep_plots.py: {out}/sweep.csv has no rows")
    fits = read_rows(out / "fragility_fit.csv")
    scenarios = [f["scenario"] for f in fits]  # the sweep file's order

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, scenario in enumerate(scenarios):
        records = sorted({r["record"] for r in runs})
        for record, member in sorted({(r["record"], r["member"]) for r in runs}):
            points = sorted((float(r["pga_g"]), 1000 * float(r["largest_crown_drop_m"]), r["failed"] == "1")
                            for r in runs if (r["record"], r["member"]) == (record, member) and r["scenario"] == scenario)
            if not points:
                continue
            first = member == min(r["member"] for r in runs)  # one legend entry per record; members share its colour
            ax.plot([p[0] for p in points], [p[1] for p in points], STYLES[k % len(STYLES)], marker="o",
                    color=f"C{records.index(record)}", lw=1.2 if first else 0.6,
                    label=(f"{scenario}, {record}" if len(scenarios) > 1 else record) if first else None)
            failed = [p for p in points if p[2]]
            ax.plot([p[0] for p in failed], [p[1] for p in failed], "x", color="red", ms=10, mew=2)
    ax.set_xlabel("PGA, larger horizontal component [g]")
    ax.set_ylabel("largest crown drop [mm]")
    ax.set_yscale("symlog", linthresh=10)  # millimetres of sagging and metres of collapse on one axis
    # A sweep with [failure] stop_at_failure ends a failed run there: its point is the drop at the stop.
    ax.set_title("Incremental dynamic analysis (red x: failure; a run stopped at failure: its drop there)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, out / "ida.png")
    plt.close(fig)

    curve = read_rows(out / "fragility.csv")
    compared = {c["scenario"]: c for c in read_rows(out / "comparison.csv")}
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, fit in enumerate(fits):
        scenario = fit["scenario"]
        points = [c for c in curve if c["scenario"] == scenario]  # none where no run failed or every one did
        ax.plot([float(c["pga_g"]) for c in points], [float(c["failure_probability"]) for c in points], color=f"C{k}",
                linestyle=STYLES[k % len(STYLES)],
                label=f"{scenario}: {median_text(fit)}, {fit['failures']} of {fit['outcomes']} failed"
                + (f"; one curve with {compared[scenario]['reference']}: p = {float(compared[scenario]['p_same_fragility']):.2g}"
                   if scenario in compared else ""))
        by_level = {}
        for r in runs:
            if r["scenario"] == scenario:
                by_level.setdefault(r["level"], []).append((float(r["pga_g"]), r["failed"] == "1"))
        for outcomes in by_level.values():
            x = sum(o[0] for o in outcomes) / len(outcomes)
            ax.plot(x, sum(o[1] for o in outcomes) / len(outcomes), "o", color=f"C{k}")
    ax.set_xlabel("PGA [g]")
    ax.set_ylabel("probability of failure")
    ax.set_ylim(-0.03, 1.03)
    ax.set_title("Fragility (lognormal fits; dots: fraction failed per level)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13))  # below the axes: long names, no curve hidden
    save_figure(fig, out / "fragility.png")
    plt.close(fig)
    ties = tie_demand(out, runs, scenarios)
    print(f"sweep plots: {out / 'ida.png'}, {out / 'fragility.png'}" + (f", {ties}" if ties else ""))


if __name__ == "__main__":
    main()
