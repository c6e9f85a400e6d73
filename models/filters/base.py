"""One small interface for every per-axis tracking filter, and the tuning they share.

The seed-002 filters work "separately in each direction" of the measurement (seed 002 §2.1:
range, bearing, elevation) and the seed-000 tracker runs one α-β filter per Cartesian axis; both
are one-dimensional position measurements z with variance r. Every filter here implements
:class:`AxisFilter` (Stone Soup vocabulary: one ``predict`` and one ``update`` with the same
signature for all, so the Tracker picks a filter with a parameter):

- ``update(z, T, r=None, s=1.0) -> ν``: predict over T [s] (time since the previous update or
  coast) and correct with the measurement z; returns the innovation ν = z − ẑ (0 on the first
  measurement). ``r`` is the measurement variance [unit²] (None: ``cfg.sigma_meas²``); ``s``
  [1/m·unit] converts the metric noise parameters (σm, σa, P_u(0) in m/s²) to the axis unit:
  1 for range or Cartesian axes, 1/ρ for elevation, 1/(ρ cos El) for azimuth.
- ``coast(T, s=1.0)``: prediction only (no measurement).
- ``predict(T) -> (pos, vel, acc)``: the state extrapolated T ahead, state unchanged.
- ``x`` = (pos, vel, acc) (acc = 0 for filters without an acceleration estimate, and for the
  switching filters while no maneuver is declared); ``P`` = (P_pp, P_pv, P_vv), the 2×2
  position/velocity covariance; ``maneuver`` (FMD flag), ``statistic`` (L(k), seed 002
  eq. 11), ``threshold`` (I1); ``n`` measurements used; ``initialised``.
- ``reset()``; ``get_state()``/``set_state()``: deep copy of the whole filter state (bit-identical
  continuation after a restore; the FMU saves the Tracker, which holds the filters).

Initialisation common to the Kalman-type filters (seed 002 §2.1): from the first two
measurements y(0), y(1) taken T apart, r̂ = y(1), v̂ = (y(1) − y(0))/T and
P(0/0) = [[σr², σr²/T], [σr²/T, 2σr²/T²]] (with two different variances r0, r1:
[[r1, r1/T], [r1/T, (r0 + r1)/T²]]). The seed prints r̂(0/0) = y(0), but its P(0/0) has
cov(r̂, v̂) = +σr²/T, which holds only for r̂ = y(1) (with y(0) it would be −σr²/T):
reconstructed as the two-point differencing initialisation of Bar-Shalom, Li & Kirubarajan
(2001) §5.5.3. After the first measurement only, x = (y(0), 0, 0) and P = (r0, 0, 0)
(velocity not estimated yet).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from .fmd import FadingMemoryDetector, Quantiser

Vec3 = tuple[float, float, float]

@dataclass(frozen=True)
class FilterConfig:
    """Tuning shared by the per-axis filters (units for a metric axis; see ``s`` above).

    Attributes:
        sigma_m: σm of the two-state model, seed 002 eq. (4): Q = σm² T [[T²/3, T/2], [T/2, 1]]
            [m/s²] (dimensionally σm² is the spectral density of a continuous white
            acceleration, m²/s³; numerically the seed's σm at its T = 1 s).
        sigma_meas: default measurement σ when ``update`` gets no ``r`` [unit].
        sigma_a: acceleration noise of the SVD acceleration filter [m/s²] as a density per
            1 s: random-walk input Q_u = σa²·T/(1 s) (seed 002 eqs. 18-19, 22, 36 "Q_u constant":
            σa² at T = 1 s). # assumption: the seed gives no Q_u value; 5 m/s² (Q_u = 25) puts
            the peaks of P_u and K_u at the seed's Table 3 register ranges (docs/filters.md).
        sigma_j: jerk noise of the three-state models (VD, IMM CA) [m/s²] as a density per
            1 s: continuous white jerk of spectral density σj²/(1 s) [m²/s⁵]
            (Bar-Shalom, Li & Kirubarajan 2001 §6.2.3; not in seed 002).
        a_f, i1, i2, pfa, level, fmd_end: fading-memory detector
            (:mod:`axir.models.filters.fmd`; ``fmd_end`` is its ``end`` rule).
        pu0: P_u(0/0) of the SVD acceleration filter [(m/s²)²] (seed 002: 0.1).
        svd_c: "paper" (C = T²/2 in eqs. 20, 25, 27) or "zero" (C = 0) for the full SVD form.
        imm_sojourn_cv, imm_sojourn_ca: mean sojourn times of the IMM modes [s]; the Markov
            transition matrix over an interval T is p_ii = exp(−T/τ_i), p_ij = 1 − p_ii.
        imm_mu_ca: initial probability of the CA mode [1].
        sigma_acc0: initial acceleration σ of the IMM at the two-point initialisation [m/s²].
        n_max: α-β evolutive gain index cap (0 = none), see
            :func:`axir.models.filters.gains.scheduled_gains`.
        vel_prior_k: α-β only: r/σv² [s²] of a velocity prior on the evolutive velocity gain
            (:func:`axir.models.filters.gains.scheduled_gains` with q = vel_prior_k/T²); 0 =
            none (seed 000's evolutive gains).
        vel_prior_r: α-β only: the reading variance r₀ [unit²] ``vel_prior_k`` was computed
            with; > 0: each update scales it by the update's own r (q = vel_prior_k·r/r₀/T²,
            a prior of the same σv on axes whose readings differ, session 20); 0: as given.
        auto_gains: α-β only: when no steady gains are supplied, use Kalata's steady gains of
            the tracking index σm T²/σ (measurement input mode, no manager).
        quant: fixed-point hook (``svd_reduced`` only; :mod:`axir.models.filters.fixedpoint`).
    """

    sigma_m: float = 5.0
    sigma_meas: float = 100.0
    sigma_a: float = 5.0
    sigma_j: float = 2.0
    a_f: float = 0.8
    i1: float = 0.0
    i2: float = 0.0
    pfa: float = 1e-3
    level: float = 0.05
    fmd_end: str = "hysteresis"
    pu0: float = 0.1
    svd_c: str = "paper"
    imm_sojourn_cv: float = 20.0
    imm_sojourn_ca: float = 5.0
    imm_mu_ca: float = 0.1
    sigma_acc0: float = 20.0
    n_max: int = 0
    vel_prior_k: float = 0.0
    vel_prior_r: float = 0.0
    auto_gains: bool = False
    quant: Quantiser | None = None

    def detector(self) -> FadingMemoryDetector:
        """A fresh fading-memory detector with these settings."""
        return FadingMemoryDetector(self.a_f, self.i1, self.i2, self.pfa, self.level,
                                    self.quant, end=self.fmd_end)


class AxisFilter:
    """Interface of a one-dimensional tracking filter (see the module docstring)."""

    kind: ClassVar[str] = ""
    #: True when the filter can estimate an acceleration (``x[2]`` may be non-zero).
    has_acceleration: ClassVar[bool] = False

    def __init__(self, cfg: FilterConfig | None = None) -> None:
        self.cfg = cfg or FilterConfig()
        self.r_default = self.cfg.sigma_meas ** 2
        self.fmd = self.cfg.detector()
        self.reset()

    # ------------------------------------------------------------------ to implement
    def reset(self) -> None:
        """Forget the track (n = 0) and the detector state."""
        raise NotImplementedError

    def update(self, z: float, T: float, r: float | None = None, s: float = 1.0) -> float:
        """Predict over T [s] and correct with z; returns the innovation [unit]."""
        raise NotImplementedError

    def coast(self, T: float, s: float = 1.0) -> None:
        """Prediction only over T [s]."""
        raise NotImplementedError

    def predict(self, T: float) -> Vec3:
        """(pos, vel, acc) extrapolated T [s] ahead; the state is unchanged."""
        raise NotImplementedError

    @property
    def x(self) -> Vec3:
        """(pos [unit], vel [unit/s], acc [unit/s²])."""
        raise NotImplementedError

    @property
    def P(self) -> Vec3:
        """(P_pp [unit²], P_pv [unit²/s], P_vv [unit²/s²])."""
        raise NotImplementedError

    # ------------------------------------------------------------------ common
    @property
    def initialised(self) -> bool:
        return self.n > 0

    @property
    def maneuver(self) -> bool:
        """Maneuver flag of the fading-memory detector."""
        return self.fmd.flag

    @property
    def statistic(self) -> float:
        """L(k), seed 002 eq. (11) [1]."""
        return self.fmd.L

    @property
    def threshold(self) -> float:
        """I1, the detection threshold on L [1]."""
        return self.fmd.i1

    def set_steady_gains(self, alpha: float, beta: float) -> None:
        """Steady α-β gains from a radar manager (used by the α-β filter only)."""

    def get_state(self) -> dict[str, Any]:
        """Deep copy of the whole filter state."""
        return copy.deepcopy(self.__dict__)

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore a state from :meth:`get_state` (continues bit-identically)."""
        self.__dict__.clear()
        self.__dict__.update(copy.deepcopy(dict(state)))


class CVEstimate(AxisFilter):
    """Outputs of a filter whose estimate is the scalars ``pos``, ``vel`` and the covariance
    ``p11``, ``p12``, ``p22`` (constant-velocity model, no acceleration)."""

    pos: float
    vel: float
    p11: float
    p12: float
    p22: float

    def predict(self, T: float) -> Vec3:
        return self.pos + T * self.vel, self.vel, 0.0

    @property
    def x(self) -> Vec3:
        return self.pos, self.vel, 0.0

    @property
    def P(self) -> Vec3:
        return self.p11, self.p12, self.p22


class TwoPointFilter(AxisFilter):
    """Base of the Kalman-type filters: the two-point initialisation (module docstring), then
    ``_first_update`` once and ``_update`` for every later measurement."""

    def reset(self) -> None:
        self.n = 0
        self.fmd.reset()
        self._z0 = 0.0  # first measurement
        self._r0 = self.r_default  # its variance
        self._wait = 0.0  # time coasted since the first measurement [s]
        self._reset_state()

    def update(self, z: float, T: float, r: float | None = None, s: float = 1.0) -> float:
        r = self.r_default if r is None else r
        if self.n == 0:
            self._z0, self._r0, self._wait = z, r, 0.0
            self.n = 1
            self._set_first(z, r)
            return 0.0
        if self.n == 1:
            T = T + self._wait
            if not T > 0.0:
                raise ValueError(f"{type(self).__name__}: second measurement needs T > 0, "
                                 f"got {T!r}")
            z0 = self._z0
            # seed 002 §2.1 initialisation (reconstructed, module docstring)
            v = (z - z0) / T
            p11, p12, p22 = r, r / T, (self._r0 + r) / (T * T)
            self.n = 2
            self._set_initial(z, v, p11, p12, p22, T, r, s)
            return z - z0
        nu = self._update(z, T, r, s)
        self.n += 1
        return nu

    def coast(self, T: float, s: float = 1.0) -> None:
        if self.n == 1:
            self._wait += T
        elif self.n >= 2:
            self._coast(T, s)

    # subclass hooks
    def _reset_state(self) -> None:
        raise NotImplementedError

    def _set_first(self, z: float, r: float) -> None:
        """State after the first measurement only: x = (z, 0, 0), P = (r, 0, 0)."""
        raise NotImplementedError

    def _set_initial(self, pos: float, vel: float, p11: float, p12: float, p22: float,
                     T: float, r: float, s: float) -> None:
        """State after the second measurement: the two-point initialisation."""
        raise NotImplementedError

    def _update(self, z: float, T: float, r: float, s: float) -> float:
        raise NotImplementedError

    def _coast(self, T: float, s: float) -> None:
        raise NotImplementedError

