"""The seed-000 3-D maneuver test of the Tracker: NIS in the spherical basis, χ² threshold
with n_y = 3 on the fading-memory detector, false alarms and detection."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2
from three_axes import ThreeAxes

from axir.models.filters.gains import kalata_gains, tracking_index
from axir.models.radar.geometry import sph_to_cart_diff
from axir.models.tracker.maneuver import nis, seed000_detector


def test_nis_equals_full_covariance_form() -> None:
    rng = np.random.default_rng(3)
    for _ in range(20):
        rho, az, el = rng.uniform(1e3, 3e4), rng.uniform(0, 6.28), rng.uniform(-1.2, 1.2)
        sr, sa, f = 5.0, 2e-3, 1.7
        J = np.array([sph_to_cart_diff(rho, az, el, *e) for e in np.eye(3)]).T
        R = J @ np.diag([sr**2, (sa / math.cos(el)) ** 2, sa**2]) @ J.T
        nu = rng.normal(size=3) * 20
        expected = nu @ np.linalg.solve(f * R, nu)
        got = nis(tuple(nu), az, el, rho, sr, sa, f)
        assert got == pytest.approx(expected, rel=1e-9)


def test_detector_threshold_and_validation() -> None:
    d = seed000_detector(0.8, 1e-3)
    assert d.i1 == pytest.approx(chi2.ppf(0.999, 27.0) / 1.8)
    with pytest.raises(ValueError):
        seed000_detector(1.0, 1e-3)
    with pytest.raises(ValueError):
        seed000_detector(0.5, 0.0)


def _run_detector(accel: float, n: int, seed: int) -> tuple[np.ndarray, float]:
    rng = np.random.default_rng(seed)
    T, sig = 0.05, 10.0
    a_ss, b_ss = kalata_gains(tracking_index(1.0, T, sig))
    ab, det = ThreeAxes(), seed000_detector(0.8, 1e-3)
    rho, az, el = 10_000.0, 0.0, 0.0  # target on +Y, so X/Z are cross-range
    flags, mean_q = np.zeros(n, bool), []
    x = np.array([0.0, rho, 0.0])
    v = np.array([100.0, 0.0, 0.0])
    for k in range(n):
        if k >= n // 2:
            v = v + np.array([0.0, 0.0, accel]) * T
        x = x + v * T
        z = x + rng.normal(0, sig, 3)
        nu = ab.update(tuple(z), T, a_ss, b_ss)
        if ab.n >= 3:
            q = nis(nu, az, el, rho, sig, sig / rho, ab.innovation_factor())
            det.innovation(q)
            flags[k] = det.decide()
            if k > 200 and k < n // 2:
                mean_q.append(q)
    return flags, float(np.mean(mean_q))


def test_detector_false_alarms_low_and_maneuver_detected() -> None:
    flags, mean_q = _run_detector(accel=0.0, n=6000, seed=5)
    assert mean_q == pytest.approx(3.0, rel=0.1)  # E[νᵀS⁻¹ν] = 3 when S is right
    assert flags[200:].mean() < 0.01
    flags, _ = _run_detector(accel=60.0, n=1000, seed=6)
    assert flags[200:500].mean() < 0.02
    assert flags[500:560].any()  # 6 g vertical maneuver detected within 3 s
