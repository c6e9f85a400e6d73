"""Campaign outputs record worker losses and retries; a campaign leaves no temp files and
prints no Dask traceback at a clean exit (issue 12, point 5), through real processes."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from test_cli import AXIR


def _env(tmp: Path) -> dict[str, str]:
    env = {**os.environ, "TMPDIR": str(tmp), "PYTHONUNBUFFERED": "1"}
    env.pop("AXIR_FMU_DIR", None)
    return env


def test_campaign_leaves_tmpdir_empty_and_no_traceback(tmp_path: Path, fmu_dir: Path) -> None:
    """A LocalCluster campaign with TMPDIR an empty folder: exit 0, no traceback or Dask
    log line on stderr, TMPDIR empty afterwards (extracted FMUs, the workers' FMU copies and
    Dask's scratch space removed), runs.csv has the worker_losses and retries columns."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    out = tmp_path / "mc"
    r = subprocess.run([*AXIR, "montecarlo", "svd-1", "--runs", "3", "--workers", "1",
                        "--duration", "5", "--out", str(out), "--fmu-dir", str(fmu_dir),
                        "--no-progress", "--no-plot"], env=_env(tmp), capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    for bad in ("Traceback", "distributed.", "heartbeat"):
        assert bad not in r.stderr, r.stderr
    assert sorted(os.listdir(tmp)) == []
    with open(out / "runs.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [(r["worker_losses"], r["retries"]) for r in rows] == [("0", "0")] * 3
    summary = json.loads((out / "campaign.json").read_text())
    assert summary["worker_losses"] == 0 and summary["retried_runs"] == []


@pytest.mark.slow
def test_killed_worker_is_recorded(tmp_path: Path, fmu_dir: Path) -> None:
    """SIGKILL one of two real Dask worker processes while it runs a closed-loop run: the
    scheduler runs it again on a new worker, every run succeeds, and runs.csv /
    campaign.json record the loss and the retry of the runs that worker held."""
    psutil = pytest.importorskip("psutil")
    out = tmp_path / "mc"
    p = subprocess.Popen([*AXIR, "montecarlo", "closed-loop", "--runs", "4", "--workers", "2",
                          "--duration", "3", "--out", str(out), "--fmu-dir", str(fmu_dir),
                          "--no-progress", "--no-plot"], env=_env(Path(os.environ.get(
                              "TMPDIR", "/tmp"))), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    killed = None
    try:
        deadline = time.monotonic() + 180
        while killed is None and p.poll() is None and time.monotonic() < deadline:
            for c in psutil.Process(p.pid).children(recursive=True):
                try:
                    busy = "spawn_main" in " ".join(c.cmdline()) and \
                        sum(c.cpu_times()[:2]) > 2.5  # loaded its FMUs and stepping
                    # (start-up ≈ 0.8 CPU s since session 6; a 3 s run ≈ 3-4 CPU s more)
                except psutil.Error:
                    continue
                if busy:
                    c.send_signal(signal.SIGKILL)
                    killed = c.pid
                    break
            time.sleep(0.2)
        _, err = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
    assert killed is not None, "no busy worker process found"
    assert p.returncode == 0, err
    with open(out / "runs.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert all(r["status"] == "ok" for r in rows)
    lost = [r for r in rows if int(r["worker_losses"]) > 0]
    assert lost and all(int(r["retries"]) == int(r["worker_losses"]) for r in lost), rows
    summary = json.loads((out / "campaign.json").read_text())
    assert summary["worker_losses"] == sum(int(r["worker_losses"]) for r in rows) >= 1
    assert sorted(r["run"] for r in summary["retried_runs"]) == [int(r["run"]) for r in lost]
