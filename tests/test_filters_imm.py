"""CV/CA IMM on filterpy's IMMEstimator (comparison filter, beyond the seeds)."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from axir.models.filters.base import FilterConfig
from axir.models.filters.imm import IMMFilter
from axir.models.filters.kalman import KalmanCV


def maneuver(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    r, v = [1000.0], 250.0
    for k in range(1, n):
        a = 30.0 if 40 <= k < 70 else 0.0
        r.append(r[-1] + v + 0.5 * a)
        v += a
    truth = np.array(r)
    return truth, truth + rng.normal(0.0, 100.0, n)


def test_transition_matrix_from_sojourn_times() -> None:
    f = IMMFilter(FilterConfig(imm_sojourn_cv=20.0, imm_sojourn_ca=5.0))
    M = f._transition(2.0)
    assert M[0, 0] == pytest.approx(math.exp(-0.1)) and M[1, 1] == pytest.approx(math.exp(-0.4))
    assert np.allclose(M.sum(axis=1), 1.0)
    # two steps of T equal one step of 2T for the diagonal "stay" probability
    assert f._transition(1.0)[0, 0] ** 2 == pytest.approx(M[0, 0])


def test_reduces_to_the_cv_kalman_when_ca_is_never_entered() -> None:
    """μ_CA → 0 and τ_CV → ∞: the IMM is the two-state Kalman filter of seed 002."""
    _, z = maneuver(60, 2)
    cfg = FilterConfig(sigma_m=5.0, sigma_meas=100.0, imm_mu_ca=1e-15, imm_sojourn_cv=1e15)
    imm, kf = IMMFilter(cfg), KalmanCV(cfg)
    for k in range(35):  # before the maneuver: the CA likelihood stays comparable
        imm.update(z[k], 1.0)
        kf.update(z[k], 1.0)
        for a, b in zip(imm.x[:2] + imm.P, kf.x[:2] + kf.P, strict=True):
            assert a == pytest.approx(b, rel=1e-9, abs=1e-9)
        assert imm.x[2] == pytest.approx(0.0, abs=1e-9)


def test_mode_probability_follows_the_maneuver() -> None:
    truth, z = maneuver(140, 3)
    f = IMMFilter(FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_j=2.0))
    mu, err = [], []
    for k in range(len(z)):
        f.update(z[k], 1.0)
        mu.append(f.mode_probability)
        err.append(f.x[0] - truth[k])
    before, during, after = np.mean(mu[5:35]), np.mean(mu[50:70]), np.mean(mu[110:])
    assert before < 0.3 and after < 0.3  # stationary μ_CA of the chain: τ_CA/(τ_CV + τ_CA) = 0.2
    assert during > 0.5 and during > 2.5 * before
    assert abs(np.mean(err[50:70])) < 150.0
    assert np.all(np.isfinite(err))


def test_coast_state_round_trip_and_pickle() -> None:
    _, z = maneuver(80, 4)
    f = IMMFilter(FilterConfig())
    assert f.x == (0.0, 0.0, 0.0)
    for k in range(40):
        f.update(z[k], 1.0)
    f.coast(0.5)
    state = f.get_state()
    blob = pickle.dumps(state)
    first = [f.update(z[k], 1.0) for k in range(40, 80)] + [f.x, f.P, f.mode_probability]
    for restored in (state, pickle.loads(blob)):
        g = IMMFilter(FilterConfig())
        g.set_state(restored)
        again = [g.update(z[k], 1.0) for k in range(40, 80)] + [g.x, g.P, g.mode_probability]
        assert first == again
