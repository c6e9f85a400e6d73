"""α-β (g-h) filter of the AXIR digital tracker, one axis, evolutive and steady gains.

Sources
-------
- seed 000 "Alpha-Beta Filters": one α-β filter per Cartesian axis (X, Y, Z), DSP form
  ("Beginning period": P = V3 + V5, V1 = In − P, V2 = Alpha·V1, V4 = Beta·V1, OutP = P + V2,
  OutV = V4 + V5, V3 = OutP, V5 = OutV), with the update rules
  Xp(k+1) = X(k) + T·V(k), X(k+1) = Xp + α (z − Xp), V(k+1) = V(k) + (β/T)(z − Xp).
  In the DSP listing V5 is the velocity expressed per period; here it is in m/s, so the
  prediction is written P = V3 + V5·T with T = dt (the actual step), and the velocity
  correction divides the error by T as the seed says ("we have just to divide the error by the
  sampling period"). β is therefore dimensionless, as in the seed and in Kalata's papers.
- Gain laws (seed 000 evolutive gains, Kalata 1984 steady gains, Brookner 1998 VRR):
  :mod:`.gains`.

The Tracker runs one :class:`AlphaBetaAxis` per Cartesian axis (its default, the seed-000
tracker); its 3-D maneuver test is :mod:`axir.models.tracker.maneuver`.

Implementation note: each axis is plain Python floats, not numpy arrays; measured on this
project's machine one 3-axis update costs ≈ 0.7 µs with floats vs ≈ 4.4 µs with numpy (3 is
far too small for vectorisation to pay off).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .base import CVEstimate, FilterConfig
from .gains import (
    innovation_factor,
    kalata_gains,
    prior_q,
    scheduled_gains,
    stable_gains,
    tracking_index,
)
from .kalman import q_cwna


class AlphaBetaAxis(CVEstimate):
    """One α-β axis (seed 000, DSP form: :func:`update_axes`) behind the common
    :class:`~axir.models.filters.base.AxisFilter` interface.

    State: position ``pos`` [unit], velocity ``vel`` [unit/s], number of measurements used
    ``n`` (0 = not initialised), gains of the last update ``alpha``, ``beta``, ``evolutive``.
    At initialisation (n = 1) the position is the measurement and the velocity 0.

    Gain schedule (:func:`~axir.models.filters.gains.scheduled_gains`): the n-th measurement
    uses the evolutive gains α(n), β(n) (seed 000) while they exceed the steady gains, each gain
    separately: α = max(α(n), α_ss), β = max(β(n), β_ss). α(n), β(n) decrease monotonically, so
    once a steady gain is reached it takes over for good (unless it is raised again). A steady
    gain of 0 (or an unstable pair) means "not supplied": evolutive gains only (growing-memory
    least squares). ``cfg.n_max`` > 0 caps the evolutive index (α(n) ≥ α(n_max)), 0 = no cap.
    With uniform T the evolutive phase reproduces the least-squares line fit of all
    measurements exactly (position and slope at the last sample), whatever the initial state,
    because α(1) = α(2) = 1 and β(2) = 1. With ``cfg.vel_prior_k`` > 0 the evolutive velocity
    gain is that of the same fit with a prior of variance r/vel_prior_k on the initial velocity
    (:func:`~.gains.prior_gains`, q = vel_prior_k/T²; the position gain stays α(n); issue 11,
    session 17).

    Steady gains come from the radar manager (:meth:`set_steady_gains`) or, with
    ``cfg.auto_gains`` and none supplied, from Kalata's steady state for the tracking index
    Λ = (s·σm) T²/√r (a piecewise-constant-acceleration model, Kalata 1984; # assumption: σm of
    seed 002 eq. 4 used as Kalata's σ_w).

    Covariance ``P``: the error covariance of this fixed-gain filter for a target following the
    two-state model of seed 002 eq. (4) with σm, measured with variance r: P(k|k) =
    (I − KH)(ΦPΦᵀ + Q)(I − KH)ᵀ + K r Kᵀ, K = [α, β/T]ᵀ (Joseph form: valid for any gain). In
    the evolutive phase with σm = 0 it is the least-squares line-fit covariance
    (P_pp = α(n)·r). Detector: d = ν²/S with S = P_pp(k|k−1) + r.
    """

    kind = "alphabeta"

    def __init__(self, cfg: FilterConfig | None = None) -> None:
        super().__init__(cfg)
        #: run the per-axis detector (the Tracker's seed-000 configuration uses its 3-D
        #: detector instead and turns this off)
        self.detect = True

    def reset(self) -> None:
        self.n = 0
        self.pos = self.vel = 0.0
        self.p11 = self.p12 = self.p22 = 0.0
        self.alpha, self.beta, self.evolutive = 1.0, 0.0, True
        self.alpha_ss = self.beta_ss = 0.0
        self._steady: tuple[float, float] | None = None  # steady gains in use (fast path)
        self.fmd.reset()

    def set_steady_gains(self, alpha: float, beta: float) -> None:
        self.alpha_ss, self.beta_ss = alpha, beta

    def innovation_factor(self) -> float:
        """S/σ² of the last update from the gains alone (:func:`innovation_factor`) [1]."""
        return innovation_factor(self.alpha, self.beta, self.evolutive)

    def _predict_cov(self, T: float, s: float) -> tuple[float, float, float]:
        """ΦPΦᵀ + Q over T [s] (seed 002 eqs. 4, 7)."""
        sm = s * self.cfg.sigma_m
        return predict_cov(self.p11, self.p12, self.p22, T, *q_cwna(sm * sm, T))  # eq. (4)

    def update(self, z: float, T: float, r: float | None = None, s: float = 1.0) -> float:
        return _update_loop((self,), (z,), T, (self.r_default if r is None else r,), s,
                            None)[0]

    def coast(self, T: float, s: float = 1.0) -> None:
        if self.n > 0:
            self.pos += self.vel * T
            self.p11, self.p12, self.p22 = self._predict_cov(T, s)


def predict_cov(p11: float, p12: float, p22: float, T: float, q11: float, q12: float,
                q22: float) -> tuple[float, float, float]:
    """ΦPΦᵀ + Q of the two-state model over T [s]: P = (p11, p12, p22), Q = (q11, q12, q22)
    (seed 002 eqs. 4, 7; Φ = [[1, T], [0, 1]])."""
    a = p12 + T * p22
    return p11 + T * (p12 + a) + q11, a + q12, p22 + q22


#: (σm·s, T, Q11, Q12, Q22) of the last Q that :func:`update_axes` computed: Q is a pure
#: function of σm·s and T (seed 002 eq. 4), so a PRI with the same inputs reuses it (NaN never
#: compares equal: the first call computes it)
_q_last: tuple[float, float, float, float, float] = (math.nan, math.nan, 0.0, 0.0, 0.0)


def steady_all(st: tuple[float, float] | None, st_y: tuple[float, float] | None,
               st_z: tuple[float, float] | None, a_ss: float, b_ss: float) -> bool:
    """Whether the steady-gain tuples ``st``, ``st_y``, ``st_z`` of three axes all equal the
    manager's steady gains ``a_ss``, ``b_ss`` (dimensionless): then every axis takes those
    gains, whatever its evolutive history, and the three-axis case of :func:`update_xyz` is
    the arithmetic of its per-axis loop. With per-axis velocity priors
    (``FilterConfig.vel_prior_r``) the axes reach their steady gains at different PRIs, each
    with its own tuple, so the case is entered by value here, not by the tuple's identity
    (issue 14, session 28)."""
    return st is not None and st == (a_ss, b_ss) and st_y == st and st_z == st


def update_xyz(fx: AlphaBetaAxis, fy: AlphaBetaAxis, fz: AlphaBetaAxis, zx: float, zy: float,
               zz: float, T: float, rx: float, ry: float, rz: float, a_ss: float, b_ss: float,
               s: float = 1.0) -> tuple[float, float, float]:
    """``update_axes((fx, fy, fz), (zx, zy, zz), T, (rx, ry, rz), s, steady=(a_ss, b_ss))``
    with the arguments flat (issue 14, round 8: the Tracker's X, Y, Z call, no tuples built
    and unpacked, no keyword): measurements [m], variances [m²], T [s], the manager's steady
    gains (α, β) [1]; returns the innovations (ν_x, ν_y, ν_z) [m]."""
    global _q_last
    # the Tracker's X, Y, Z (issue 14, round 7): when the three axes share the key of the
    # loop of _update_loop (config, n ≥ 1, the steady-gain tuple object; with per-axis priors,
    # vel_prior_r, every axis's tuple equal to the manager's given gains: steady_all), that
    # loop's arithmetic for three axes written out: the gains once, then each axis, no loop,
    # zip or list appends (tested equal to the loop, bit for bit)
    n = fx.n
    cfg = fx.cfg
    st = fx._steady
    if (n and fy.n == n and fz.n == n and fy.cfg is cfg and fz.cfg is cfg
            and not cfg.auto_gains
            and ((fy._steady is st and fz._steady is st and not cfg.vel_prior_r)
                 or steady_all(st, fy._steady, fz._steady, a_ss, b_ss))):
        fx.alpha_ss = fy.alpha_ss = fz.alpha_ss = a_ss  # as set_steady_gains
        fx.beta_ss = fy.beta_ss = fz.beta_ss = b_ss
        if st is not None and st == (a_ss, b_ss):  # as below: the steady gains hold
            a, b = a_ss, b_ss
        else:
            m = n + 1
            n_max = cfg.n_max
            if 0 < n_max < m or cfg.vel_prior_k:  # capped, or a velocity prior: itself
                a, b, evo = scheduled_gains(m, n_max, a_ss, b_ss, prior_q(cfg.vel_prior_k, T))
            else:  # scheduled_gains(m, n_max, α_ss, β_ss) uncapped, written out (m ≥ 2)
                den = m * (m + 1.0)
                a = 2.0 * (2.0 * m - 1.0) / den  # seed 000 "Evolutive coefficients": α(n)
                b = 6.0 / den  # β(n)
                evo = True
                if 0.0 < a_ss < 2.0 and 0.0 < b_ss < 4.0 - 2.0 * a_ss:  # stable_gains
                    if a_ss >= a:
                        a, evo = a_ss, False
                    if b_ss >= b:
                        b, evo = b_ss, False
            sched_st = (a, b) if (a, b) == (a_ss, b_ss) else None
            fx.evolutive = fy.evolutive = fz.evolutive = evo
            fx._steady = fy._steady = fz._steady = sched_st
        fx.alpha = fy.alpha = fz.alpha = a
        fx.beta = fy.beta = fz.beta = b
        bt = b / T
        c = 1.0 - a
        cc, aa, abt, bt2, btbt = c * c, a * a, a * bt, 2.0 * bt, bt * bt
        sm = s * cfg.sigma_m
        q_sm, q_dt, q11, q12, q22 = _q_last
        if sm != q_sm or q_dt != T:
            q11, q12, q22 = q_cwna(sm * sm, T)  # seed 002 eq. (4)
            _q_last = (sm, T, q11, q12, q22)
        # each axis as below: seed 000 "Beginning period" (DSP form), then the
        # Joseph-form covariance after ΦPΦᵀ + Q (seed 002 eqs. 4, 7)
        vel = fx.vel
        p = fx.pos + vel * T
        nu_x = zx - p
        fx.pos = p + a * nu_x
        fx.vel = vel + bt * nu_x
        p12 = fx.p12
        p22 = fx.p22
        ap = p12 + T * p22
        pp11 = fx.p11 + T * (p12 + ap) + q11
        pp12 = ap + q12
        fx.p11 = cc * pp11 + aa * rx
        fx.p12 = c * (pp12 - bt * pp11) + abt * rx
        fx.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + rx)
        if n >= 2 and fx.detect:
            fmd = fx.fmd
            fmd.innovation(nu_x * nu_x / (pp11 + rx))
            fmd.decide()
        vel = fy.vel
        p = fy.pos + vel * T
        nu_y = zy - p
        fy.pos = p + a * nu_y
        fy.vel = vel + bt * nu_y
        p12 = fy.p12
        p22 = fy.p22
        ap = p12 + T * p22
        pp11 = fy.p11 + T * (p12 + ap) + q11
        pp12 = ap + q12
        fy.p11 = cc * pp11 + aa * ry
        fy.p12 = c * (pp12 - bt * pp11) + abt * ry
        fy.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + ry)
        if n >= 2 and fy.detect:
            fmd = fy.fmd
            fmd.innovation(nu_y * nu_y / (pp11 + ry))
            fmd.decide()
        vel = fz.vel
        p = fz.pos + vel * T
        nu_z = zz - p
        fz.pos = p + a * nu_z
        fz.vel = vel + bt * nu_z
        p12 = fz.p12
        p22 = fz.p22
        ap = p12 + T * p22
        pp11 = fz.p11 + T * (p12 + ap) + q11
        pp12 = ap + q12
        fz.p11 = cc * pp11 + aa * rz
        fz.p12 = c * (pp12 - bt * pp11) + abt * rz
        fz.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + rz)
        if n >= 2 and fz.detect:
            fmd = fz.fmd
            fmd.innovation(nu_z * nu_z / (pp11 + rz))
            fmd.decide()
        fx.n = fy.n = fz.n = n + 1
        return nu_x, nu_y, nu_z
    nu = _update_loop((fx, fy, fz), (zx, zy, zz), T, (rx, ry, rz), s, (a_ss, b_ss))
    return nu[0], nu[1], nu[2]


def update_axes(axes: Sequence[AlphaBetaAxis], zs: Sequence[float], T: float,
                rs: Sequence[float], s: float = 1.0,
                steady: tuple[float, float] | None = None) -> list[float]:
    """:meth:`AlphaBetaAxis.update` of several axes with the measurements ``zs``, variances
    ``rs`` [unit²], all over the same T [s] and scale ``s``; returns the innovations.

    Axis by axis exactly what one ``update`` per axis computes (it is how ``update`` runs);
    with several axes (the Tracker's X, Y, Z, issue 14) what does not depend on the axis's
    own measurement and state — the gain schedule, Q, and the gain products of the update —
    is computed once for the axes that share its inputs (the same config object, n, steady
    gains and gain-schedule state: the Tracker's three axes, PRI after PRI). ``steady``: the
    manager's steady gains (α, β), as :meth:`AlphaBetaAxis.set_steady_gains` on each axis
    first; None keeps each axis's own.
    """
    if steady is not None and len(axes) == 3:
        (fx, fy, fz), (zx, zy, zz), (rx, ry, rz) = axes, zs, rs
        a_ss, b_ss = steady
        return list(update_xyz(fx, fy, fz, zx, zy, zz, T, rx, ry, rz, a_ss, b_ss, s))
    return _update_loop(axes, zs, T, rs, s, steady)


def _update_loop(axes: Sequence[AlphaBetaAxis], zs: Sequence[float], T: float,
                 rs: Sequence[float], s: float, steady: tuple[float, float] | None
                 ) -> list[float]:
    """:func:`update_axes` axis by axis (the general case: any number of axes, the key of
    the shared quantities recomputed where it changes)."""
    global _q_last
    out: list[float] = []
    append = out.append
    # key of the shared per-update quantities below: (config, n, α_ss, β_ss, the axis's
    # steady-gain tuple before the update); NaN never compares equal (recomputed)
    k_cfg: FilterConfig | None = None
    k_n, k_a, k_b, k_st = -1, math.nan, math.nan, None
    # Q of the last call (a pure function of σm·s and T, usually the same PRI after PRI)
    q_sm, q_dt, q11, q12, q22 = _q_last
    has_steady = steady is not None
    st_a, st_b = steady if has_steady else (math.nan, math.nan)
    for f, z, r in zip(axes, zs, rs, strict=True):
        if has_steady:  # as set_steady_gains
            f.alpha_ss = a_ss = st_a
            f.beta_ss = b_ss = st_b
        else:
            a_ss = f.alpha_ss
            b_ss = f.beta_ss
        n = f.n
        if n == 0:  # initialisation: x = z, v = 0, n = 1
            f.pos, f.vel, f.n = z, 0.0, 1
            f.alpha, f.beta, f.evolutive = 1.0, 0.0, True
            f.p11, f.p12, f.p22 = r, 0.0, 0.0
            append(0.0)
            continue
        cfg = f.cfg
        st = f._steady
        if cfg is not k_cfg or n != k_n or a_ss != k_a or b_ss != k_b or st is not k_st:
            # the gains and what follows from them, for this axis and the next ones that
            # share the key (a pure function of it, of s and T; not with auto_gains: r enters)
            k_cfg = None if cfg.auto_gains or cfg.vel_prior_r else cfg  # (r enters)
            k_n, k_a, k_b, k_st = n, a_ss, b_ss, st
            if cfg.auto_gains and not stable_gains(a_ss, b_ss):
                a_ss, b_ss = kalata_gains(tracking_index(s * cfg.sigma_m, T, math.sqrt(r)))
            if st is not None and st == (a_ss, b_ss):  # (no tuple built while evolutive)
                # both steady gains already exceeded the evolutive ones; α(n), β(n) only
                # decrease with n (or are capped), so scheduled_gains would return them again
                a, b = a_ss, b_ss
                sched = None  # evolutive and _steady stay as they are
            else:
                k = cfg.vel_prior_k  # per-axis prior (vel_prior_r, session 20): k·r/r₀
                if cfg.vel_prior_r > 0.0:
                    k *= r / cfg.vel_prior_r
                sched = scheduled_gains(n + 1, cfg.n_max, a_ss, b_ss, prior_q(k, T))
                a, b, evo = sched
                sched_st = (a, b) if (a, b) == (a_ss, b_ss) else None
            bt = b / T
            c = 1.0 - a
            cc, aa, abt, bt2, btbt = c * c, a * a, a * bt, 2.0 * bt, bt * bt
            sm = s * cfg.sigma_m
            if sm != q_sm or q_dt != T:
                q_sm, q_dt = sm, T
                q11, q12, q22 = q_cwna(sm * sm, T)  # seed 002 eq. (4)
                _q_last = (sm, T, q11, q12, q22)  # (one tuple: replaced at once)
        if sched is not None:
            f.evolutive = evo
            f._steady = sched_st
        f.alpha = a
        f.beta = b
        # seed 000 "Beginning period" (DSP form), P = V3 + V5·T with T = dt:
        #   P = V3 + V5·T; V1 = In − P; V2 = α·V1; V4 = (β/T)·V1;
        #   OutP = P + V2; OutV = V4 + V5; V3 = OutP; V5 = OutV
        vel = f.vel
        p = f.pos + vel * T  # P = V3 + V5·T
        nu = z - p  # V1 = In − P
        f.pos = p + a * nu  # OutP = P + α·V1
        f.vel = vel + bt * nu  # OutV = V5 + (β/T)·V1
        # covariance of the fixed-gain filter, Joseph form (class docstring), after
        # ΦPΦᵀ + Q (seed 002 eqs. 4, 7), c = 1 − α:
        #   P11 = c²·pp11 + α²·r, P12 = c·(pp12 − (β/T)·pp11) + α·(β/T)·r,
        #   P22 = pp22 − 2(β/T)·pp12 + (β/T)²·(pp11 + r)
        # ΦPΦᵀ + Q as predict_cov (seed 002 eqs. 4, 7), written out: no call per axis
        p12 = f.p12
        p22 = f.p22
        ap = p12 + T * p22
        pp11 = f.p11 + T * (p12 + ap) + q11
        pp12 = ap + q12
        f.p11 = cc * pp11 + aa * r
        f.p12 = c * (pp12 - bt * pp11) + abt * r
        f.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + r)
        if n >= 2 and f.detect:
            fmd = f.fmd
            fmd.innovation(nu * nu / (pp11 + r))
            fmd.decide()
        f.n = n + 1
        append(nu)
    return out

