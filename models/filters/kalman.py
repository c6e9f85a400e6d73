"""Kalman filters of one measurement axis with plain-float algebra (no numpy, no inversion).

- :class:`KalmanCV`: the two-state (position, velocity) filter of seed 002 §2.1, eqs. (1)-(10),
  process noise eq. (4), two-point initialisation (see :mod:`axir.models.filters.base`), with the
  fading-memory detector of eqs. (11)-(15) on its innovations.
- :class:`KalmanCA`: a three-state (position, velocity, acceleration) filter, the "augmented"
  maneuver model of the VD filter (Bar-Shalom & Birmiwal 1982; seed 002 Fig. 2), with the
  continuous white-noise-jerk process noise (Bar-Shalom, Li & Kirubarajan 2001, §6.2.3).

The measurement is scalar (H = [1 0] / [1 0 0]), so the innovation variance S is a scalar and the
gain is a division; the symmetric covariance is kept as its upper triangle. One predict + update
costs ≈ 1 µs in CPython, ≈ 1/20 of filterpy's KalmanFilter (``benchmarks/bench_filters.py``).
"""

from __future__ import annotations

from .base import CVEstimate, FilterConfig, TwoPointFilter, Vec3


def q_cwna(q: float, T: float) -> tuple[float, float, float]:
    """(Q11, Q12, Q22) of the two-state model over T [s] for density q.

    # seed 002 eq. (4): Q(k) = σm² T [[T²/3, T/2], [T/2, 1]]   (q = σm²)
    """
    qt = q * T
    return qt * T * T / 3.0, qt * T / 2.0, qt


def q_cwnj(q: float, T: float) -> tuple[float, float, float, float, float, float]:
    """(Q11, Q12, Q13, Q22, Q23, Q33) of the continuous white-noise-jerk model over T [s]
    for density q: q·[[T⁵/20, T⁴/8, T³/6], [T⁴/8, T³/3, T²/2], [T³/6, T²/2, T]]
    (Bar-Shalom, Li & Kirubarajan 2001, eq. 6.2.3-8)."""
    t2 = T * T
    t3 = t2 * T
    return (q * t3 * t2 / 20.0, q * t2 * t2 / 8.0, q * t3 / 6.0, q * t3 / 3.0, q * t2 / 2.0,
            q * T)


class KalmanCV(CVEstimate, TwoPointFilter):
    """Two-state Kalman filter, seed 002 eqs. (1)-(10), with the FMD (eqs. 11-15).

    State: ``pos`` [unit], ``vel`` [unit/s], covariance ``p11, p12, p22``; after each update the
    gain ``k1, k2``, innovation ``nu`` (eq. 13) and its variance ``S`` (eq. 14).
    """

    kind = "kalman"

    def _reset_state(self) -> None:
        self.pos = self.vel = 0.0
        self.p11 = self.p12 = self.p22 = 0.0
        self.k1 = self.k2 = self.nu = 0.0
        self.S = self.r_default

    def _set_first(self, z: float, r: float) -> None:
        self.pos, self.vel = z, 0.0
        self.p11, self.p12, self.p22 = r, 0.0, 0.0

    def _set_initial(self, pos: float, vel: float, p11: float, p12: float, p22: float,
                     T: float, r: float, s: float) -> None:
        self.pos, self.vel = pos, vel
        self.p11, self.p12, self.p22 = p11, p12, p22

    # -------------------------------------------------------------- equations
    def _predict(self, T: float, s: float) -> None:
        """State and covariance prediction in place."""
        sm = s * self.cfg.sigma_m
        q11, q12, q22 = q_cwna(sm * sm, T)  # eq. (4)
        self.pos += T * self.vel  # eq. (6): X(k/k−1) = Φ X(k−1/k−1)
        p12, p22 = self.p12, self.p22
        a = p12 + T * p22
        # eq. (7): P(k/k−1) = Φ P Φᵀ + Q
        self.p11 += T * (p12 + a) + q11
        self.p12 = a + q12
        self.p22 = p22 + q22

    def _correct(self, z: float, r: float) -> None:
        """Measurement update in place (after :meth:`_predict`)."""
        p11, p12 = self.p11, self.p12
        S = p11 + r  # eqs. (8), (14): N = H P(k/k−1) Hᵀ + σr²
        k1 = p11 / S  # eq. (8): K = P(k/k−1) Hᵀ N⁻¹
        k2 = p12 / S
        nu = z - self.pos  # eq. (13): R(k) = Y(k) − H X(k/k−1)
        self.pos += k1 * nu  # eq. (9)
        self.vel += k2 * nu
        self.p22 -= k2 * p12  # eq. (10): P(k/k) = (I − K H) P(k/k−1)
        self.p12 = (1.0 - k1) * p12
        self.p11 = (1.0 - k1) * p11
        self.k1, self.k2, self.nu, self.S = k1, k2, nu, S

    def _step(self, z: float, T: float, r: float, s: float) -> float:
        """Predict + correct + L(k) (no maneuver decision); returns the innovation."""
        self._predict(T, s)
        self._correct(z, r)
        nu = self.nu
        self.fmd.innovation(nu * nu / self.S)  # eqs. (11)-(12): d = R² / N
        return nu

    # -------------------------------------------------------------- interface
    def _update(self, z: float, T: float, r: float, s: float) -> float:
        nu = self._step(z, T, r, s)
        self.fmd.decide()
        return nu

    def _coast(self, T: float, s: float) -> None:
        self._predict(T, s)



class KalmanCA:
    """Three-state Kalman filter (position, velocity, acceleration), scalar measurement.

    Not an :class:`AxisFilter` on its own: the VD filter drives it (initialisation from its
    window). F = [[1, T, T²/2], [0, 1, T], [0, 0, 1]], H = [1 0 0], Q = continuous white jerk of
    density (s·σj)²/(1 s) (:func:`q_cwnj`; ``cfg.sigma_j``).
    """

    def __init__(self, cfg: FilterConfig) -> None:
        self.cfg = cfg
        self.set(0.0, 0.0, 0.0, (0.0,) * 6)

    def set(self, pos: float, vel: float, acc: float,
            P: tuple[float, float, float, float, float, float]) -> None:
        """Set the state and covariance (P11, P12, P13, P22, P23, P33)."""
        self.pos, self.vel, self.acc = pos, vel, acc
        self.p11, self.p12, self.p13, self.p22, self.p23, self.p33 = P
        self.nu = 0.0
        self.S = 0.0

    @property
    def cov(self) -> tuple[float, float, float, float, float, float]:
        return self.p11, self.p12, self.p13, self.p22, self.p23, self.p33

    def predict_step(self, T: float, s: float) -> None:
        """x = F x, P = F P Fᵀ + Q in place."""
        h = 0.5 * T * T
        sj = s * self.cfg.sigma_j  # white-jerk density σj²/(1 s) (cfg.sigma_j)
        q11, q12, q13, q22, q23, q33 = q_cwnj(sj * sj, T)
        acc = self.acc
        self.pos += T * self.vel + h * acc
        self.vel += T * acc
        p11, p12, p13, p22, p23, p33 = self.cov
        # A = F P
        a11 = p11 + T * p12 + h * p13
        a12 = p12 + T * p22 + h * p23
        a13 = p13 + T * p23 + h * p33
        a22 = p22 + T * p23
        a23 = p23 + T * p33
        # F P Fᵀ + Q (upper triangle)
        self.p11 = a11 + T * a12 + h * a13 + q11
        self.p12 = a12 + T * a13 + q12
        self.p13 = a13 + q13
        self.p22 = a22 + T * a23 + q22
        self.p23 = a23 + q23
        self.p33 = p33 + q33

    def correct(self, z: float, r: float) -> float:
        """Measurement update in place; returns the innovation."""
        n11, n12, n13 = self.p11, self.p12, self.p13
        S = n11 + r
        k1, k2, k3 = n11 / S, n12 / S, n13 / S
        nu = z - self.pos
        self.pos += k1 * nu
        self.vel += k2 * nu
        self.acc += k3 * nu
        # P = (I − K H) P
        self.p22 -= k2 * n12
        self.p23 -= k2 * n13
        self.p33 -= k3 * n13
        self.p11 = n11 - k1 * n11
        self.p12 = n12 - k1 * n12
        self.p13 = n13 - k1 * n13
        self.nu, self.S = nu, S
        return nu

    def extrapolate(self, T: float) -> Vec3:
        """(pos, vel, acc) T [s] ahead, state unchanged."""
        return (self.pos + T * self.vel + 0.5 * T * T * self.acc, self.vel + T * self.acc,
                self.acc)
