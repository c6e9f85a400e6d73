"""The ``axir`` command line, through subprocesses (exit codes, one-line errors, files written).

User errors exit with code 2 and print ONE line naming the file / key / variable, never a
traceback. Every run loads pythonfmu FMUs into the process: it must also *exit* cleanly (the
pythonfmu exit-crash trap, docs/fmu_build.md), which the slow test checks 50 times.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

AXIR_SCRIPT = Path(sys.executable).parent / "axir"
AXIR = [str(AXIR_SCRIPT)] if AXIR_SCRIPT.exists() else [sys.executable, "-m",
                                                        "axir.orchestrator.cli"]


def axir(*args: str | Path, timeout: float = 120, cwd: Path | None = None
         ) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    env.pop("AXIR_FMU_DIR", None)
    return subprocess.run([*AXIR, *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, cwd=cwd, env=env)


def assert_user_error(r: subprocess.CompletedProcess[str], *needles: str) -> str:
    """Exit code 2, one line on stderr starting with 'error:', naming ``needles``."""
    err = r.stderr.strip()
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    assert "Traceback" not in r.stderr and "Traceback" not in r.stdout, r.stderr
    assert err.startswith("error:") and "\n" not in err, f"not one line: {r.stderr!r}"
    for n in needles:
        assert n in err, (n, err)
    return err


SCENARIO_UNITS = """
[units.Tracker]
fmu = "Tracker.fmu"
[units.Pedestal]
fmu = "Pedestal.fmu"
"""


# ------------------------------------------------------------------ info
def test_info_lists_variables_with_units(fmu_dir: Path) -> None:
    r = axir("info", fmu_dir / "Pedestal.fmu")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("Pedestal  FMI 2.0  GUID {")
    rows = {ln.split()[2]: ln for ln in lines[2:]}
    assert "[V]" in rows["cmd.az"] and rows["cmd.az"].split()[0] == "input"
    assert "[rad]" in rows["az"] and rows["az"].split()[0] == "output"
    assert "[Hz]" in rows["bandwidth"]
    assert rows["rate_per_volt"].split()[0] == "parameter"
    r = axir("info", fmu_dir / "Tracker.fmu")
    assert r.returncode == 0, r.stderr
    assert "beam.up[16,3]" in r.stdout and "sum[16,3]" in r.stdout
    real_rows = [ln for ln in r.stdout.splitlines()[2:] if ln.split()[1] == "Real"]
    assert real_rows and all("[]" not in ln for ln in real_rows), "every Real shows a unit"


def test_info_missing_file(tmp_path: Path) -> None:
    assert_user_error(axir("info", tmp_path / "Nope.fmu"), "Nope.fmu")


# ------------------------------------------------------------------ user errors → exit 2
def test_malformed_scenario_file(tmp_path: Path, fmu_dir: Path) -> None:
    f = tmp_path / "bad.toml"
    f.write_text('[scenario\nname = "x"\n')
    assert_user_error(axir("run", f, "--fmu-dir", fmu_dir, "--out", tmp_path / "o",
                           "--no-progress"), str(f), "malformed TOML")


def test_invalid_scenario_key(tmp_path: Path, fmu_dir: Path) -> None:
    f = tmp_path / "key.toml"
    f.write_text('[scenario]\nname = "x"\nduration = -1\n' + SCENARIO_UNITS)
    assert_user_error(axir("run", f, "--fmu-dir", fmu_dir, "--no-progress",
                           "--out", tmp_path / "o"), str(f), "scenario.duration")


def test_unknown_variable_in_connection(tmp_path: Path, fmu_dir: Path) -> None:
    f = tmp_path / "conn.toml"
    f.write_text('[scenario]\nname = "conn"\nduration = 0.01\nstep = 1e-3\n'
                 + SCENARIO_UNITS
                 + '[[connections]]\nfrom = "Tracker.cmd.azz"\nto = "Pedestal.cmd.az"\n'
                 + '[record]\nvariables = ["Pedestal.az"]\n')
    assert_user_error(axir("run", f, "--fmu-dir", fmu_dir, "--no-progress",
                           "--out", tmp_path / "o"), "Tracker", "'cmd.azz'")


def test_missing_fmu_file(tmp_path: Path) -> None:
    empty = tmp_path / "nofmus"
    empty.mkdir()
    err = assert_user_error(axir("run", "--fmu-dir", empty, "--no-progress",
                                 "--out", tmp_path / "o"), str(empty), ".fmu")
    assert "FMU file not found" in err


def test_unknown_scenario(tmp_path: Path, fmu_dir: Path) -> None:
    assert_user_error(axir("run", "no-such-scenario", "--fmu-dir", fmu_dir, "--no-progress",
                           "--out", tmp_path / "o"), "'no-such-scenario'", "closed-loop")


# ------------------------------------------------------------------ runs
def test_run_plot_writes_pngs_csv_summary(tmp_path: Path, fmu_dir: Path) -> None:
    out = tmp_path / "out"
    r = axir("run", "--duration", "0.3", "--seed", "3", "--plot", "--out", out,
             "--fmu-dir", fmu_dir, "--no-progress")
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr
    for name in ("errors.png", "ascope.png", "trajectory.png", "pedestal.png"):
        p = out / name
        assert p.is_file() and p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        assert f"wrote {p}" in r.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is True and summary["seed"] == 3
    assert summary["duration"] == 0.3
    header = (out / "results.csv").read_text().splitlines()[0]
    assert header.startswith('"time",')
    # the printed summary: engineering units (deg, m, s), summary.json stays SI (rad)
    assert f"{summary['steps']} in " in r.stdout and ", complete" in r.stdout
    pointing = [ln for ln in r.stdout.splitlines() if "max pointing error" in ln]
    assert len(pointing) == 1 and pointing[0].endswith(" deg"), r.stdout
    deg = float(pointing[0].split()[-2])
    assert deg == pytest.approx(summary["max_pointing_error_rad"] * 180 / 3.141592653589793,
                                rel=1e-3)


def test_sigint_writes_partial_results(tmp_path: Path, fmu_dir: Path) -> None:
    """A real Ctrl-C (SIGINT) during a run: partial results.csv + summary.json
    (complete: false), no traceback, no crash at exit; ideally exit code 130."""
    out = tmp_path / "out"
    err_file = tmp_path / "stderr.txt"
    with open(err_file, "w") as err:
        p = subprocess.Popen([*AXIR, "run", "--duration", "20", "--out", str(out), "--fmu-dir",
                              str(fmu_dir), "--progress"], stdout=subprocess.DEVNULL,
                             stderr=err, text=True)
        try:
            deadline = time.monotonic() + 60
            while "s sim" not in err_file.read_text() and time.monotonic() < deadline:
                time.sleep(0.1)  # the progress bar appears when the master starts stepping
            time.sleep(1.0)  # a few thousand steps
            p.send_signal(signal.SIGINT)
            p.wait(timeout=120)
        finally:
            if p.poll() is None:
                p.kill()
    stderr = err_file.read_text()
    assert p.returncode in (2, 130), (p.returncode, stderr)  # not a crash (< 0) nor 0
    assert "Traceback" not in stderr, stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is False and 0 < summary["end_time"] < 20
    assert (out / "results.csv").read_text().count("\n") >= 2
    assert p.returncode == 130, stderr  # an interrupt, not an FMU error
    assert summary["error"] is None


@pytest.mark.slow
def test_50_consecutive_runs_exit_cleanly(tmp_path: Path, fmu_dir: Path) -> None:
    """50 short runs in fresh processes all exit with 0: each loads the four pythonfmu FMUs,
    steps them and frees them (a double free / missing free aborts at interpreter exit)."""
    failures = []
    t0 = time.perf_counter()
    for i in range(50):
        r = axir("run", "--duration", "0.05", "--seed", str(i), "--out", tmp_path / "o",
                 "--fmu-dir", fmu_dir, "--no-progress", timeout=60)
        if r.returncode != 0:
            failures.append((i, r.returncode, r.stderr[-500:]))
    wall = time.perf_counter() - t0
    print(f"50 runs: {wall:.1f} s ({wall / 50:.2f} s per run)")
    assert failures == [], failures
