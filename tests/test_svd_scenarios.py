"""Built-in scenarios svd-1 and svd-2 (seed 002 §7): the documented maneuver profiles, the
TargetGenerator → Tracker measurement system through the FMUs, and short campaigns.

The truth is checked against the piecewise constant-acceleration motion written out here from
the values stated in the scenario files (independent of models/radar/trajectory.py).
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from axir.models.target_generator import TargetGenerator
from axir.orchestrator.campaign import run_campaign
from axir.orchestrator.run import run_scenario
from axir.orchestrator.scenario import load_scenario

#: the documented profiles: (onset [s], offset [s], radial acceleration [m/s²])
PROFILES = {
    "svd-1": [(30.0, 50.0, 20.0)],
    "svd-2": [(30.0, 40.0, 50.0), (60.0, 70.0, -50.0)],
}
SIGMA_M = {"svd-1": 5.0, "svd-2": 20.0}  # seed 002: σm1, σm2 [m/s²]
R0, V0, T, SIGMA_R = 1000.0, 250.0, 1.0, 100.0  # seed 002 §7


def radial_truth(t: np.ndarray, profile: list[tuple[float, float, float]]):
    """Range, range rate, range acceleration of a target receding radially from R0 at V0 with
    acceleration steps ``profile``."""
    r, v, a = R0 + V0 * t, np.full_like(t, V0), np.zeros_like(t)
    for on, off, acc in profile:
        d = off - on
        inside = (t >= on) & (t < off)
        tau = np.clip(t - on, 0.0, d)  # time spent accelerating so far
        a += np.where(inside, acc, 0.0)
        v += acc * tau
        r += acc * tau * tau / 2 + acc * d * np.clip(t - off, 0.0, None)
    return r, v, a


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_scenario_values_and_truth_profile(name: str) -> None:
    sc = load_scenario(name)
    assert sc.step == T and sc.duration == 100.0 and sc.order == ["TargetGenerator", "Tracker"]
    tg = sc.units["TargetGenerator"]["parameters"]
    tr = sc.units["Tracker"]["parameters"]
    assert tg["fidelity"] == "measurement" and tg["meas_interval"] == T
    assert tg["meas_sigma_range"] == SIGMA_R == tr["sigma_range"]
    assert tr["input_mode"] == "measurement" and tr["filter_sigma_m"] == SIGMA_M[name]
    conns = {(c.src_unit, c.src_var, c.dst_unit, c.dst_var) for c in sc.connections}
    assert conns == {("TargetGenerator", f"meas.{v}", "Tracker", f"meas.{v}")
                     for v in ("range", "az", "el", "valid", "new")}
    gen = TargetGenerator(**tg)
    t = np.arange(1.0, 101.0)
    out = [gen.step(T, {}) for _ in t]
    r, v, a = radial_truth(t, PROFILES[name])
    np.testing.assert_allclose([o["truth.range"] for o in out], r, rtol=1e-12)
    np.testing.assert_allclose([o["truth.range_rate"] for o in out], v, rtol=1e-12)
    np.testing.assert_allclose([o["truth.range_acc"] for o in out], a, atol=1e-9)
    # along the line of sight: azimuth 90° (East), elevation 0, whatever the range
    np.testing.assert_allclose([o["truth.az"] for o in out], np.pi / 2, atol=1e-12)
    np.testing.assert_allclose([o["truth.el"] for o in out], 0.0, atol=1e-12)
    assert json.loads(tg["trajectory"])["position"] == [R0, 0.0, 0.0]


# ------------------------------------------------------------------ through the FMUs
def test_svd1_kalman_reaches_the_riccati_steady_state(fmu_dir: Path) -> None:
    """svd-1 with the two-state Kalman filter on the range axis, through both FMUs: before the
    maneuver the Tracker's P(k/k) is the steady state of the discrete Riccati equation of
    seed 002 eqs. (1)-(10) with σm1 and σr (scipy's DARE): the scenario's noise values reach
    the filter, one measurement per step."""
    sc = load_scenario("svd-1")
    units = {**sc.units, "Tracker": {**sc.units["Tracker"],
                                     "parameters": {**sc.units["Tracker"]["parameters"],
                                                    "filter_range": "kalman"}}}
    summary, rec = run_scenario(replace(sc, units=units), fmu_dir, None, progress=False)
    assert summary["complete"] and summary["steps"] == 100
    phi = np.array([[1.0, T], [0.0, 1.0]])
    q = SIGMA_M["svd-1"] ** 2 * T * np.array([[T * T / 3, T / 2], [T / 2, 1.0]])  # eq. (4)
    h = np.array([[1.0, 0.0]])
    prior = solve_discrete_are(phi.T, h.T, q, np.array([[SIGMA_R**2]]))
    post = prior - prior @ h.T @ h @ prior / (prior[0, 0] + SIGMA_R**2)
    t = rec.data[:, 0]
    k = int(np.flatnonzero(t == 29.0)[0])
    got = [rec.column(f"Tracker.track.P_{c}")[k] for c in ("rr", "rv", "vv")]
    np.testing.assert_allclose(got, [post[0, 0], post[0, 1], post[1, 1]], rtol=1e-3)
    assert np.all(rec.column("Tracker.track.valid")[1:] == 1)


@pytest.fixture(scope="module")
def short_campaigns(fmu_dir: Path):
    """svd-1 and svd-2, 8 runs each, with the SVD and the Kalman range filters (in-process)."""
    out = {}
    for name in PROFILES:
        for f in ("svd", "kalman"):
            out[(name, f)] = run_campaign(name, fmu_dir, 8, workers=0, progress=False,
                                          parameters={"Tracker": {"filter_range": f}})
    return out


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_short_campaigns_run_and_aggregate(short_campaigns, name: str) -> None:
    """Every run succeeds; range, velocity and acceleration errors and the NEES are
    aggregated; the SVD filter's acceleration estimate closes in on the maneuver level over the
    second half of the first maneuver (a filter without one, Kalman, reports 0: its
    acceleration error is the maneuver level itself); before the
    first maneuver both filter the 100 m noise down (RMS < σr) with a NEES at or below its
    95 % band (the truth has no random acceleration: the filters are conservative)."""
    on, off, acc = PROFILES[name][0]
    for f in ("svd", "kalman"):
        res = short_campaigns[(name, f)]
        assert res.summary["succeeded"] == 8, res.failed
        agg = res.aggregates
        assert set(agg.rms) == {"range", "velocity", "acceleration"}
        assert agg.nees is not None and np.all(agg.n[1:] == 8)
        quiet = (agg.t >= 10.0) & (agg.t < on)
        assert np.mean(agg.rms["range"][quiet]) < 0.8 * SIGMA_R
        assert np.mean(agg.nees[quiet]) < np.mean(agg.nees_band[1][quiet])
    late = (short_campaigns[(name, "svd")].aggregates.t >= on + (off - on) / 2) & (
        short_campaigns[(name, "svd")].aggregates.t < off)
    svd_acc = short_campaigns[(name, "svd")].aggregates.rms["acceleration"][late]
    kal_acc = short_campaigns[(name, "kalman")].aggregates.rms["acceleration"][late]
    np.testing.assert_allclose(kal_acc, abs(acc), rtol=1e-12)
    assert svd_acc[-1] < svd_acc[0] and svd_acc[-1] < 0.75 * abs(acc)


# ------------------------------------------------------------------ reports/seed002.py
def _seed002():
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "reports"))
    import seed002

    return seed002


def test_seed002_periods_and_windows() -> None:
    s2 = _seed002()
    assert s2.maneuver_windows(load_scenario("svd-2")) == [(30.0, 40.0, 50.0),
                                                           (60.0, 70.0, -50.0)]
    t = np.arange(1.0, 101.0)
    p = s2.periods(t, s2.maneuver_windows(load_scenario("svd-1")))
    np.testing.assert_array_equal(t[p.maneuver], np.arange(30.0, 50.0))
    np.testing.assert_array_equal(t[p.after], np.arange(50.0, 50.0 + s2.SETTLE))
    np.testing.assert_array_equal(t[p.quiet], np.r_[np.arange(s2.WARMUP, 30.0),
                                                    np.arange(50.0 + s2.SETTLE, 101.0)])


def test_seed002_report_end_to_end(fmu_dir: Path, tmp_path: Path) -> None:
    """The report with 3 runs and two filters: figures, markdown with the verdict, JSON."""
    s2 = _seed002()
    assert s2.main(["--runs", "3", "--filters", "svd,vd", "--fmu-dir", str(fmu_dir),
                    "--out", str(tmp_path)]) == 0
    for f in ("seed002_profiles.png", "seed002_svd-1_rms.png", "seed002_svd-2_rms.png",
              "seed002_nees.png"):
        assert (tmp_path / f).stat().st_size > 10_000, f
    md = (tmp_path / "seed002.md").read_text()
    assert "## Against the paper" in md and md.count("claim 1") == 2
    blob = json.loads((tmp_path / "seed002.json").read_text())
    assert set(blob["metrics"]) == {"svd-1/svd", "svd-1/vd", "svd-2/svd", "svd-2/vd"}
    assert all(v["runs_ok"] == 3 for v in blob["metrics"].values())
    # the range filter's own flag: the replay reproduces the FMU's track.range exactly
    assert all(v["replay_max_diff_m"] == 0.0 for v in blob["metrics"].values())


def test_range_filter_replay_flag_is_the_range_filters(short_campaigns) -> None:
    """The replayed range filter reproduces the FMU's track.range bit for bit, and its flag
    differs from ``Tracker.maneuver`` (range OR angle detectors) only where the recorded
    ``Tracker.maneuver`` is up: the OR can only add flags."""
    s2 = _seed002()
    res = short_campaigns[("svd-2", "svd")]
    rep = s2.range_filter_replay(res)
    assert rep["max_diff_m"] == 0.0
    j = 1 + res.spec.record.index("Tracker.maneuver")
    ored = np.stack([r["data"][1:, j] for r in res.results]) > 0.5
    assert rep["flag"].shape == ored.shape
    assert not np.any(rep["flag"] & ~ored)
    assert rep["tuning"]["filter_sigma_a"] == 5.0 and rep["tuning"]["fmd_end"] == "hysteresis"
