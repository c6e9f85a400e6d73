"""Filter selection in the Tracker: the measurement input mode (seed-002 experiments), the
spherical → Cartesian kinematics, the range-axis outputs, the state save/restore per filter and
the filter parameters."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from axir.models.filters.registry import FILTER_KINDS
from axir.models.radar.geometry import sph_to_cart
from axir.models.tracker import Tracker
from axir.models.tracker.measurement import sph_to_cart_kinematics

NEW_OUTPUTS = ("track.range_acc", "track.acc.x", "track.acc.y", "track.acc.z", "track.P_rr",
               "track.P_rv", "track.P_vv")


# ------------------------------------------------------------------ geometry
def test_sph_to_cart_kinematics_matches_finite_differences() -> None:
    def sph(t: float) -> tuple[float, float, float]:
        return 5000.0 + 200.0 * t + 3.0 * t * t, 0.3 + 0.02 * t - 0.004 * t * t, \
            0.1 + 0.01 * t + 0.002 * t * t

    t, h = 1.3, 1e-4
    s = sph(t)
    sd = (200.0 + 6.0 * t, 0.02 - 0.008 * t, 0.01 + 0.004 * t)
    sdd = (6.0, -0.008, 0.004)
    pos, vel, acc = sph_to_cart_kinematics(s, sd, sdd)
    c = [np.array(sph_to_cart(*sph(t + d))) for d in (-h, 0.0, h)]
    assert pos == pytest.approx(tuple(c[1]), rel=1e-12)
    assert vel == pytest.approx(tuple((c[2] - c[0]) / (2 * h)), rel=1e-6)
    assert acc == pytest.approx(tuple((c[2] - 2 * c[1] + c[0]) / h**2), rel=1e-3, abs=1e-3)


# ------------------------------------------------------------------ measurement mode
def meas_inputs(r: float, az: float, el: float, new: bool = True, valid: bool = True) -> dict:
    return {"meas.range": r, "meas.az": az % (2 * math.pi), "meas.el": el,
            "meas.valid": float(valid), "meas.new": float(new)}


def run_measurement(kind: str, n: int = 100, seed: int = 3, **params: object
                    ) -> tuple[Tracker, list[dict], np.ndarray]:
    """Seed-002-like target (1000 m, 250 m/s, 30 m/s² between 40 and 70 s), T = 1 s."""
    rng = np.random.default_rng(seed)
    trk = Tracker(input_mode="measurement", filter_range=kind, filter_az=kind, filter_el=kind,
                  sigma_range=100.0, sigma_angle=1e-3, **params)
    r, v, outs, truth = 1000.0, 250.0, [], []
    for k in range(n):
        a = 30.0 if 40 <= k < 70 else 0.0
        if k:
            r += v + 0.5 * a
            v += a
        truth.append(r)
        outs.append(trk.step(1.0, meas_inputs(r + rng.normal(0, 100.0),
                                              0.5 + 1e-3 * rng.normal(),
                                              0.1 + 1e-3 * rng.normal())))
    return trk, outs, np.array(truth)


@pytest.mark.parametrize("kind", FILTER_KINDS)
def test_measurement_mode_each_filter(kind: str) -> None:
    trk, outs, truth = run_measurement(kind)
    fr = trk.core.sph[0]
    out = outs[-1]
    assert all(np.all(np.isfinite(np.asarray(v, dtype=float))) for o in outs
               for v in o.values())
    assert out["track.valid"] and not out["coasting"] and out["track.n"] == 100
    assert (out["track.range"], out["track.range_rate"], out["track.range_acc"]) == fr.x
    assert (out["track.P_rr"], out["track.P_rv"], out["track.P_vv"]) == fr.P
    err = np.array([o["track.range"] for o in outs]) - truth
    assert np.sqrt(np.mean(err[5:] ** 2)) < 400.0
    assert out["track.az"] == pytest.approx(0.5, abs=3e-3)
    pos = sph_to_cart(out["track.range"], out["track.az"], out["track.el"])
    assert (out["track.x"], out["track.y"], out["track.z"]) == pytest.approx(pos)
    assert out["cmd.az"] == 0.0 and out["dev.range"] == 0.0
    if fr.has_acceleration:
        assert any(o["track.range_acc"] != 0.0 for o in outs[40:80])


def test_measurement_mode_maneuver_flag_and_acceleration() -> None:
    _, outs, _ = run_measurement("svd", n=120)
    flags = [o["maneuver"] for o in outs]
    assert any(flags[40:55])
    acc = [o["track.range_acc"] for o in outs[55:70]]
    assert np.mean(acc) == pytest.approx(30.0, abs=10.0)
    stat = [o["maneuver.statistic"] for o in outs]
    thr = outs[0]["maneuver.threshold"]
    assert thr > 0.0 and max(stat[40:60]) > thr


def test_measurement_mode_coasts_between_samples_and_waits_for_valid() -> None:
    trk = Tracker(input_mode="measurement", filter_range="kalman", sigma_range=10.0)
    out = trk.step(0.25, meas_inputs(math.nan, 0.0, 0.0, new=False, valid=False))
    assert not out["track.valid"] and out["coasting"] and out["track.n"] == 0
    for k in range(12):  # a sample every 4 steps of 0.25 s
        out = trk.step(0.25, meas_inputs(1000.0 + 100.0 * k, 0.2, 0.05, new=True))
        assert not out["coasting"]
        for j in range(1, 4):
            out = trk.step(0.25, meas_inputs(1000.0 + 100.0 * k, 0.2, 0.05, new=False))
            assert out["coasting"] and out["track.n"] == k + 1
            if k >= 3:  # extrapolated at 100 m/s
                assert out["track.range"] == pytest.approx(1000.0 + 100.0 * (k + j / 4),
                                                           abs=1e-6)
    # a NaN measurement is not used
    out = trk.step(0.25, meas_inputs(math.nan, 0.2, 0.05))
    assert out["coasting"] and out["track.n"] == 12


def test_measurement_mode_azimuth_wraps_through_north() -> None:
    trk = Tracker(input_mode="measurement", filter_range="kalman", filter_az="kalman",
                  filter_el="kalman", sigma_range=1.0, sigma_angle=1e-6)
    for k in range(40):
        az = -0.02 + 0.001 * k  # crosses 0 (= 2π) at k = 20
        out = trk.step(1.0, meas_inputs(10_000.0, az, 0.1))
        assert math.cos(out["track.az"] - az) == pytest.approx(1.0, abs=1e-9)
        assert 0.0 <= out["track.az"] < 2 * math.pi
    assert trk.core.sph[1].x[1] == pytest.approx(0.001, rel=1e-3)  # continuous azimuth rate


def beams_inputs(rng: np.random.Generator) -> dict:
    """Noisy beams with an echo in the gate bins 6-8 (random imbalance), confirmed mode."""
    b = 1.0 + 0.2 * rng.random((4, 16, 3))
    b[:, 5:8, :] += 60.0 * (1.0 + 0.05 * rng.standard_normal((4, 1, 1)))
    return {"beam": b, "ped.az": 0.6, "ped.el": 0.1, "mode": 2, "alpha": 0.3, "beta": 0.05,
            "range.offset": 0.0, "gate.command": 5000.0}


@pytest.mark.parametrize("kind", FILTER_KINDS)
@pytest.mark.parametrize("mode", ["measurement", "beams"])
def test_state_round_trip_bit_identical(kind: str, mode: str) -> None:
    if mode == "measurement":
        trk, _, _ = run_measurement(kind, n=50)
        seq = [meas_inputs(20_000.0 + 260.0 * k, 0.5, 0.1, new=k % 3 == 0) for k in range(40)]
        dt = 1.0
    else:
        trk = Tracker(filter_x=kind, filter_y=kind, filter_z=kind)
        rng = np.random.default_rng(9)
        seq = [beams_inputs(rng) for k in range(40)]
        dt = 1e-3
        for s in seq[:10]:
            trk.step(dt, s)
        seq = seq[10:]
    state = trk.get_state()
    blob = pickle.dumps(state)
    first = [trk.step(dt, s) for s in seq]
    for restored in (state, pickle.loads(blob)):
        other = Tracker()
        other.set_state(restored)
        again = [other.step(dt, s) for s in seq]
        for a, b in zip(first, again, strict=True):
            assert a.keys() == b.keys()
            for key in a:
                assert np.array_equal(a[key], b[key]), key


def test_beams_mode_new_outputs() -> None:
    """Default (α-β) outputs: no acceleration; P projected on the line of sight."""
    trk = Tracker()
    rng = np.random.default_rng(2)
    out = {}
    for _ in range(20):
        out = trk.step(1e-3, beams_inputs(rng))
    assert out["track.valid"] and not out["coasting"]
    for key in NEW_OUTPUTS:
        assert key in out and math.isfinite(out[key])
    assert out["track.range_acc"] == 0.0 and out["track.acc.x"] == 0.0
    u = np.array([out["track.x"], out["track.y"], out["track.z"]]) / out["track.range"]
    p = np.array([f.P for f in trk.core.axes])  # (3 axes, (pp, pv, vv))
    assert out["track.P_rr"] == pytest.approx(float(u**2 @ p[:, 0]))
    assert out["track.P_vv"] == pytest.approx(float(u**2 @ p[:, 2]))
    assert out["track.P_rr"] > 0.0


def test_parameter_validation() -> None:
    with pytest.raises(ValueError, match="filter_range"):
        Tracker(filter_range="ukf")
    with pytest.raises(ValueError, match="input_mode"):
        Tracker(input_mode="tracks")
    with pytest.raises(ValueError, match="filter_sigma_m"):
        Tracker(filter_sigma_m=-1.0)
    with pytest.raises(ValueError, match="fmd_level"):
        Tracker(fmd_level=1.0)
    trk = Tracker(filter_x="vd", fmd_i1=7.5, fmd_i2=11.04, maneuver_fading=0.8)
    assert (trk.core.axes[0].fmd.i1, trk.core.axes[0].fmd.i2) == (7.5, 11.04)
    assert not trk.core.legacy_detector
