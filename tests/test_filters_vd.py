"""Variable dimension filter (Bar-Shalom & Birmiwal 1982; seed 002 Fig. 2)."""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from axir.models.filters.base import FilterConfig
from axir.models.filters.kalman import KalmanCV, q_cwnj
from axir.models.filters.vd import VDFilter

CFG = FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_a=2.0, sigma_j=2.0)


def maneuver(n: int, seed: int, a: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """(truth, z) at T = 1 s: 250 m/s from 1000 m, ``a`` m/s² between samples 40 and 70."""
    rng = np.random.default_rng(seed)
    r, v = [1000.0], 250.0
    for k in range(1, n):
        acc = a if 40 <= k < 70 else 0.0
        r.append(r[-1] + v + 0.5 * acc)
        v += acc
    truth = np.array(r)
    return truth, truth + rng.normal(0.0, 100.0, n)


def test_reinitialisation_formula() -> None:
    """One stored update: â = 2/T²·(z − ẑ), v̂ = v̂(j−1) + T·â, r̂ = z, and P33 =
    (4/T⁴)(r + P11 + 2T P12 + T² P22) (Bar-Shalom & Birmiwal 1982)."""
    vd = VDFilter(CFG)
    T, r = 2.0, 400.0
    p, v, a = 1000.0, 50.0, 7.0
    p11, p12, p22 = 90.0, 20.0, 9.0
    z = p + v * T + 0.5 * a * T * T
    vd.history.append((z, T, T, r, 1.0, p, v, p11, p12, p22))
    vd._to_three_state()
    ca = vd.ca
    assert vd.mode == 3 and vd.maneuver
    assert (ca.pos, ca.vel, ca.acc) == pytest.approx((z, v + a * T, a))
    assert ca.p11 == pytest.approx(r)
    assert ca.p13 == pytest.approx(2.0 * r / T**2)
    assert ca.p33 == pytest.approx(4.0 / T**4 * (r + p11 + 2 * T * p12 + T * T * p22))
    # the full covariance: A Σ Aᵀ (numpy), A = ∂(r̂, v̂, â)/∂(z, r̂(j−1), v̂(j−1))
    A = np.array([[1, 0, 0], [2 / T, -2 / T, -1], [2 / T**2, -2 / T**2, -2 / T]])
    S = np.array([[r, 0, 0], [0, p11, p12], [0, p12, p22]])
    P = A @ S @ A.T
    assert ca.cov == pytest.approx((P[0, 0], P[0, 1], P[0, 2], P[1, 1], P[1, 2], P[2, 2]))


def test_switch_reruns_the_window_like_a_three_state_kalman() -> None:
    """At the detection step k the three-state state equals a filterpy CA filter started at
    k − M from the re-initialisation and run over z(k − M + 1) … z(k)."""
    _, z = maneuver(120, 1)
    vd, cv = VDFilter(CFG), KalmanCV(CFG)
    before = []
    k_det = None
    for k in range(len(z)):
        before.append((cv.pos, cv.vel, cv.p11, cv.p12, cv.p22))
        cv.update(z[k], 1.0)
        vd.update(z[k], 1.0)
        if vd.mode == 3:
            k_det = k
            break
    assert k_det is not None and 40 <= k_det < 60
    M = vd.fmd.window
    j = k_det - M
    pos, vel, p11, p12, p22 = before[j]
    T, r = 1.0, 1e4
    a0 = 2.0 / T**2
    acc = a0 * (z[j] - (pos + T * vel))
    A = np.array([[1, 0, 0], [2 / T, -2 / T, -1], [a0, -a0, -2 / T]])
    ref = KalmanFilter(dim_x=3, dim_z=1)
    ref.x = np.array([[z[j]], [vel + T * acc], [acc]])
    ref.P = A @ np.array([[r, 0, 0], [0, p11, p12], [0, p12, p22]]) @ A.T
    ref.F = np.array([[1, T, 0.5], [0, 1, T], [0, 0, 1.0]])
    q = q_cwnj(CFG.sigma_j**2, T)
    ref.Q = np.array([[q[0], q[1], q[2]], [q[1], q[3], q[4]], [q[2], q[4], q[5]]])
    ref.H = np.array([[1.0, 0, 0]])
    ref.R = np.array([[r]])
    for i in range(j + 1, k_det + 1):
        ref.predict()
        ref.update(z[i])
    ca = vd.ca
    ours = (ca.pos, ca.vel, ca.acc, *ca.cov)
    theirs = (*ref.x[:, 0], ref.P[0, 0], ref.P[0, 1], ref.P[0, 2], ref.P[1, 1], ref.P[1, 2],
              ref.P[2, 2])
    for u, v in zip(ours, theirs, strict=True):
        assert abs(u - v) <= 1e-9 * max(1.0, abs(v))
    assert vd.x == (ca.pos, ca.vel, ca.acc)


def test_maneuver_tracked_and_model_returns_to_two_states() -> None:
    truth, z = maneuver(160, 11)
    vd, cv = VDFilter(CFG), KalmanCV(CFG)
    e_vd, e_cv, modes = [], [], []
    for k in range(len(z)):
        vd.update(z[k], 1.0)
        cv.update(z[k], 1.0)
        e_vd.append(vd.x[0] - truth[k])
        e_cv.append(cv.x[0] - truth[k])
        modes.append(vd.mode)
    win = slice(50, 80)
    assert np.sqrt(np.mean(np.square(e_vd[win]))) < 0.5 * np.sqrt(np.mean(np.square(e_cv[win])))
    assert 3 in modes[40:55]
    assert modes[-1] == 2 and vd.x[2] == 0.0 and not vd.maneuver
    assert vd.switches >= 2
    # the three-state model holds through the rest of the maneuver
    assert np.all(np.array(modes[55:70]) == 3)


def test_end_test_uses_chi2_window() -> None:
    vd = VDFilter(CFG)
    assert vd.fmd.window == 5
    assert vd.fmd.i2 == pytest.approx(11.0705, abs=1e-3)


def test_coast_and_state_round_trip() -> None:
    _, z = maneuver(120, 5)
    vd = VDFilter(CFG)
    for k in range(55):
        vd.update(z[k], 1.0)
    vd.coast(0.5)
    state = vd.get_state()
    first = [vd.update(z[k], 0.5 if k == 55 else 1.0) for k in range(55, 120)] + [vd.x, vd.P]
    other = VDFilter(FilterConfig())
    other.set_state(state)
    again = [other.update(z[k], 0.5 if k == 55 else 1.0) for k in range(55, 120)] + \
        [other.x, other.P]
    assert first == again


def test_jerk_noise_is_its_own_parameter() -> None:
    """The three-state model's process noise is the white-jerk Q of σj (``sigma_j``), not σa:
    changing σa leaves the VD filter bit-identical, changing σj changes its CA covariance by
    exactly q_cwnj(σj², T) (Bar-Shalom, Li & Kirubarajan 2001 eq. 6.2.3-8)."""
    _truth, z = maneuver(120, 3)
    ref = VDFilter(FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_a=2.0, sigma_j=2.0))
    other_a = VDFilter(FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_a=7.0, sigma_j=2.0))
    for zk in z:
        ref.update(zk, 1.0)
        other_a.update(zk, 1.0)
        assert ref.x == other_a.x and ref.P == other_a.P
    for sj in (2.0, 10.0):
        vd = VDFilter(FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_j=sj))
        ca = vd.ca
        ca.set(0.0, 0.0, 0.0, (0.0,) * 6)
        ca.predict_step(1.0, 1.0)
        assert ca.cov == pytest.approx(q_cwnj(sj * sj, 1.0), rel=1e-12)
