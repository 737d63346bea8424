"""Readers of the program's outputs, shared by the report (analysis/report.py) and the
scripts: summary.json and the tables (runs.csv, sweep.csv, history.csv, ...) under the
names the program writes now (analysis/run_result.cpp), whatever program wrote them."""
import csv
import json
from pathlib import Path

# Names of earlier programs -> today's.
RENAMED = {
    "first_opening_time_s": "first_opening_s", "wall_time_s": "wall_s",  # summary.json
    "shaking_s": "shaking_time_s",  # runs.csv, sweep.csv
    "open_joints": "joints_open", "cracked_joints": "joints_cracked", "slipped_joints": "joints_slipped",  # history.csv
    "fallen_blocks": "fallen_stones", "left_model_blocks": "blocks_left_model",
}


def _today(row):
    for old, new in RENAMED.items():
        if old in row:
            row.setdefault(new, row.pop(old))
    if "energy_balance_pct" in row:  # a percentage then, a fraction now
        pct = row.pop("energy_balance_pct")
        try:
            row.setdefault("energy_balance_error_relative", repr(float(pct) / 100))
        except (TypeError, ValueError):
            row.setdefault("energy_balance_error_relative", pct)
    return row


def read_summary(run):
    """A run folder's summary.json as a dict (first_opening_s is None when no joint opened)."""
    return _today(json.loads((Path(run) / "summary.json").read_text()))


def read_rows(path):
    """A CSV table's rows as dicts; no rows when the file does not exist."""
    path = Path(path)
    if not path.exists():
        return []
    with open(path, newline="") as f:
        return [_today(row) for row in csv.DictReader(f)]
