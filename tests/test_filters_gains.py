"""α-β gain laws: evolutive gains = least squares, Kalata steady gains, VRR."""

from __future__ import annotations

import math

import numpy as np
import pytest
from filterpy.common import Q_discrete_white_noise
from filterpy.gh import least_squares_parameters
from filterpy.kalman import KalmanFilter
from scipy.linalg import solve_discrete_lyapunov

from axir.models.filters.gains import (
    evolutive_gains,
    kalata_gains,
    prediction_vrr,
    prior_gains,
    prior_q,
    scheduled_gains,
    stable_gains,
    tracking_index,
)


def _schedule_reference(n: int, n_max: int, a_ss: float, b_ss: float
                        ) -> tuple[float, float, bool]:
    """scheduled_gains as documented, from the two gain laws it combines (the definition the
    written-out function must equal bit for bit)."""
    capped = 0 < n_max < n
    a, b = evolutive_gains(n_max if capped else n)
    evolutive = not capped
    if a_ss > 0.0 and stable_gains(a_ss, b_ss):
        if a_ss >= a:
            a, evolutive = a_ss, False
        if b_ss >= b:
            b, evolutive = b_ss, False
    return a, b, evolutive


def test_scheduled_gains_equal_the_composition_of_the_gain_laws() -> None:
    """Evolutive, mixed (α steady, β evolutive), steady, capped and unstable/NaN/inf steady
    gains: the same floats and flag as evolutive_gains + stable_gains, and n < 1 refused."""
    rng = np.random.default_rng(7)
    specials = [0.0, -0.1, 1.0, 1.5, 2.0, 3.0, math.nan, math.inf, -math.inf, 1e-300]
    steady = [kalata_gains(lam) for lam in (1e-4, 0.01, 0.05, 0.3, 2.0, 50.0)]
    steady += [(a, b) for a in specials for b in specials]
    steady += [tuple(rng.uniform(-0.5, 2.5, 2)) for _ in range(300)]
    for a_ss, b_ss in steady:
        for n in (1, 2, 3, 5, 14, 40, 1000, 123457):
            for n_max in (0, -3, 1, 4, 14, 2000):
                got = scheduled_gains(n, n_max, a_ss, b_ss)
                want = _schedule_reference(n, n_max, a_ss, b_ss)
                assert got == want and type(got[2]) is bool, (n, n_max, a_ss, b_ss)
                assert [math.copysign(1.0, v) for v in got[:2]] == [
                    math.copysign(1.0, v) for v in want[:2]]
    with pytest.raises(ValueError, match="n = 0"):
        scheduled_gains(0, 0, 0.3, 0.05)


def _batch_gains(n: int, q: float) -> tuple[float, float]:
    """(α, β) of the newest of n samples from the batch posterior (numpy linear algebra, not
    the closed form): samples a T = 1 apart of variance 1, ages k = 0 … n − 1 measuring
    pos − k·vel, a flat position prior and a velocity prior of variance 1/q."""
    h = np.array([[1.0, -float(k)] for k in range(n)])
    info = h.T @ h + np.diag([0.0, q])
    gain = np.linalg.solve(info, h[0])
    return float(gain[0]), float(gain[1])


@pytest.mark.parametrize("q", [1e-3, 0.5, 10.0, 3.0e3, 2.4e5])
def test_prior_gains_are_the_batch_posterior_gains(q: float) -> None:
    """issue 11 (session 17): the closed form equals the batch least squares with a velocity
    prior; the first sample sets the position only; the gains approach the seed's as the
    samples outweigh the prior."""
    for n in (1, 2, 3, 7, 10, 64, 200, 5000):
        a, b = prior_gains(n, q)
        ra, rb = _batch_gains(n, q)
        assert a == pytest.approx(ra, rel=1e-9, abs=1e-15), n
        assert b == pytest.approx(rb, rel=1e-9, abs=1e-15), n
    assert prior_gains(1, q) == (1.0, 0.0)
    ea, eb = evolutive_gains(100_000)
    a, b = prior_gains(100_000, q)
    assert a == pytest.approx(ea, rel=1e-4) and b == pytest.approx(eb, rel=1e-4)


def test_prior_gains_without_prior_are_the_seed_gains() -> None:
    for n in range(1, 200):
        a, b = prior_gains(n, 0.0)
        ea, eb = evolutive_gains(n)
        assert a == pytest.approx(ea, rel=1e-12) and b == pytest.approx(eb, rel=1e-12)
    # the schedule with a prior: the seed's position gain, the prior's velocity gain
    assert scheduled_gains(7, 0, 0.0, 0.0, 50.0) == (evolutive_gains(7)[0],
                                                     prior_gains(7, 50.0)[1], True)
    for n in range(2, 300):  # the prior's velocity gain never exceeds the seed's
        assert prior_gains(n, 50.0)[1] < evolutive_gains(n)[1]
    assert scheduled_gains(7, 0, 0.0, 0.0, 0.0) == scheduled_gains(7, 0, 0.0, 0.0)


def test_prior_at_a_zero_interval_averages_the_position() -> None:
    """T = 0: q = inf, the samples (all at one time) carry no velocity: α = 1/n, β = 0; with no
    prior (k = 0) q stays 0 whatever T."""
    assert prior_q(0.0, 0.0) == 0.0 and prior_q(0.0, 1e-4) == 0.0
    assert prior_q(2.0, 0.0) == math.inf and prior_q(2.0, 0.5) == 8.0
    for n in (1, 2, 5, 40):
        assert prior_gains(n, math.inf) == (1.0 / n, 0.0)
        a, b = prior_gains(n, 1e30)
        assert a == pytest.approx(1.0 / n) and b == pytest.approx(0.0, abs=1e-25)


def test_evolutive_gains_match_filterpy_least_squares() -> None:
    for n in range(1, 60):
        assert evolutive_gains(n) == pytest.approx(least_squares_parameters(n - 1), rel=1e-15)
    with pytest.raises(ValueError):
        evolutive_gains(0)


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
