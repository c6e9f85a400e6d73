"""Shared test data of the seed-002 filter tests: a radial track with one maneuver."""

from __future__ import annotations

import numpy as np


def radial_maneuver(n: int, seed: int, noise: float = 100.0, T_lo: float = 1.0,
                    T_hi: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(T_k [s], true range [m], measured range [m]): 250 m/s from 1000 m (seed 002 §7), a
    30 m/s² maneuver between samples 40 and 70, intervals T_k uniform in [T_lo, T_hi], white
    Gaussian range noise of σ = ``noise`` [m]; seeded."""
    rng = np.random.default_rng(seed)
    Ts = rng.uniform(T_lo, T_hi, n)
    r, v = [1000.0], 250.0
    for k in range(1, n):
        a = 30.0 if 40 <= k < 70 else 0.0
        r.append(r[-1] + v * Ts[k] + 0.5 * a * Ts[k] ** 2)
        v += a * Ts[k]
    truth = np.array(r)
    return Ts, truth, truth + rng.normal(0.0, noise, n)
