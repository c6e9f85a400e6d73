"""Two-state Kalman filter (seed 002 eqs. 1-10) and three-state filter: filterpy as the oracle,
analytic initialisation, coasting."""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter
from radial_track import radial_maneuver

from axir.models.filters.base import FilterConfig
from axir.models.filters.kalman import KalmanCA, KalmanCV, q_cwna, q_cwnj

TOL = 1e-9  # relative agreement required with filterpy (measured ≈ 3e-15)


def rel_diff(a: float, b: float) -> float:
    return abs(a - b) / max(1.0, abs(b))


def trajectory(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random intervals T_k in [0.5, 1.5] s (variable-step filters), see radial_maneuver."""
    return radial_maneuver(n, seed, T_lo=0.5, T_hi=1.5)


def test_q_matches_eq4_and_composes() -> None:
    # seed 002 eq. (4): Q = σm² T [[T²/3, T/2], [T/2, 1]]
    q11, q12, q22 = q_cwna(25.0, 2.0)
    assert (q11, q12, q22) == pytest.approx((25 * 2 * 4 / 3, 25 * 2 * 1, 25 * 2))
    # a continuous model: Q(T1 + T2) = Φ(T2) Q(T1) Φ(T2)ᵀ + Q(T2)
    for q_fun, F in ((q_cwna, lambda T: np.array([[1, T], [0, 1.0]])),
                     (q_cwnj, lambda T: np.array([[1, T, T * T / 2], [0, 1, T], [0, 0, 1.0]]))):
        def full(T: float, q_fun=q_fun) -> np.ndarray:
            v = q_fun(3.0, T)
            if len(v) == 3:
                return np.array([[v[0], v[1]], [v[1], v[2]]])
            return np.array([[v[0], v[1], v[2]], [v[1], v[3], v[4]], [v[2], v[4], v[5]]])
        t1, t2 = 0.7, 1.9
        lhs = full(t1 + t2)
        rhs = F(t2) @ full(t1) @ F(t2).T + full(t2)
        assert np.allclose(lhs, rhs, rtol=1e-12, atol=0)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_kalman_cv_equals_filterpy(seed: int) -> None:
    Ts, _, z = trajectory(150, seed)
    sm, sr = 5.0, 100.0
    kf = KalmanCV(FilterConfig(sigma_m=sm, sigma_meas=sr))
    ref = None
    worst = 0.0
    for k in range(len(z)):
        kf.update(z[k], Ts[k])
        if k == 1:  # same state and covariance as ours after the two-point initialisation
            ref = KalmanFilter(dim_x=2, dim_z=1)
            ref.x = np.array([[kf.pos], [kf.vel]])
            ref.P = np.array([[kf.p11, kf.p12], [kf.p12, kf.p22]])
            ref.H = np.array([[1.0, 0.0]])
            ref.R = np.array([[sr * sr]])
        elif k > 1:
            T = Ts[k]
            ref.F = np.array([[1.0, T], [0.0, 1.0]])
            q11, q12, q22 = q_cwna(sm * sm, T)
            ref.Q = np.array([[q11, q12], [q12, q22]])
            ref.predict()
            ref.update(z[k])
            ours = (kf.pos, kf.vel, kf.p11, kf.p12, kf.p22, kf.k1, kf.k2, kf.nu, kf.S)
            theirs = (ref.x[0, 0], ref.x[1, 0], ref.P[0, 0], ref.P[0, 1], ref.P[1, 1],
                      ref.K[0, 0], ref.K[1, 0], ref.y[0, 0], ref.S[0, 0])
            worst = max(worst, *(rel_diff(a, b) for a, b in zip(ours, theirs, strict=True)))
    assert worst < TOL, worst


def test_kalman_ca_equals_filterpy() -> None:
    Ts, _, z = trajectory(120, 7)
    cfg = FilterConfig(sigma_j=3.0)
    ca = KalmanCA(cfg)
    P0 = (1e4, 1e4, 0.0, 2e4, 0.0, 400.0)
    ca.set(z[0], 250.0, 0.0, P0)
    ref = KalmanFilter(dim_x=3, dim_z=1)
    ref.x = np.array([[z[0]], [250.0], [0.0]])
    ref.P = np.array([[1e4, 1e4, 0], [1e4, 2e4, 0], [0, 0, 400.0]])
    ref.H = np.array([[1.0, 0.0, 0.0]])
    ref.R = np.array([[1e4]])
    for k in range(1, len(z)):
        T = Ts[k]
        ca.predict_step(T, 1.0)
        ca.correct(z[k], 1e4)
        ref.F = np.array([[1, T, T * T / 2], [0, 1, T], [0, 0, 1.0]])
        q = q_cwnj(9.0, T)
        ref.Q = np.array([[q[0], q[1], q[2]], [q[1], q[3], q[4]], [q[2], q[4], q[5]]])
        ref.predict()
        ref.update(z[k])
        ours = (ca.pos, ca.vel, ca.acc, *ca.cov)
        theirs = (*ref.x[:, 0], ref.P[0, 0], ref.P[0, 1], ref.P[0, 2], ref.P[1, 1],
                  ref.P[1, 2], ref.P[2, 2])
        assert max(rel_diff(a, b) for a, b in zip(ours, theirs, strict=True)) < TOL


def test_two_point_initialisation_covariance() -> None:
    """P(0/0) of seed 002 §2.1 is the covariance of (y(1), (y(1) − y(0))/T) errors."""
    T, sr = 0.8, 30.0
    rng = np.random.default_rng(11)
    errs = []
    for _ in range(20000):
        kf = KalmanCV(FilterConfig(sigma_meas=sr))
        e0, e1 = rng.normal(0.0, sr, 2)
        kf.update(500.0 + e0, T)
        kf.update(500.0 + 40.0 * T + e1, T)
        errs.append((kf.pos - (500.0 + 40.0 * T), kf.vel - 40.0))
    emp = np.cov(np.array(errs).T)
    kf_p = (kf.p11, kf.p12, kf.p22)
    assert kf_p == pytest.approx((sr**2, sr**2 / T, 2 * sr**2 / T**2))
    assert emp[0, 0] == pytest.approx(kf_p[0], rel=0.05)
    assert emp[0, 1] == pytest.approx(kf_p[1], rel=0.05)  # + σr²/T: position = y(1)
    assert emp[1, 1] == pytest.approx(kf_p[2], rel=0.05)


def test_coast_then_update_equals_one_long_prediction() -> None:
    """Coasting T1 then updating after T2 = updating after T1 + T2 (continuous model)."""
    Ts, _, z = trajectory(30, 4)
    a, b = KalmanCV(), KalmanCV()
    for k in range(20):
        a.update(z[k], Ts[k])
        b.update(z[k], Ts[k])
    a.coast(0.4)
    a.update(z[20], 0.6)
    b.update(z[20], 1.0)
    for u, v in zip(a.x + a.P, b.x + b.P, strict=True):
        assert u == pytest.approx(v, rel=1e-12, abs=1e-9)
    # coasting before the second measurement lengthens the differencing interval
    c = KalmanCV()
    c.update(100.0, 1.0)
    c.coast(0.5)
    c.update(160.0, 1.5)
    assert c.vel == pytest.approx(30.0)


def test_first_measurement_only_and_validation() -> None:
    kf = KalmanCV(FilterConfig(sigma_meas=10.0))
    assert not kf.initialised and kf.n == 0
    assert kf.update(42.0, 1.0) == 0.0
    assert kf.x == (42.0, 0.0, 0.0) and kf.P == (100.0, 0.0, 0.0) and kf.n == 1
    with pytest.raises(ValueError, match="T > 0"):
        kf.update(43.0, 0.0)
