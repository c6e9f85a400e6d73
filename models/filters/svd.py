"""Simplified variable dimension (SVD) filter of seed 002, full and reduced forms.

The SVD filter (seed 002 §2, Fig. 1) runs the two-state Kalman filter of eqs. (1)-(10) without
ever changing it, a fading-memory detector on its innovations (eqs. 11-15) and, in parallel, a
scalar Kalman filter of the target acceleration u driven by the two-state filter's innovations
through the sensitivity vectors U, V (eqs. 16-27): an input-estimation / two-stage estimator
(Friedland 1969; Blair 1993 = seed 002 ref. [6]). While a maneuver is declared the output is
the compensated state X_n = X + V û (eq. 28) with P_n = P + V P_u Vᵀ (eq. 29); otherwise the
two-state output X, P (the FMD switch U12 of Fig. 1 / Table 9).

- :class:`SVDFilter` — full form, eqs. (16)-(29), on :class:`~axir.models.filters.kalman.KalmanCV`.
  The measurement model (20) carries C = T²/2 (``cfg.svd_c = "paper"``, as printed) or C = 0
  (``"zero"``).
- :class:`SVDReducedFilter` — the reduced scalar form the paper implements in hardware,
  eqs. (30)-(39): the two-state filter in three equations (30)-(32), C removed from (25), the
  −K·C term removed from (27), eq. (29) not computed. Every register assignment passes through
  an optional quantiser hook (``cfg.quant``): this one implementation is also the fixed-point
  emulation (:mod:`axir.models.filters.fixedpoint`, seed 002 Table 3).

Equivalence (tests/test_svd.py, docs/filters.md): the reduced form is the full form with C = 0,
term by term, so the two agree to rounding (≈ 1e-12 relative) when ``svd_c = "zero"``. With
C = T²/2 they are different models: the full form's position state then lags the target by C·u
(its compensated position is biased by −C·û during a maneuver), and the estimates differ by
that order. With Q_u = 0 the full form is exactly the augmented three-state Kalman filter
[r, v, u] (Friedland's decomposition; tested against filterpy).

Reconstructions of the printed text (docs/filters.md):
- eqs. (30), (33), (35): the denominators "P11 + S_r" are read as the predicted P11(k/k−1) plus
  σr², as in eqs. (8), (14), (23) (P11 is m², S_r would be m; and only the predicted P11 gives the
  Kalman gain of eq. 8 — Table 6, U35, builds K from h1 = predicted P11).
- eq. (22): "P_u + G Q_u Gᵀ" with the two-state G of eq. (1) would not be a scalar; read with the
  G_u = 1 of eq. (18): P_u(k/k−1) = P_u(k−1/k−1) + Q_u, as eq. (36) prints it.
- eq. (35) uses the predicted P_u(k/k−1) (eq. 23).
- eq. (39) writes the compensated state with the names X1, X2 of the two-state filter; it is the
  output X_n of eq. (28) and is not written back (the text: the acceleration filter runs "without
  modifying the operation of the first Kalman filter"; writing it back would count V·û twice).
- order within a step: U (37) → K_u (35) → u (34) → P_u (36) → V (38) → X_n (39); eq. (34)
  needs U1(k) and K_u(k).
"""

from __future__ import annotations

import math

from .base import AxisFilter, TwoPointFilter, Vec3
from .fmd import Quantiser
from .kalman import KalmanCV, q_cwna


def _noq(name: str, value: float) -> float:
    """Identity hook (floating point)."""
    return value


class SVDFilter(AxisFilter):
    """SVD filter, full form (seed 002 eqs. 16-29) on a :class:`KalmanCV`.

    State: the two-state filter ``base`` (eqs. 1-15, its detector is this filter's detector),
    the acceleration estimate ``u`` [unit/s²] and variance ``pu``, the sensitivities ``U1, U2``
    (eq. 26) and ``V1, V2`` (eq. 27). U = V = 0, û = 0 and P_u = ``cfg.pu0`` at the two-point
    initialisation (seed 002 §2.3).
    """

    kind = "svd"
    has_acceleration = True

    def reset(self) -> None:
        self.base = KalmanCV(self.cfg)
        self.fmd = self.base.fmd
        self._reset_acc(1.0)

    def _reset_acc(self, s: float) -> None:
        # seed 002 §2.3: û(0/0) = 0, P_u(0/0) = [0.1]; U, V initially zero
        self.u = 0.0
        self.pu = self.cfg.pu0 * s * s
        self.U1 = self.U2 = self.V1 = self.V2 = 0.0
        self.ku = 0.0

    @property
    def n(self) -> int:
        return self.base.n

    def update(self, z: float, T: float, r: float | None = None, s: float = 1.0) -> float:
        b = self.base
        if b.n < 2:
            nu = b.update(z, T, r, s)
            if b.n == 2:
                self._reset_acc(s)
            return nu
        r = b.r_default if r is None else r
        nu = b._step(z, T, r, s)  # eqs. (6)-(14) and L(k)
        b.n += 1
        self._acc_step(T, s, b.k1, b.k2, nu, b.S)
        u, pu = self.u, self.pu
        self.fmd.acceleration(u * u / pu if pu > 0.0 else 0.0)
        self.fmd.decide()
        return nu

    def _acc_step(self, T: float, s: float, k1: float, k2: float, res: float,
                  n_var: float) -> None:
        """Acceleration filter and sensitivities, eqs. (21)-(27) (k1 = k2 = 0: no update)."""
        c = 0.5 * T * T if self.cfg.svd_c == "paper" else 0.0  # eq. (20): C = T²/2
        # eq. (26): U(k) = Φ V(k−1) + B, B = [T²/2, T]ᵀ (eq. 17)
        u1 = self.V1 + T * self.V2 + 0.5 * T * T
        u2 = self.V2 + T
        sens = u1 + c  # eq. (25): S(k) = H U(k) + C
        sa = s * self.cfg.sigma_a
        pu = self.pu + sa * sa * T  # eq. (22): P_u(k/k−1) = P_u + Q_u, Q_u = σa²·T/(1 s)
        if k1 == 0.0 and k2 == 0.0:  # coast: no measurement, no acceleration update
            ku = 0.0
        else:
            ku = pu * sens / (sens * pu * sens + n_var)  # eq. (23)
            self.u += ku * (res - sens * self.u)  # eq. (21), û(k/k−1) = û(k−1/k−1) (eq. 18)
            pu = (1.0 - ku * sens) * pu  # eq. (24)
        self.pu, self.ku = pu, ku
        self.U1, self.U2 = u1, u2
        # eq. (27): V(k) = [I − K(k)H] U(k) − K(k) C
        self.V1 = (1.0 - k1) * u1 - k1 * c
        self.V2 = u2 - k2 * u1 - k2 * c

    def coast(self, T: float, s: float = 1.0) -> None:
        b = self.base
        if b.n >= 2:
            b._coast(T, s)
            self._acc_step(T, s, 0.0, 0.0, 0.0, 0.0)
        else:
            b.coast(T, s)

    # ------------------------------------------------------------------ outputs
    @property
    def x(self) -> Vec3:
        b = self.base
        if self.fmd.flag:  # eq. (28): X_n = X + V û
            u = self.u
            return b.pos + self.V1 * u, b.vel + self.V2 * u, u
        return b.pos, b.vel, 0.0

    @property
    def P(self) -> Vec3:
        b = self.base
        if self.fmd.flag:  # eq. (29): P_n = P + V P_u Vᵀ
            pu, v1, v2 = self.pu, self.V1, self.V2
            return b.p11 + v1 * v1 * pu, b.p12 + v1 * v2 * pu, b.p22 + v2 * v2 * pu
        return b.p11, b.p12, b.p22

    def predict(self, T: float) -> Vec3:
        p, v, a = self.x
        return p + T * v + 0.5 * T * T * a, v + T * a, a


class SVDReducedFilter(TwoPointFilter):
    """SVD filter, reduced form (seed 002 eqs. 30-39), with the quantiser hook.

    Registers (the paper's names): ``X1, X2`` (two-state estimate), ``P11, P12, P21, P22``,
    ``K1, K2``, ``u``, ``Pu``, ``Ku``, ``U1, U2``, ``V1, V2``; the FMD's ``L`` (eq. 33).
    Each assignment is ``Q(name, value)`` with ``Q`` the identity in floating point or the
    Table 3 quantiser (:class:`axir.models.filters.fixedpoint.TableQuantiser`) when ``cfg.quant`` is
    set. Output covariance: P (eq. 29 is not computed in the reduced form).
    """

    kind = "svd_reduced"
    has_acceleration = True

    @property
    def quant(self) -> Quantiser | None:
        return self.cfg.quant

    def _reset_state(self) -> None:
        self.X1 = self.X2 = 0.0
        self.P11 = self.P12 = self.P21 = self.P22 = 0.0
        self.K1 = self.K2 = 0.0
        self.nu = 0.0
        self._reset_acc(1.0)

    def _reset_acc(self, s: float) -> None:
        Q = self.quant or _noq
        self.u = 0.0  # seed 002 §2.3: û(0/0) = 0
        self.Pu = Q("Pu", self.cfg.pu0 * s * s)  # P_u(0/0) = 0.1
        self.Ku = 0.0
        self.U1 = self.U2 = self.V1 = self.V2 = 0.0  # U, V initially zero

    def _set_first(self, z: float, r: float) -> None:
        Q = self.quant or _noq
        self.X1, self.X2 = Q("X1", z), 0.0  # Table 8 U021: r(0/0) = y(0)
        self.P11, self.P12, self.P21, self.P22 = Q("h", r), 0.0, 0.0, 0.0

    def _set_initial(self, pos: float, vel: float, p11: float, p12: float, p22: float,
                     T: float, r: float, s: float) -> None:
        Q = self.quant or _noq
        # Table 8 U021-U023: r, v and P(0/0) = σr²[[1, 1], [1, 2]] (T = 1); P(0/0) comes from
        # the U02 multiplexers into the first prediction, not from a 12-bit P register (its
        # 2σr² = 2·10⁴ would saturate the 0…10⁴ P bus): predicted-covariance ("h") format
        self.X1, self.X2 = Q("X1", pos), Q("X2", vel)
        self.P11, self.P12, self.P21, self.P22 = Q("h", p11), Q("h", p12), Q("h", p12), \
            Q("h", p22)
        self._reset_acc(s)

    # ------------------------------------------------------------------ equations
    def _step(self, y: float, T: float, r: float, s: float, meas: bool) -> float:
        """One step of eqs. (30)-(38); ``meas`` False = coast (K1 = K2 = K_u = 0)."""
        q = self.quant
        Q = q or _noq
        sm = s * self.cfg.sigma_m
        sa = s * self.cfg.sigma_a
        if q is not None:  # 8-bit constant registers (Table 3, Table 7) and the input bus
            r = q("s_r", math.sqrt(r)) ** 2
            sm = q("s_m", sm)
            y = q("X1", y)
        g1, g2, g4 = q_cwna(sm * sm, T)  # q·q11, q·q12 = q·q21, q·q22 (eq. 4, Table 6 U32)
        g1, g2, g4 = Q("P", g1), Q("P", g2), Q("P", g4)
        P11, P12, P21, P22 = self.P11, self.P12, self.P21, self.P22
        # eq. (30) (Table 6 U31-U35): h1 = predicted P11, h2 = predicted P12, f = predicted P21
        # (adder outputs; "h" format = the N bus, whose range holds h1 + σr²)
        h1 = Q("h", g1 + (P11 + T * P21 + T * (P12 + T * P22)))
        h2 = Q("h", g2 + (P12 + T * P22))
        f = Q("h", g2 + (P21 + T * P22))
        n_var = Q("N", h1 + r)  # N = P11(k/k−1) + σr² (eq. 14; "P11 + S_r" reconstructed)
        if meas:
            K1, K2 = Q("K", h1 / n_var), Q("K", f / n_var)  # eq. (30)
        else:
            K1 = K2 = 0.0
        # eq. (31) (Table 6 U34, U36): m1 = X1 + T·X2, R = Y − m1
        m1 = Q("X1", self.X1 + T * self.X2)
        res = Q("R", y - m1) if meas else 0.0
        self.X1 = Q("X1", m1 + K1 * res)
        self.X2 = Q("X2", self.X2 + K2 * res)
        # eq. (32) (Table 6 U37)
        self.P11 = Q("P", (1.0 - K1) * h1)
        self.P12 = Q("P", (1.0 - K1) * h2)
        self.P21 = Q("P", -K2 * h1 + f)
        self.P22 = Q("P", -K2 * h2 + (g4 + P22))
        self.K1, self.K2 = K1, K2
        if meas:
            # eq. (33) (Table 4): L = a_f·L + R·R/N
            self.fmd.innovation(Q("d", res * res / n_var))
        # eq. (37): U1 = V1 + T·V2 + T²/2, U2 = V2 + T
        U1 = Q("U1", self.V1 + T * self.V2 + 0.5 * T * T)
        U2 = Q("U2", self.V2 + T)
        pu = Q("Pu", self.Pu + Q("Pu", sa * sa * T))  # P_u + Q_u (eqs. 22, 36)
        if meas:
            Ku = Q("Ku", pu * U1 / (U1 * pu * U1 + n_var))  # eq. (35)
            self.u = Q("u", self.u + Ku * (res - U1 * self.u))  # eq. (34)
        else:
            Ku = 0.0
        self.Pu = Q("Pu", (1.0 - Ku * U1) * pu)  # eq. (36)
        self.Ku, self.U1, self.U2 = Ku, U1, U2
        # eq. (38): V1 = (1 − K1)·U1, V2 = −K2·U1 + U2
        self.V1 = Q("V1", (1.0 - K1) * U1)
        self.V2 = Q("V2", -K2 * U1 + U2)
        self.nu = res
        return res

    def _update(self, z: float, T: float, r: float, s: float) -> float:
        res = self._step(z, T, r, s, True)
        u, pu = self.u, self.Pu
        self.fmd.acceleration(u * u / pu if pu > 0.0 else 0.0)
        self.fmd.decide()
        return res

    def _coast(self, T: float, s: float) -> None:
        self._step(0.0, T, self.r_default, s, False)

    # ------------------------------------------------------------------ outputs
    @property
    def x(self) -> Vec3:
        if self.fmd.flag:  # eq. (39) = eq. (28): X_n = X + V·u (output only)
            Q = self.quant or _noq
            u = self.u
            return Q("X1", self.X1 + self.V1 * u), Q("X2", self.X2 + self.V2 * u), u
        return self.X1, self.X2, 0.0

    @property
    def P(self) -> Vec3:
        return self.P11, self.P12, self.P22

    def predict(self, T: float) -> Vec3:
        p, v, a = self.x
        return p + T * v + 0.5 * T * T * a, v + T * a, a
