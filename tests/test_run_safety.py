"""Runs that never lose or corrupt results (issue 12), through real child processes: real
signals (SIGTERM, SIGHUP, SIGKILL), two real concurrent runs into one folder, real unusable
output paths, every pre-run check with its one-line error, an empty TMPDIR left empty.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import time
import zipfile
from pathlib import Path

import pytest
from fmpy.util import read_csv
from test_cli import AXIR, assert_user_error, axir

from axir.orchestrator.errors import AxirError
from axir.orchestrator.outdir import LOCK_NAME, claim, write_json_atomic
from axir.orchestrator.run import RUN_FILES


def start_run(out: Path, fmu_dir: Path, *args: str, env: dict[str, str] | None = None,
              duration: str = "5") -> subprocess.Popen[str]:
    return subprocess.Popen([*AXIR, "run", "--duration", duration, "--out", str(out),
                             "--fmu-dir", str(fmu_dir), "--no-progress", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, **(env or {})})


def wait_for_rows(p: subprocess.Popen[str], csv: Path, rows: int = 10,
                  timeout: float = 120) -> int:
    """Wait until ``csv`` holds ``rows`` data lines while ``p`` runs (the rows reached the
    disk during the run); returns the line count seen."""
    deadline = time.monotonic() + timeout
    n = 0
    while time.monotonic() < deadline and p.poll() is None:
        if csv.is_file():
            n = csv.read_bytes().count(b"\n") - 1
            if n >= rows:
                return n
        time.sleep(0.1)
    return n


def stop(p: subprocess.Popen[str]) -> tuple[str, str]:
    try:
        return p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()


# ------------------------------------------------------------------ 1. signals, streaming
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP])
def test_sigterm_sighup_flush_partial_results(tmp_path: Path, fmu_dir: Path,
                                              sig: signal.Signals) -> None:
    """A real SIGTERM / SIGHUP to a real child run, once rows have reached the disk: exit
    128 + signal, results.csv parses, summary.json complete false naming the signal, and the
    empty TMPDIR given to the run is empty again (extracted FMUs removed)."""
    out, tmp = tmp_path / "out", tmp_path / "tmp"
    tmp.mkdir()
    p = start_run(out, fmu_dir, env={"TMPDIR": str(tmp)})
    seen = wait_for_rows(p, out / "results.csv")
    assert seen >= 10, ("no rows on disk while running", stop(p))
    p.send_signal(sig)
    _, err = stop(p)
    assert p.returncode == 128 + sig, (p.returncode, err)
    assert "Traceback" not in err, err
    data = read_csv(str(out / "results.csv"))
    assert len(data) >= seen and data.dtype.names[0] == "time"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is False and summary["status"] == "interrupted"
    assert summary["signal"] == sig.name and summary["error"] is None
    assert 0 < data["time"][-1] < 5 and data["time"][-1] == pytest.approx(summary["end_time"])
    assert sorted(os.listdir(tmp)) == [], "temp files left behind"


def test_sigkill_keeps_streamed_rows_and_running_status(tmp_path: Path, fmu_dir: Path) -> None:
    """SIGKILL cannot be handled: the rows streamed so far stay readable (whole lines) and
    summary.json says the run never finished (status running, complete false)."""
    out = tmp_path / "out"
    p = start_run(out, fmu_dir)
    seen = wait_for_rows(p, out / "results.csv")
    assert seen >= 10, stop(p)
    p.kill()
    stop(p)
    assert p.returncode == -signal.SIGKILL
    data = read_csv(str(out / "results.csv"))
    assert len(data) >= seen and data["time"][-1] > 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "running" and summary["complete"] is False


def test_complete_run_results_equal_the_recording(tmp_path: Path, fmu_dir: Path) -> None:
    """The streamed results.csv is byte-identical to writing the recording at the end (the
    format of every release so far), and the final summary replaces the running one."""
    from axir.orchestrator.record import write_csv
    from axir.orchestrator.run import run_scenario
    from axir.orchestrator.scenario import load_scenario

    out = tmp_path / "out"
    summary, rec = run_scenario(load_scenario("closed-loop"), fmu_dir, out, seed=3,
                                duration=0.2, progress=False)
    write_csv(tmp_path / "whole.csv", rec)
    assert (out / "results.csv").read_bytes() == (tmp_path / "whole.csv").read_bytes()
    on_disk = json.loads((out / "summary.json").read_text())
    assert on_disk["status"] == "complete" and on_disk["complete"] is True
    assert on_disk["steps"] == summary["steps"] > 0
    assert [n for n in os.listdir(out) if n.startswith(".axir-tmp")] == []


# ------------------------------------------------------------------ 2. one run per folder
def test_two_concurrent_runs_into_one_folder(tmp_path: Path, fmu_dir: Path) -> None:
    """The second run into a folder another run is using is refused (exit 2, naming the
    folder) while the first is still running (it is long; SIGTERM ends it afterwards); the
    folder keeps the first run's results.csv, which fmpy reads, and its own summary."""
    out = tmp_path / "out"
    first = start_run(out, fmu_dir, "--seed", "5", duration="60")
    wait_for_rows(first, out / "results.csv", rows=1)
    assert first.poll() is None, stop(first)
    second = axir("run", "--duration", "0.5", "--seed", "6", "--out", out, "--fmu-dir",
                  fmu_dir, "--no-progress")
    still_running = first.poll() is None
    first.send_signal(signal.SIGTERM)
    _, err = stop(first)
    assert still_running, err
    assert first.returncode == 128 + signal.SIGTERM, err
    assert_user_error(second, str(out), "in use by another axir run")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["seed"] == 5 and summary["status"] == "interrupted"
    assert len(read_csv(str(out / "results.csv"))) > 1


def test_folder_reuse_clears_earlier_run_and_refuses_foreign_files(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    for name in ("results.csv", "summary.json", "errors.png", "trajectory.png"):
        (out / name).write_text("earlier run")
    with claim(out, RUN_FILES):
        assert sorted(os.listdir(out)) == [LOCK_NAME]  # the earlier --plot PNGs are gone
        with pytest.raises(AxirError, match="in use by another axir run"):
            claim(out, RUN_FILES)  # same process, second descriptor: flock refuses too
    (out / "notes.txt").write_text("mine")
    (out / "results.csv").write_text("earlier run")
    with pytest.raises(AxirError, match=r"'notes\.txt', which no axir run wrote"):
        claim(out, RUN_FILES)
    assert (out / "notes.txt").read_text() == "mine"
    assert (out / "results.csv").is_file()  # nothing deleted when refused


def test_nested_results_folder_left_alone(tmp_path: Path) -> None:
    """out/montecarlo (a campaign's folder) inside a run's folder is neither foreign nor
    cleared."""
    out = tmp_path / "out"
    (out / "montecarlo").mkdir(parents=True)
    (out / "montecarlo" / "campaign.json").write_text("{}")
    (out / "summary.json").write_text("earlier run")
    with claim(out, RUN_FILES):
        assert sorted(os.listdir(out)) == [LOCK_NAME, "montecarlo"]
    assert (out / "montecarlo" / "campaign.json").read_text() == "{}"


def test_write_json_atomic_replaces_whole_file(tmp_path: Path) -> None:
    target = tmp_path / "s.json"
    write_json_atomic(target, {"status": "running"})
    write_json_atomic(target, {"status": "complete", "x": [1, 2]})
    assert json.loads(target.read_text()) == {"status": "complete", "x": [1, 2]}
    assert os.listdir(tmp_path) == ["s.json"]
    with pytest.raises(TypeError):
        write_json_atomic(target, {"bad": object()})
    assert json.loads(target.read_text())["status"] == "complete"  # old file intact
    assert os.listdir(tmp_path) == ["s.json"]  # no temp file left


# ------------------------------------------------------------------ 3. checked before the run
TOML = """
[scenario]
name = "t"
{scenario}
[units.TargetGenerator]
parameters = {{ {params} }}
[units.Tracker]
[units.Pedestal]
[units.RadarManager]
"""


@pytest.mark.parametrize(("scenario", "params", "needles"), [
    ("duration = 0.2", 'rcs = "big"', ["TargetGenerator.rcs", "'big'"]),
    ("duration = 0.2", "rcs = -1.0", ["TargetGenerator.rcs", "out of range"]),
    ("duration = 0.2", "rcs = nan", ["TargetGenerator.rcs", "finite"]),
    ("duration = 0.2", "seed = 4294967298", ["TargetGenerator.seed", "4294967298", "32 bit"]),
    ("duration = 0.2", "noise = 2", ["TargetGenerator.noise", "Boolean"]),
    ("duration = inf", "", ["scenario.duration", "inf"]),
    ("duration = 0.2\ninitial_step = inf", "", ["scenario.initial_step", "inf"]),
    ("duration = 1e12", "", ["1e+12", "--long"]),
], ids=["rcs-string", "rcs-range", "rcs-nan", "int32", "bool", "duration-inf",
        "initial-step-inf", "duration-1e12"])
def test_scenario_values_refused_before_the_run(tmp_path: Path, fmu_dir: Path, scenario: str,
                                               params: str, needles: list[str]) -> None:
    f = tmp_path / "s.toml"
    f.write_text(TOML.format(scenario=scenario, params=params))
    out = tmp_path / "out"
    assert_user_error(axir("run", f, "--fmu-dir", fmu_dir, "--out", out, "--no-progress"),
                      str(f) if "1e12" not in scenario else "--long", *needles)
    assert not out.exists()  # refused before anything was written


def test_non_utf8_scenario(tmp_path: Path, fmu_dir: Path) -> None:
    f = tmp_path / "latin1.toml"
    text = TOML.format(scenario="duration = 0.2", params="")
    f.write_bytes("# café\n".encode("latin-1") + text.encode())
    assert_user_error(axir("run", f, "--fmu-dir", fmu_dir, "--out", tmp_path / "o"),
                      str(f), "UTF-8")


def _rewrite_fmu(src: Path, dst: Path, edit) -> None:
    with zipfile.ZipFile(src) as z:
        entries = {i.filename: z.read(i) for i in z.infolist()}
    entries = edit(entries)
    with zipfile.ZipFile(dst, "w") as z:
        for name, data in entries.items():
            z.writestr(name, data)


def _fmu_copy(fmu_dir: Path, tmp_path: Path, unit: str, edit) -> Path:
    d = tmp_path / "fmus"
    d.mkdir()
    for f in fmu_dir.glob("*.fmu"):
        if f.stem == unit:
            _rewrite_fmu(f, d / f.name, edit)
        else:
            (d / f.name).write_bytes(f.read_bytes())
    return d


def test_fmu_without_linux64_binary(tmp_path: Path, fmu_dir: Path) -> None:
    d = _fmu_copy(fmu_dir, tmp_path, "Tracker", lambda e: {
        k: v for k, v in e.items() if not k.startswith("binaries/linux64/")})
    assert_user_error(axir("run", "--fmu-dir", d, "--out", tmp_path / "o"),
                      "Tracker.fmu", "binaries/linux64/Tracker.so")


def test_fmu_guid_mismatch(tmp_path: Path, fmu_dir: Path) -> None:
    def edit(e: dict[str, bytes]) -> dict[str, bytes]:
        md = e["modelDescription.xml"].decode()
        guid = re.search(r'guid="([^"]+)"', md).group(1)
        e["modelDescription.xml"] = md.replace(guid, "{0f0f0f0f-0000-4000-8000-000000000000}"
                                               ).encode()
        return e

    d = _fmu_copy(fmu_dir, tmp_path, "Pedestal", edit)
    assert_user_error(axir("run", "--fmu-dir", d, "--out", tmp_path / "o"),
                      "Pedestal.fmu", "GUID {0f0f0f0f-0000-4000-8000-000000000000}")


def test_content_guid_matches_fresh_build(fmu_dir: Path) -> None:
    """The GUID check recomputes exactly what fmus/build.py wrote (every built FMU passes)."""
    from axir.orchestrator.preflight import check_fmu_file

    for f in sorted(fmu_dir.glob("*.fmu")):
        assert check_fmu_file(f, f.stem).guid.startswith("{")


@pytest.mark.parametrize("command", ["run", "montecarlo"])
def test_output_path_under_a_file(tmp_path: Path, fmu_dir: Path, command: str) -> None:
    (tmp_path / "afile").write_text("x")
    args = ["--runs", "2", "--workers", "1"] if command == "montecarlo" else []
    r = axir(command, *args, "--duration", "0.2", "--out", tmp_path / "afile" / "sub",
             "--fmu-dir", fmu_dir, "--no-progress")
    assert_user_error(r, "afile/sub", "is a file, not a folder")
    assert "wrote" not in r.stdout  # refused before the run, not after it


@pytest.mark.parametrize("command", ["run", "montecarlo"])
def test_unwritable_output_folder(tmp_path: Path, fmu_dir: Path, command: str) -> None:
    """A read-only folder (chmod 555); as root, who writes anywhere, a folder under /sys,
    where the kernel refuses even root."""
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    out = Path("/sys/axir_unwritable") if os.geteuid() == 0 else ro / "sub"
    args = ["--runs", "2", "--workers", "1"] if command == "montecarlo" else []
    try:
        r = axir(command, *args, "--duration", "0.2", "--out", out, "--fmu-dir",
                 fmu_dir, "--no-progress")
    finally:
        ro.chmod(0o755)
    assert_user_error(r, str(out), "not writable")


def test_set_values_refused_before_the_campaign(tmp_path: Path, fmu_dir: Path) -> None:
    for assignment, needle in (("TargetGenerator.seed=4294967298", "32 bit"),
                               ("TargetGenerator.noise=2", "Boolean"),
                               ("TargetGenerator.rcs=big", "'big'")):
        r = axir("montecarlo", "svd-1", "--runs", "2", "--workers", "1", "--out",
                 tmp_path / "mc", "--fmu-dir", fmu_dir, "--set", assignment, "--no-progress")
        assert_user_error(r, "--set", assignment.split("=")[0], needle)
    assert not (tmp_path / "mc").exists()


# ------------------------------------------------------------------ 4. temp files
def test_no_temp_files_left_by_run_or_error(tmp_path: Path, fmu_dir: Path) -> None:
    """With TMPDIR an empty folder, a complete run and a run failing after its FMUs were
    extracted (an unknown recorded variable) leave it empty."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    env = {**os.environ, "TMPDIR": str(tmp)}
    env.pop("AXIR_FMU_DIR", None)

    def run(*args: str | Path) -> subprocess.CompletedProcess[str]:
        return subprocess.run([*AXIR, "run", *map(str, args), "--fmu-dir", str(fmu_dir),
                               "--no-progress"], env=env, capture_output=True, text=True,
                              timeout=120)

    ok = run("--duration", "0.1", "--out", tmp_path / "o")
    assert ok.returncode == 0, ok.stderr
    assert os.listdir(tmp) == []
    f = tmp_path / "bad.toml"
    f.write_text(TOML.format(scenario="duration = 0.1", params="")
                 + '[record]\nvariables = ["Tracker.no_such_variable"]\n')
    bad = run(f, "--out", tmp_path / "o2")
    assert_user_error(bad, "no_such_variable")
    assert os.listdir(tmp) == []


def test_duration_check_scales_with_runs_and_workers() -> None:
    from axir.orchestrator.config import LONG_RUN_S, US_PER_STEP
    from axir.orchestrator.preflight import check_duration

    step = 1e-4
    day_duration = LONG_RUN_S / (US_PER_STEP * 1e-6) * step  # [s] simulated in a day of wall
    check_duration(0.99 * day_duration, step, long_ok=False)
    with pytest.raises(AxirError, match="--long"):
        check_duration(1.01 * day_duration, step, long_ok=False)
    check_duration(1.01 * day_duration, step, long_ok=True)
    with pytest.raises(AxirError, match="--long"):  # 10 runs on 2 workers: 5 runs each
        check_duration(0.25 * day_duration, step, long_ok=False, runs=10, workers=2)
    check_duration(0.19 * day_duration, step, long_ok=False, runs=10, workers=2)


def test_value_problem_int32_bool_real() -> None:
    from types import SimpleNamespace

    from axir.orchestrator.preflight import value_problem

    integer = SimpleNamespace(type="Integer", min="0", max=None, unit=None)
    assert value_problem("U.n", integer, 2**31 - 1) is None
    assert "32 bit" in value_problem("U.n", integer, 2**31)
    assert "32 bit" in value_problem("U.n", integer, 4294967298)
    assert "Integer" in value_problem("U.n", integer, 1.5)
    assert "out of range" in value_problem("U.n", integer, -1)
    boolean = SimpleNamespace(type="Boolean", min=None, max=None, unit=None)
    for ok in (True, False, 0, 1):
        assert value_problem("U.b", boolean, ok) is None
    for bad in (2, -1, "true", 0.5):
        assert "Boolean" in value_problem("U.b", boolean, bad)
    real = SimpleNamespace(type="Real", min="0.0", max="10.0", unit="m")
    assert value_problem("U.x", real, 10) is None
    assert value_problem("U.x", real, 10.5) == "U.x = 10.5 is out of range [0.0, 10.0] m"
    assert "finite" in value_problem("U.x", real, float("inf"))
    assert "a number" in value_problem("U.x", real, True)
