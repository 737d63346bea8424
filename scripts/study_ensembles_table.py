#!/usr/bin/python3
"""The study's runs as ensembles, beside what the study says (issue 48 items 4-5): a Markdown
table of scenarios/results/study_ensembles.csv with each run's probabilities and their 95 %
Wilson intervals, the study's statement and the probability of the study's own outcome
here, as `ishibashi study --members N` puts them in its report's runs table (the same
columns, from analysis/report/report.py). For the study's results assembled from
ensembles run separately, by several programs, which no single study folder holds.

    scripts/study_ensembles_table.py [STUDY_ENSEMBLES_CSV] [STUDY_TOML]

Defaults: scenarios/results/study_ensembles.csv and scenarios/nishida_study.toml.
"""
import csv
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "analysis" / "report"))
from report import ensemble_columns, probability  # noqa: E402


def table(rows, says, outcomes):
    lines = ["| run | members | dashpots | program | p collapse [95 %] | p a stone falls [95 %] | "
             "p a ring stone falls [95 %] | stones fallen, median (range) | first opening, median [s] | "
             "the study says | p of the study's outcome here |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        scenario = f"nishida_{r['model']}_kobe_{r['variant']}"
        members, p_collapse, p_stones, _, of_study = ensemble_columns(r, outcomes.get(scenario, ""))
        fallen = r["fallen_median"] if r["fallen_min"] == r["fallen_max"] else \
            f"{r['fallen_median']} ({r['fallen_min']}-{r['fallen_max']})"
        dashpots = {"study": "explicit", "implicit": "fast path"}.get(r["damping"], r["damping"])
        lines.append(f"| {r['model'].upper()} {r['variant']} | {members} | {dashpots} | {r['commit']} | {p_collapse} | "
                     f"{p_stones} | {probability(r, 'ring_stones_fall')} | {fallen} | {r['first_opening_median_s']} | "
                     f"{says.get(scenario, '')} | {of_study} |")
    return "\n".join(lines)


def main():
    ensembles = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "scenarios" / "results" / "study_ensembles.csv"
    study_file = Path(sys.argv[2]) if len(sys.argv) > 2 else ROOT / "scenarios" / "nishida_study.toml"
    reference = tomllib.loads(study_file.read_text()).get("reference", {})
    rows = list(csv.DictReader(open(ensembles)))
    print(table(rows, reference.get("says", {}), reference.get("outcome", {})))


if __name__ == "__main__":
    main()
