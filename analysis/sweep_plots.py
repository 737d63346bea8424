#!/usr/bin/python3
"""Figures of a sweep made by `ishibashi sweep`: ida.png (per record, the crown drop
against the PGA the record was scaled to; failures marked) and fragility.png (the
fraction of runs that failed at each level and the fitted lognormal curve).

    /usr/bin/python3 analysis/sweep_plots.py OUT     (OUT: the sweep's output folder)
"""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: sweep_plots.py SWEEP_OUTPUT_FOLDER")
    out = Path(sys.argv[1])
    runs = rows(out / "sweep.csv")
    if not runs:
        sys.exit(f"sweep_plots.py: {out}/sweep.csv has no rows")

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for record in sorted({r["record"] for r in runs}):
        points = sorted((float(r["pga_g"]), 1000 * float(r["largest_crown_drop_m"]), r["failed"] == "1")
                        for r in runs if r["record"] == record)
        line, = ax.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=record)
        failed = [p for p in points if p[2]]
        ax.plot([p[0] for p in failed], [p[1] for p in failed], "x", color="red", ms=10, mew=2)
    ax.set_xlabel("PGA, larger horizontal component [g]")
    ax.set_ylabel("largest crown drop [mm]")
    ax.set_title("Incremental dynamic analysis (red x: failure)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out / "ida.png", dpi=110, bbox_inches="tight")
    plt.close(fig)

    fit = rows(out / "fragility_fit.csv")[0]
    curve = rows(out / "fragility.csv")
    by_level = {}
    for r in runs:
        by_level.setdefault(r["level"], []).append((float(r["pga_g"]), r["failed"] == "1"))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot([float(c["pga_g"]) for c in curve], [float(c["failure_probability"]) for c in curve], color="k",
            label=f"lognormal fit: median {float(fit['median_g']):.3f} g, beta {float(fit['beta']):.3f}"
            + (" (degenerate)" if fit["degenerate"] == "1" else ""))
    for level, outcomes in by_level.items():
        x = sum(o[0] for o in outcomes) / len(outcomes)
        ax.plot(x, sum(o[1] for o in outcomes) / len(outcomes), "o", color="C3")
    ax.set_xlabel("PGA [g]")
    ax.set_ylabel("probability of failure")
    ax.set_ylim(-0.03, 1.03)
    ax.set_title(f"Fragility ({fit['failures']} failures in {fit['outcomes']} runs; dots: fraction failed per level)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out / "fragility.png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(f"sweep plots: {out / 'ida.png'}, {out / 'fragility.png'}")


if __name__ == "__main__":
    main()
