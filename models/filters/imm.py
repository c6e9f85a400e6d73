"""Interacting multiple model (IMM) filter, CV/CA, on filterpy's ``IMMEstimator`` (comparison).

Beyond the seeds: the usual reference for maneuvering-target tracking (Blom & Bar-Shalom 1988;
Bar-Shalom, Li & Kirubarajan 2001, §11.6.6), here to compare the seed-002 filters with. Two
three-state models (position, velocity, acceleration) with H = [1 0 0]:

- CV: F = [[1, T, 0], [0, 1, 0], [0, 0, 0]] (the acceleration is forced to 0), process noise of
  the two-state model of seed 002 eq. (4) on (position, velocity) with σm (``cfg.sigma_m``);
- CA: F = [[1, T, T²/2], [0, 1, T], [0, 0, 1]], continuous white jerk of density σj²/(1 s)
  (``cfg.sigma_j``; :func:`axir.models.filters.kalman.q_cwnj`).

Mode switching: a Markov chain with mean sojourn times τ_CV, τ_CA (``cfg.imm_sojourn_cv``,
``cfg.imm_sojourn_ca``); over an interval T, p_ii = exp(−T/τ_i), p_ij = 1 − p_ii (so the matrix
is right for any update interval). Initial mode probabilities (1 − μ_CA, μ_CA) with
μ_CA = ``cfg.imm_mu_ca``. Initialisation: the two-point one (:mod:`axir.models.filters.base`) for
both models, acceleration 0 with σ = ``cfg.sigma_acc0``.

The filter runs through filterpy (numpy, ≈ 0.2 ms per update): it is for comparison runs at the
seed-002 rates (T = 1 s), not for the per-PRI hot path. ``maneuver``/``statistic`` come from the
same fading-memory detector as the other filters, on the IMM's combined innovation
z − H x̂(k|k−1) with variance H P(k|k−1) Hᵀ + r; ``mode_probability`` is μ_CA.
"""

from __future__ import annotations

import math

import numpy as np
from filterpy.kalman import IMMEstimator, KalmanFilter

from .base import TwoPointFilter, Vec3
from .kalman import q_cwna, q_cwnj


class IMMFilter(TwoPointFilter):
    """CV/CA IMM on filterpy (module docstring). ``imm`` is the filterpy estimator once the
    two-point initialisation is done (None before)."""

    kind = "imm"
    has_acceleration = True

    def _reset_state(self) -> None:
        self.imm: IMMEstimator | None = None
        self._first = (0.0, 0.0)  # (z, r) until the second measurement

    def _set_first(self, z: float, r: float) -> None:
        self._first = (z, r)

    def _set_initial(self, pos: float, vel: float, p11: float, p12: float, p22: float,
                     T: float, r: float, s: float) -> None:
        cfg = self.cfg
        filters = []
        sa0 = s * cfg.sigma_acc0
        for _ in range(2):
            kf = KalmanFilter(dim_x=3, dim_z=1)
            kf.x = np.array([[pos], [vel], [0.0]])
            kf.P = np.array([[p11, p12, 0.0], [p12, p22, 0.0], [0.0, 0.0, sa0 * sa0]])
            kf.H = np.array([[1.0, 0.0, 0.0]])
            kf.R = np.array([[r]])
            filters.append(kf)
        mu = np.array([1.0 - cfg.imm_mu_ca, cfg.imm_mu_ca])
        self.imm = IMMEstimator(filters, mu, self._transition(T))

    def _transition(self, T: float) -> np.ndarray:
        p_cv = math.exp(-T / self.cfg.imm_sojourn_cv)
        p_ca = math.exp(-T / self.cfg.imm_sojourn_ca)
        return np.array([[p_cv, 1.0 - p_cv], [1.0 - p_ca, p_ca]])

    def _set_models(self, T: float, s: float) -> None:
        cv, ca = self.imm.filters
        sm, sj = s * self.cfg.sigma_m, s * self.cfg.sigma_j
        q11, q12, q22 = q_cwna(sm * sm, T)  # seed 002 eq. (4)
        cv.F = np.array([[1.0, T, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
        cv.Q = np.array([[q11, q12, 0.0], [q12, q22, 0.0], [0.0, 0.0, 0.0]])
        c11, c12, c13, c22, c23, c33 = q_cwnj(sj * sj, T)
        ca.F = np.array([[1.0, T, 0.5 * T * T], [0.0, 1.0, T], [0.0, 0.0, 1.0]])
        ca.Q = np.array([[c11, c12, c13], [c12, c22, c23], [c13, c23, c33]])
        imm = self.imm
        imm.M = self._transition(T)
        imm._compute_mixing_probabilities()  # mixing weights for this interval's matrix

    def _predict(self, T: float, s: float) -> None:
        self._set_models(T, s)
        self.imm.predict()

    def _update(self, z: float, T: float, r: float, s: float) -> float:
        self._predict(T, s)
        imm = self.imm
        x_prior, p_prior = float(imm.x[0, 0]), float(imm.P[0, 0])
        for kf in imm.filters:
            kf.R = np.array([[r]])
        imm.update(np.array([[z]]))
        nu = z - x_prior
        S = p_prior + r
        self.fmd.innovation(nu * nu / S)
        self.fmd.decide()
        return nu

    def _coast(self, T: float, s: float) -> None:
        self._predict(T, s)

    # ------------------------------------------------------------------ outputs
    @property
    def mode_probability(self) -> float:
        """μ_CA, probability of the CA mode [1] (initial value before the IMM starts)."""
        return float(self.imm.mu[1]) if self.imm is not None else self.cfg.imm_mu_ca

    @property
    def x(self) -> Vec3:
        if self.imm is None:
            return self._first[0], 0.0, 0.0
        x = self.imm.x
        return float(x[0, 0]), float(x[1, 0]), float(x[2, 0])

    @property
    def P(self) -> Vec3:
        if self.imm is None:
            return self._first[1], 0.0, 0.0
        P = self.imm.P
        return float(P[0, 0]), float(P[0, 1]), float(P[1, 1])

    def predict(self, T: float) -> Vec3:
        p, v, a = self.x
        return p + T * v + 0.5 * T * T * a, v + T * a, a
