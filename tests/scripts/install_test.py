#!/usr/bin/python3
"""`cmake --install`: the installed program runs a scenario installed beside it and draws its
report with the installed scripts, not the source tree's (one script removed from the
installed copy is reported missing there), `study` finds the installed Nishida study, and
the installed comparison scripts run.
Arguments: the cmake program and the build folder (tests/CMakeLists.txt)."""
import subprocess
import sys
import tempfile
from pathlib import Path

cmake, build = sys.argv[1], sys.argv[2]


def run(args):
    done = subprocess.run(args, capture_output=True, text=True)
    return done.returncode, done.stdout + done.stderr


with tempfile.TemporaryDirectory() as tmp:
    prefix = Path(tmp) / "prefix"
    status, said = run([cmake, "--install", build, "--prefix", str(prefix)])
    assert status == 0, said
    program, share = prefix / "bin" / "ishibashi", prefix / "share" / "ishibashi"
    for shipped in ("analysis/report/run_report.py", "analysis/report/run_outputs.py", "scenarios/nishida_study.toml",
                    "models/nishida_f.toml", "data/ground_motions/kobe_1995_jma/RSN1106_KOBE_KJM-UP.AT2"):
        assert (share / shipped).is_file(), shipped
    assert not (share / "scenarios" / "results").exists(), "the kept results are not installed"
    # The comparison scripts import the installed report scripts' readers.
    status, said = run([str(share / "scripts" / "compare_ensembles.py"), "--help"])
    assert status == 0 and "usage" in said, said

    # The example's ../../models and ../../data paths resolve inside the installed share.
    out = Path(tmp) / "run"
    scenario = share / "scenarios" / "examples" / "stack_of_three_kobe.toml"
    short = ["run", "--quiet", str(scenario), "--duration", "0.02", "--settle-max", "0.02", "--out", str(out)]
    status, said = run([str(program)] + short)
    assert status == 0, said
    assert "warning" not in said, said
    assert (out / "report.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", said
    status, said = run([str(share / "scripts" / "compare_histories.py"), str(out), str(out), "--at", "0.01"])
    assert status == 0 and "| run |" in said, said

    (share / "analysis" / "report" / "run_report.py").unlink()
    (out / "report.png").unlink()
    status, said = run([str(program)] + short)
    assert status == 0, said
    missing = str(share / "analysis" / "report" / "run_report.py") + " is missing"
    assert "warning: report.png not drawn: " + missing in said, said
    assert not (out / "report.png").exists()

    # `study` without a file reads the installed study: moved away, its path is in the error.
    (share / "scenarios" / "nishida_study.toml").rename(share / "scenarios" / "moved.toml")
    status, said = run([str(program), "study", "--quick", "--out", str(Path(tmp) / "study")])
    assert status != 0, said
    assert str(share / "scenarios" / "nishida_study.toml") in said, said
print("installed program: ran, drew its report with the installed scripts, found the installed study")
