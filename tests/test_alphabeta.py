"""α-β filters: evolutive gains = least squares, Kalata steady gains, maneuver detector."""

from __future__ import annotations

import math

import numpy as np
import pytest
from filterpy.common import Q_discrete_white_noise
from filterpy.gh import least_squares_parameters
from filterpy.kalman import KalmanFilter
from scipy.linalg import solve_discrete_lyapunov
from scipy.stats import chi2

from axir.models.alphabeta import (
    AlphaBeta3,
    ManeuverDetector,
    evolutive_gains,
    kalata_gains,
    prediction_vrr,
    stable_gains,
    tracking_index,
)
from axir.models.radar.geometry import sph_to_cart_diff


def test_evolutive_gains_match_filterpy_least_squares() -> None:
    for n in range(1, 60):
        assert evolutive_gains(n) == pytest.approx(least_squares_parameters(n - 1), rel=1e-15)
    with pytest.raises(ValueError):
        evolutive_gains(0)


def test_evolutive_filter_equals_polyfit() -> None:
    rng = np.random.default_rng(1)
    T = 0.1
    t = np.arange(50) * T
    z = np.stack([50 + 3 * t, -20 + 0.5 * t, 7 - 2 * t], axis=1) + rng.normal(0, 1.0, (50, 3))
    ab = AlphaBeta3()
    ab.update(tuple(z[0]), T)
    assert ab.x == pytest.approx(list(z[0]), abs=1e-12)  # n = 1: position = measurement
    for n in range(2, 51):
        ab.update(tuple(z[n - 1]), T)
        assert ab.n == n
        for axis in range(3):
            slope, icpt = np.polyfit(t[:n], z[:n, axis], 1)
            assert ab.x[axis] == pytest.approx(icpt + slope * t[n - 1], abs=1e-9)
            assert ab.v[axis] == pytest.approx(slope, abs=1e-9)


def test_steady_gains_take_over_per_gain() -> None:
    ab = AlphaBeta3()
    a_ss, b_ss = 0.3, 0.05
    ab.update((0.0, 0.0, 0.0), 1.0, a_ss, b_ss)
    for n in range(2, 40):
        ab.update((1.0, 2.0, 3.0), 1.0, a_ss, b_ss)
        a_n, b_n = 2 * (2 * n - 1) / (n * (n + 1)), 6 / (n * (n + 1))
        assert ab.alpha == max(a_n, a_ss)
        assert ab.beta == max(b_n, b_ss)
    # unstable or missing steady gains are ignored: evolutive only
    ab2 = AlphaBeta3()
    for _ in range(1, 30):
        ab2.update((1.0, 2.0, 3.0), 1.0, 1.5, 2.0)  # β > 4 − 2α: unstable pair
    assert ab2.alpha == pytest.approx(2 * (2 * 29 - 1) / (29 * 30))
    assert not stable_gains(1.5, 2.0) and stable_gains(0.5, 0.1) and not stable_gains(0.0, 0.1)


def test_n_max_caps_evolutive_index() -> None:
    ab = AlphaBeta3(n_max=10)
    for _ in range(30):
        ab.update((1.0, 1.0, 1.0), 1.0)
    assert (ab.alpha, ab.beta) == pytest.approx(evolutive_gains(10))


def test_dsp_form_constant_velocity_is_exact_and_predict_coast() -> None:
    # any stable gains: a noise-free constant-velocity track is followed without error
    ab = AlphaBeta3()
    T = 0.01
    for k in range(200):
        ab.update((100 + 5 * k * T, -3 * k * T, 2.0), T, 0.4, 0.1)
    t_last = 199 * T
    assert ab.x == pytest.approx([100 + 5 * t_last, -3 * t_last, 2.0], abs=1e-8)
    assert ab.v == pytest.approx([5.0, -3.0, 0.0], abs=1e-8)
    assert ab.predict(0.5) == pytest.approx((100 + 5 * (t_last + 0.5), -3 * (t_last + 0.5), 2.0))
    ab.coast(0.5)
    assert ab.x == pytest.approx([100 + 5 * (t_last + 0.5), -3 * (t_last + 0.5), 2.0])


def test_tracking_index_definition() -> None:
    assert tracking_index(5.0, 2.0, 10.0) == pytest.approx(2.0)
    with pytest.raises(ValueError):
        tracking_index(1.0, 1.0, 0.0)


@pytest.mark.parametrize("lam", [1e-4, 0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 100.0])
def test_kalata_identities(lam: float) -> None:
    a, b = kalata_gains(lam)
    assert 0 < a < 1 and 0 < b < 2
    # Kalata (1984): Λ² = β²/(1 − α) and β = 2(2 − α) − 4√(1 − α)
    assert lam**2 == pytest.approx(b**2 / (1 - a), rel=1e-9)
    assert b == pytest.approx(2 * (2 - a) - 4 * math.sqrt(1 - a), rel=1e-9, abs=1e-15)
    # Kalata's explicit (cancellation-prone) formulas, for moderate Λ
    if lam >= 0.01:
        s = math.sqrt(lam**2 + 8 * lam)
        assert a == pytest.approx(-(lam**2 + 8 * lam - (lam + 4) * s) / 8, rel=1e-9)
        assert b == pytest.approx((lam**2 + 4 * lam - lam * s) / 4, rel=1e-9)


def test_kalata_limits_and_not_benedict_bordner() -> None:
    assert kalata_gains(0.0) == (0.0, 0.0)
    a, b = kalata_gains(1e8)
    assert a == pytest.approx(1.0, abs=1e-6) and b == pytest.approx(2.0, abs=1e-6)
    # α = 0.5 ⇔ r = √0.5 ⇔ Λ = 2(1 − r)²/r: β = 3 − 2√2 ≈ 0.1716, whereas the
    # Benedict-Bordner pair would be α²/(2 − α) = 1/6
    r = math.sqrt(0.5)
    a, b = kalata_gains(2 * (1 - r) ** 2 / r)
    assert a == pytest.approx(0.5, rel=1e-12)
    assert b == pytest.approx(3 - 2 * math.sqrt(2), rel=1e-12)
    assert abs(b - a * a / (2 - a)) > 4e-3


@pytest.mark.parametrize("sig_w,T,sig_n", [(1.0, 1.0, 10.0), (20.0, 1.0, 100.0),
                                            (50.0, 0.1, 2.0), (5.0, 0.5, 0.5)])
def test_kalata_gains_equal_kalman_steady_state(sig_w: float, T: float, sig_n: float) -> None:
    kf = KalmanFilter(dim_x=2, dim_z=1)
    kf.F = np.array([[1.0, T], [0.0, 1.0]])
    kf.H = np.array([[1.0, 0.0]])
    kf.R *= sig_n**2
    kf.Q = Q_discrete_white_noise(dim=2, dt=T, var=sig_w**2)  # piecewise-constant accel.
    kf.P *= 1e6
    for _ in range(5000):
        kf.predict()
        kf.update(np.array([0.0]))
    a, b = kalata_gains(tracking_index(sig_w, T, sig_n))
    assert kf.K[0, 0] == pytest.approx(a, abs=1e-6)
    assert kf.K[1, 0] * T == pytest.approx(b, abs=1e-6)


@pytest.mark.parametrize("a,b", [(0.5, 0.1716), (0.2, 0.02), (0.8, 0.5), (1.2, 0.9), (0.1, 0.2)])
def test_prediction_vrr_matches_lyapunov(a: float, b: float) -> None:
    T = 0.3
    F = np.array([[1.0, T], [0.0, 1.0]])
    K = np.array([[a], [b / T]])
    H = np.array([[1.0, 0.0]])
    A = (np.eye(2) - K @ H) @ F
    P_upd = solve_discrete_lyapunov(A, K @ K.T)  # σ² = 1, no process noise
    P_pred = F @ P_upd @ F.T
    assert prediction_vrr(a, b) == pytest.approx(P_pred[0, 0], rel=1e-9)
    assert prediction_vrr(1.5, 1.5) == math.inf


def test_innovation_factor_least_squares_phase() -> None:
    # S/σ² at measurement n = 1 + variance of the LS line extrapolated from n − 1 points
    ab = AlphaBeta3()
    for n in range(1, 30):
        ab.update((0.0, 0.0, 0.0), 1.0)
        if n < 3:
            assert ab.innovation_factor() == math.inf
            continue
        m = n - 1
        A = np.stack([np.ones(m), np.arange(1, m + 1)], axis=1)
        g = np.array([1.0, m + 1.0])
        expected = 1.0 + g @ np.linalg.inv(A.T @ A) @ g
        assert ab.innovation_factor() == pytest.approx(expected, rel=1e-9)


def test_nis_equals_full_covariance_form() -> None:
    rng = np.random.default_rng(3)
    for _ in range(20):
        rho, az, el = rng.uniform(1e3, 3e4), rng.uniform(0, 6.28), rng.uniform(-1.2, 1.2)
        sr, sa, f = 5.0, 2e-3, 1.7
        J = np.array([sph_to_cart_diff(rho, az, el, *e) for e in np.eye(3)]).T
        R = J @ np.diag([sr**2, (sa / math.cos(el)) ** 2, sa**2]) @ J.T
        nu = rng.normal(size=3) * 20
        expected = nu @ np.linalg.solve(f * R, nu)
        got = ManeuverDetector.nis(tuple(nu), az, el, rho, sr, sa, f)
        assert got == pytest.approx(expected, rel=1e-9)


def test_detector_threshold_and_validation() -> None:
    d = ManeuverDetector(0.8, 1e-3)
    assert d.threshold == pytest.approx(chi2.ppf(0.999, 27.0) / 1.8)
    with pytest.raises(ValueError):
        ManeuverDetector(1.0, 1e-3)
    with pytest.raises(ValueError):
        ManeuverDetector(0.5, 0.0)


def _run_detector(accel: float, n: int, seed: int) -> tuple[np.ndarray, float]:
    rng = np.random.default_rng(seed)
    T, sig = 0.05, 10.0
    a_ss, b_ss = kalata_gains(tracking_index(1.0, T, sig))
    ab, det = AlphaBeta3(), ManeuverDetector(0.8, 1e-3)
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
            q = ManeuverDetector.nis(nu, az, el, rho, sig, sig / rho, ab.innovation_factor())
            flags[k] = det.update(q)
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
