"""DDRE rough range tracker of an (extended) target from a range profile (seed 001, eqs. 1-11).

Range (seed 001 §2): amplitude-squared-weighted centroid over a window of s bins,

    C0(r) = Σ_{r'=r}^{r+s−1} |A(r')|²                     # seed 001 eq. (1)
    C1(r) = Σ_{r'=r}^{r+s−1} |A(r')|² r'Δr                # seed 001 eq. (2)
    B0(r) = ½[Σ_{r−s}^{r−1} |A|² + Σ_{r+s}^{r+2s−1} |A|²]  # seed 001 eq. (3), local background
    B1(r) = ½[Σ_{r−s}^{r−1} |A|² r'Δr + Σ_{r+s}^{r+2s−1} |A|² r'Δr]   # seed 001 eq. (4)
    S0 = C0 − B0, S1 = C1 − B1                            # seed 001 eqs. (5), (6)
    R(t) = S1(r_max)/S0(r_max), r_max = argmax_r S0(r)    # seed 001 eq. (7)

with an optional threshold on S0(r_max): if rejected, the previous range is reused (eq. 7
note). Bin r' (0-based index into the profile) is at range ``range_start + r'·Δr``; the
constant ``range_start`` commutes with eq. (7) (S1 + range_start·S0 over S0), so it is added
to the centroid afterwards.

Background (``background``): "none" (B0 = B1 = 0), "local" (eqs. 3-4; only windows whose two
flanks of s bins lie inside the profile are candidates), "global" — named but not specified by
the seed; our assumption: a flat background level b = median of |A|² over the whole profile
(robust to the target), B0 = s·b, B1 = b·Δr·Σ_{r}^{r+s−1} r'.

Smoothing (seed 001 §3): RS(t) = α RS(t−1) + (1 − α) R(t) (eq. 8, equivalently the damped sum
eq. 9) with α = exp(−Δt/τ) (eq. 10), Δt the actual time between updates; then the velocity cut
limits |RS(t) − RS(t−1)| ≤ v_cut·Δt.

Prediction (eq. 11), RT(t) = RS(t − t_pred): the seed calls RT the "prediction" of the next
range-gate centre and says its figures are "shifted 0.1 s". Read literally, RS(t − t_pred) is a
delay line (a *past* value), which would make the gate lag the target further. We therefore
implement, by default (``prediction = "extrapolate"``), the forward shift of the smoothed track
by t_pred along its smoothed slope, RT(t) = RS(t) + t_pred·V_S(t), where V_S is the
exponentially smoothed (same α) rate of RS — for a constant-velocity target V_S → ṙ, so RT is
RS shifted t_pred ahead in time; and, for fidelity to the literal equation,
``prediction = "delay"``: RT(t) = RS(t − t_pred) by linear interpolation in a delay line of past
RS values (RS of the oldest sample before the history fills).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..radar.params import Configurable, Param


class DDREOutput(NamedTuple):
    """Result of one :meth:`DDRE.update`."""

    range: float  # R(t) [m], eq. (7) (held when rejected; NaN before the first detection)
    smoothed: float  # RS(t) [m], eqs. (8)-(10) with the velocity cut
    predicted: float  # RT(t) [m], eq. (11)
    rate: float  # V_S(t) [m/s], smoothed rate of RS
    detected: bool  # S0(r_max) passed the threshold at this update
    s0: float  # S0(r_max) [units of |A|²]
    r_max: int  # 0-based first bin of the selected window (−1: none)


class DDRE(Configurable):
    """DDRE range estimator and exponentially damped range track (seed 001 eqs. 1-11)."""

    PARAMS = (
        Param("window", 8, "1", "number s of active bins in the range window", low=1,
              high=100_000),
        Param("bin_size", 3.0, "m", "size Δr of a range bin", low=0.0, low_open=True),
        Param("range_start", 0.0, "m", "range of profile bin 0"),
        Param("background", "none", "", "background subtraction: none, local (eqs. 3-4) or "
              "global (flat median level, assumption)", choices=("none", "local", "global")),
        Param("threshold", 0.0, "1",
              "threshold on S0(r_max) in |A|² units; below it the previous range is reused",
              low=0.0),
        Param("memory", 0.5, "s", "characteristic time τ of the damping, α = exp(−Δt/τ)",
              low=0.0, low_open=True),
        Param("velocity_cut", 200.0, "m/s", "limit of |dRS/dt| (0 = no cut)", low=0.0),
        Param("t_pred", 0.1, "s", "prediction shift t_pred of eq. (11)", low=0.0),
        Param("prediction", "extrapolate", "",
              "eq. (11): 'extrapolate' RS(t) + t_pred·V_S (forward shift, default) or "
              "'delay' RS(t − t_pred) (literal delay line)", choices=("extrapolate", "delay")),
    )

    def __init__(self, **overrides: object) -> None:
        super().__init__(**overrides)
        self.reset()

    def reset(self) -> None:
        """Forget the track."""
        self.t: float | None = None
        self.r_meas = math.nan
        self.rs = math.nan
        self.rate = 0.0
        self.history: list[tuple[float, float]] = []  # (t, RS) for the delay line

    # ------------------------------------------------------------------ eqs. 1-7
    def measure(
        self, profile: np.ndarray, range_start: float | None = None
    ) -> tuple[float, float, int]:
        """Range centroid of one profile: (R [m] or NaN, S0(r_max), r_max) — eqs. (1)-(7),
        without the threshold. ``range_start`` [m] overrides the parameter for this profile
        (a moving range window)."""
        p = np.abs(np.asarray(profile)) ** 2
        n, s, dr = p.size, self.window, self.bin_size
        idx = np.arange(n, dtype=float) * dr
        c0 = np.concatenate(([0.0], np.cumsum(p)))
        c1 = np.concatenate(([0.0], np.cumsum(p * idx)))
        # candidate first bins: local background needs both flanks inside the profile
        r = np.arange(s, n - 2 * s + 1) if self.background == "local" else np.arange(n - s + 1)
        if r.size == 0:
            return math.nan, math.nan, -1
        C0 = c0[r + s] - c0[r]  # seed 001 eq. (1)
        C1 = c1[r + s] - c1[r]  # seed 001 eq. (2)
        if self.background == "local":
            B0 = 0.5 * ((c0[r] - c0[r - s]) + (c0[r + 2 * s] - c0[r + s]))  # eq. (3)
            B1 = 0.5 * ((c1[r] - c1[r - s]) + (c1[r + 2 * s] - c1[r + s]))  # eq. (4)
        elif self.background == "global":
            b = float(np.median(p))  # assumption: flat background level per bin
            B0 = s * b
            B1 = b * dr * (s * r + 0.5 * s * (s - 1))  # b·Δr·Σ_{r}^{r+s−1} r'
        else:
            B0 = B1 = 0.0
        S0 = C0 - B0  # seed 001 eq. (5)
        S1 = C1 - B1  # seed 001 eq. (6)
        k = int(np.argmax(S0))
        s0 = float(S0[k])
        if not (s0 > 0.0 and math.isfinite(s0)):
            return math.nan, s0, int(r[k])
        r0 = self.range_start if range_start is None else range_start
        return r0 + float(S1[k]) / s0, s0, int(r[k])  # seed 001 eq. (7)

    # ------------------------------------------------------------------ eqs. 8-11
    def update(
        self, profile: np.ndarray, t: float, range_start: float | None = None
    ) -> DDREOutput:
        """Process the profile |A(r)| (or complex A) observed at time t [s]; ``range_start``
        [m] optionally overrides the range of bin 0 for this profile."""
        if self.t is not None and t < self.t:
            raise ValueError(f"DDRE.update: time went backwards ({t!r} < {self.t!r})")
        r, s0, rmax = self.measure(profile, range_start)
        detected = math.isfinite(r) and s0 >= self.threshold  # eq. (7) note: threshold
        if detected:
            self.r_meas = r
        # else: the previous range is reused (seed 001 eq. 7 note)
        if math.isnan(self.r_meas):  # nothing detected yet: no track
            self.t = t
            return DDREOutput(math.nan, math.nan, math.nan, 0.0, False, s0, rmax)
        if math.isnan(self.rs):
            self.rs, self.rate = self.r_meas, 0.0  # initialise on the first detection
        else:
            dt = t - self.t
            if dt > 0.0:
                a = math.exp(-dt / self.memory)  # seed 001 eq. (10)
                new = a * self.rs + (1.0 - a) * self.r_meas  # seed 001 eq. (8)
                step = new - self.rs
                if self.velocity_cut > 0.0:  # seed 001 §3: velocity cut on RS
                    lim = self.velocity_cut * dt
                    step = lim if step > lim else (-lim if step < -lim else step)
                self.rs += step
                self.rate = a * self.rate + (1.0 - a) * step / dt  # smoothed dRS/dt
        self.t = t
        return DDREOutput(self.r_meas, self.rs, self._predict(t), self.rate, detected, s0, rmax)

    def _predict(self, t: float) -> float:
        """RT(t), seed 001 eq. (11) — see the module docstring for the two readings."""
        if self.prediction == "extrapolate":
            return self.rs + self.t_pred * self.rate
        h = self.history
        h.append((t, self.rs))
        target = t - self.t_pred
        while len(h) >= 2 and h[1][0] <= target:  # keep one sample at or before the target
            del h[0]
        t0, r0 = h[0]
        if target <= t0 or len(h) == 1:
            return r0
        t1, r1 = h[1]
        return r0 + (r1 - r0) * (target - t0) / (t1 - t0)
