"""Monte Carlo campaigns (orchestrator/campaign.py): reuse of FMU instances by fmi2Reset,
determinism across worker counts, failed runs, statistics, NEES and the CLI.

Scenarios are tiny: the TargetGenerator alone in measurement fidelity (20 steps of 1 s) or
the closed loop for 0.03 s. Expected values come from outside the code under test:
``run_scenario`` (fresh instances), the measurement noise σ the generator is given, numpy's
linear algebra and scipy's χ² quantiles.
"""

from __future__ import annotations

import copy
import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import chi2

from axir.orchestrator.campaign import (
    LOCAL_CLUSTER_QUIET,
    aggregate,
    nees2,
    nees_band,
    parse_assignment,
    prepare,
    run_campaign,
)
from axir.orchestrator.errors import AxirError
from axir.orchestrator.run import run_scenario
from axir.orchestrator.scenario import Scenario, load_scenario, parse_scenario

SIGMA_R = 100.0  # [m] measurement noise given to the generator (seed 002's σr)
MEAS_ERRORS = {"range": ("TargetGenerator.meas.range", "TargetGenerator.truth.range")}

AXIR_SCRIPT = Path(sys.executable).parent / "axir"
AXIR = [str(AXIR_SCRIPT)] if AXIR_SCRIPT.exists() else [sys.executable, "-m",
                                                        "axir.orchestrator.cli"]

TG_TOML = f"""
connections = []
[scenario]
name = "tg-only"
duration = 20.0
seed = 3
order = ["TargetGenerator"]
step = 1.0
[units.TargetGenerator]
parameters = {{ fidelity = "measurement", meas_sigma_range = {SIGMA_R} }}
"""


def tg_scenario() -> Scenario:
    """The TargetGenerator alone, measuring every 1 s for 20 s (seed-002 like noise); the
    same as :data:`TG_TOML`."""
    data = {"connections": [],
            "scenario": {"name": "tg-only", "duration": 20.0, "seed": 3,
                         "order": ["TargetGenerator"], "step": 1.0},
            "units": {"TargetGenerator": {"parameters": {"fidelity": "measurement",
                                                         "meas_sigma_range": SIGMA_R}}}}
    return parse_scenario(data, "<test tg-only>")


def axir(*args: str | Path, timeout: float = 180) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    env.pop("AXIR_FMU_DIR", None)
    return subprocess.run([*AXIR, *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)


# ------------------------------------------------------------------ reuse by fmi2Reset
def test_reused_instances_equal_fresh_runs(fmu_dir: Path) -> None:
    """Runs 0..2 in one process reuse the same four instances (fmi2Reset, parameters incl. the
    run's seeds, initialization): each equals ``run_scenario`` with seed BASE + i on freshly
    instantiated FMUs, bit for bit; and different seeds give different noise."""
    sc = replace(load_scenario("closed-loop"), duration=0.03)
    res = run_campaign(sc, fmu_dir, 3, workers=0, seed=11, progress=False)
    assert [r["status"] for r in res.results] == ["ok"] * 3, res.failed
    record = list(res.spec.record)
    assert "TargetGenerator.truth.range_acc" in record and "Tracker.track.range" in record
    for r in res.results:
        _, rec = run_scenario(replace(sc, record=record), fmu_dir, None, seed=11 + r["run"],
                              progress=False)
        np.testing.assert_array_equal(r["data"], rec.data)
    assert not np.array_equal(res.results[0]["data"], res.results[1]["data"])


# ------------------------------------------------------------------ Dask: 1 vs 2 workers
@pytest.fixture(scope="module")
def external_cluster():
    """A one-worker Dask cluster started here, used through its scheduler address."""
    import logging

    from distributed import LocalCluster

    cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                           silence_logs=logging.ERROR, **LOCAL_CLUSTER_QUIET)
    yield cluster.scheduler_address
    cluster.close()


def test_one_and_two_workers_identical_with_a_failed_run(fmu_dir: Path, tmp_path: Path,
                                                         external_cluster: str) -> None:
    """Same campaign on an existing 1-worker cluster (--scheduler) and on a 2-worker
    LocalCluster: identical aggregates and per-run results. Run 3 has an invalid parameter:
    it is reported (callback, runs.csv) and the other runs, including the later ones on the
    same worker, still run and are aggregated."""
    runs, bad = 8, 3
    per_run = {bad: {"TargetGenerator": {"meas_sigma_range": -1.0}}}
    out = {}
    failures: dict[int, list[dict]] = {1: [], 2: []}
    for n in (1, 2):
        kw = {"scheduler": external_cluster} if n == 1 else {"workers": 2}
        out[n] = run_campaign(tg_scenario(), fmu_dir, runs, per_run=per_run,
                              errors=MEAS_ERRORS, progress=False, out_dir=tmp_path / f"w{n}",
                              on_failure=failures[n].append, **kw)
    a1, a2 = out[1].aggregates, out[2].aggregates
    assert a1.t.size == 20 and np.all(a1.n == runs - 1)
    np.testing.assert_array_equal(a1.t, a2.t)
    np.testing.assert_array_equal(a1.rms["range"], a2.rms["range"])
    np.testing.assert_array_equal(a1.mean["range"], a2.mean["range"])
    assert a1.per_run == a2.per_run
    for r1, r2 in zip(out[1].results, out[2].results, strict=True):
        assert r1["status"] == r2["status"]
        if r1["status"] == "ok":
            np.testing.assert_array_equal(r1["data"], r2["data"])
    assert out[1].summary["executed_on"].startswith("scheduler ")
    assert "LocalCluster of 2" in out[2].summary["executed_on"]
    assert len({r["worker"] for r in out[2].results if r["status"] == "ok"}) == 2
    for n in (1, 2):
        assert [f["run"] for f in failures[n]] == [bad]
        assert "meas_sigma_range" in failures[n][0]["error"]
        assert out[n].summary["failed"] == 1 and out[n].summary["succeeded"] == runs - 1
        rows = (tmp_path / f"w{n}" / "runs.csv").read_text().splitlines()
        assert len(rows) == runs + 1
        assert rows[1 + bad].split(",")[2] == "failed" and "meas_sigma_range" in rows[1 + bad]
        assert (tmp_path / f"w{n}" / "campaign.png").stat().st_size > 0


# ------------------------------------------------------------------ statistics
def test_rms_of_measurement_error_is_sigma(fmu_dir: Path) -> None:
    """RMS over 40 runs × 20 samples of (meas.range − truth.range) is the σr the generator
    was given: RMS²/σ² ~ χ²(800)/800 (relative s.d. of the RMS 2.5 %: bound at 4 s.d.), mean
    within 4 σ/√800 of 0; seeds are BASE + i (runs.csv)."""
    res = run_campaign(tg_scenario(), fmu_dir, 40, workers=0, seed=100, errors=MEAS_ERRORS,
                       progress=False)
    agg = res.aggregates
    e = agg.errors["range"]
    assert e.shape == (40, 20) and np.all(np.isfinite(e))
    assert np.sqrt(np.mean(e * e)) == pytest.approx(SIGMA_R, rel=4 / np.sqrt(2 * 800))
    assert abs(np.mean(e)) < 4 * SIGMA_R / np.sqrt(800)
    np.testing.assert_allclose(agg.rms["range"], np.sqrt(np.mean(e * e, axis=0)), rtol=1e-12)
    assert [r["seed"] for r in res.results] == list(range(100, 140))


def test_nees_matches_linear_algebra() -> None:
    rng = np.random.default_rng(1)
    for _ in range(50):
        a = rng.normal(size=(2, 2))
        p = a @ a.T + 0.1 * np.eye(2)
        e = rng.normal(size=2) * 30
        expect = e @ np.linalg.solve(p, e)
        got = nees2(e[0], e[1], p[0, 0], p[0, 1], p[1, 1])
        assert got == pytest.approx(expect, rel=1e-10)
    assert np.isnan(nees2(1.0, 1.0, 1.0, 2.0, 1.0))  # not positive definite
    assert np.isnan(nees2(1.0, 1.0, 0.0, 0.0, 0.0))  # no covariance yet


def test_mean_nees_of_consistent_errors_inside_band_95_percent() -> None:
    """Errors drawn from N(0, P) with the P they are scored with: the mean NEES over N = 50
    runs falls in the 95 % χ² band at ≈ 95 % of 4000 time samples (binomial s.d. 0.35 %)."""
    rng = np.random.default_rng(7)
    runs, times = 50, 4000
    p = np.array([[1.0e4, 2.0e3], [2.0e3, 1.5e3]])
    e = rng.multivariate_normal([0.0, 0.0], p, size=(runs, times))
    eps = nees2(e[..., 0], e[..., 1], p[0, 0], p[0, 1], p[1, 1])
    lo, hi = nees_band(np.full(times, runs))
    mean = eps.mean(axis=0)
    inside = np.mean((mean >= lo) & (mean <= hi))
    assert inside == pytest.approx(0.95, abs=0.015)
    assert lo[0] == pytest.approx(chi2.ppf(0.025, 100) / 50) and lo[0] < 2.0 < hi[0]


def _result(run: int, t: np.ndarray, cols: np.ndarray) -> dict:
    return {"run": run, "seed": run, "status": "ok", "error": "", "worker": "w", "steps": 0,
            "wall_s": 0.0, "data": np.column_stack([t, cols])}


def test_aggregate_grid_validity_and_nees_from_records() -> None:
    """Hand-made records: the t = 0 sample is dropped, samples without a valid track are
    excluded, a run on another time grid is interpolated, the NEES uses the recorded P."""
    rec = ["Tracker.track.range", "TargetGenerator.truth.range", "Tracker.track.range_rate",
           "TargetGenerator.truth.range_rate", "Tracker.track.P_rr", "Tracker.track.P_rv",
           "Tracker.track.P_vv", "Tracker.track.valid"]
    t = np.arange(0.0, 4.0)
    ones = np.ones_like(t)
    # run 0: range error 3, velocity error 0, P = diag(9, 1) → NEES 1; invalid at t = 1
    r0 = np.column_stack([100 + 3 * ones, 100 * ones, 5 * ones, 5 * ones, 9 * ones, 0 * ones,
                          ones, [1, 0, 1, 1]])
    # run 1 on a half-step grid: range error 4·t, velocity error 0, P = diag(16, 1)
    t1 = np.arange(0.0, 3.5, 0.5)
    o1 = np.ones_like(t1)
    r1 = np.column_stack([4 * t1, 0 * o1, o1, o1, 16 * o1, 0 * o1, o1, o1])
    failed = {"run": 2, "seed": 2, "status": "failed", "error": "x", "data": None}
    agg = aggregate([_result(1, t1, r1), failed, _result(0, t, r0)], rec)
    np.testing.assert_array_equal(agg.t, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(agg.n, [1, 2, 2])
    np.testing.assert_allclose(agg.rms["range"], [4.0, np.sqrt((9 + 64) / 2),
                                                  np.sqrt((9 + 144) / 2)])
    np.testing.assert_allclose(agg.nees, [1.0, (1 + 4) / 2, (1 + 9) / 2])
    np.testing.assert_array_equal(agg.nees_n, [1, 2, 2])
    assert set(agg.rms) == {"range", "velocity"}  # no acceleration recorded
    assert [r["run"] for r in agg.per_run] == [0, 1]


# ------------------------------------------------------------------ inputs
def test_parse_assignment() -> None:
    assert parse_assignment("Tracker.filter_range=svd") == ("Tracker", "filter_range", "svd")
    assert parse_assignment("A.x = 3") == ("A", "x", 3)
    assert parse_assignment("A.x=1e-3") == ("A", "x", 1e-3)
    assert parse_assignment("A.flag=TRUE") == ("A", "flag", True)
    for bad in ("A=3", "Ax", ".x=1", "A.=1"):
        with pytest.raises(AxirError, match=r"UNIT\.PARAMETER=VALUE"):
            parse_assignment(bad)


def test_prepare_errors_name_the_problem(fmu_dir: Path, tmp_path: Path) -> None:
    with pytest.raises(AxirError, match="unknown unit 'Nope'"):
        prepare(tg_scenario(), fmu_dir, 2, parameters={"Nope": {"x": 1}})
    with pytest.raises(AxirError, match="FMU file not found"):
        prepare(tg_scenario(), tmp_path, 2)
    with pytest.raises(AxirError, match="--runs"):
        prepare(tg_scenario(), fmu_dir, 0)
    sc = copy.deepcopy(tg_scenario())
    spec, blobs = prepare(sc, fmu_dir, 2, duration=5.0)
    assert spec.scenario.duration == 5.0 and set(blobs) == {"TargetGenerator"}
    assert "TargetGenerator.truth.range" in spec.record


# ------------------------------------------------------------------ CLI
def test_cli_montecarlo_writes_outputs_and_exit_codes(fmu_dir: Path, tmp_path: Path) -> None:
    scen = tmp_path / "tg.toml"
    scen.write_text(TG_TOML)
    out = tmp_path / "mc"
    r = axir("montecarlo", scen, "--runs", "4", "--workers", "2", "--out", out, "--fmu-dir",
             fmu_dir, "--seed", "7", "--duration", "5", "--no-progress")
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr
    summary = json.loads((out / "campaign.json").read_text())
    assert summary["succeeded"] == 4 and summary["seeds"] == "7..10"
    assert summary["duration"] == 5.0
    assert (out / "runs.csv").read_text().count("\n") == 5
    # usage error: --workers with --scheduler
    r = axir("montecarlo", scen, "--runs", "2", "--workers", "1", "--scheduler", "tcp://x:1",
             "--fmu-dir", fmu_dir)
    assert r.returncode == 2 and "mutually exclusive" in r.stderr
    # an invalid parameter for all runs: refused before the campaign, exit 2, named
    r = axir("montecarlo", scen, "--runs", "2", "--workers", "1", "--out", tmp_path / "bad",
             "--fmu-dir", fmu_dir, "--set", "TargetGenerator.meas_sigma_range=-5",
             "--no-progress")
    assert r.returncode == 2, r.stderr
    assert "--set: TargetGenerator.meas_sigma_range = -5 is out of range" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "bad").exists()


@pytest.mark.slow
def test_cli_montecarlo_exits_cleanly_repeatedly(fmu_dir: Path, tmp_path: Path) -> None:
    """Five invocations with 2 worker processes each loading the FMU: all exit 0 with no
    worker crash on stderr (the pythonfmu exit trap in worker processes)."""
    scen = tmp_path / "tg.toml"
    scen.write_text(TG_TOML)
    for i in range(5):
        r = axir("montecarlo", scen, "--runs", "4", "--workers", "2", "--out", tmp_path / "o",
                 "--fmu-dir", fmu_dir, "--seed", str(i), "--no-plot", "--no-progress")
        assert r.returncode == 0, (i, r.stderr[-2000:])
        for bad in ("Traceback", "died", "signal", "core dumped", "corrupted"):
            assert bad not in r.stderr, (i, bad, r.stderr[-2000:])
