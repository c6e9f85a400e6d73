"""Fading-memory maneuver detector (FMD) of the seed-002 filters, one measurement axis.

Sources
-------
- seed 002 §2.2, eqs. (11)-(15): L(k) = a_f·L(k − 1) + d(k), d(k) = Rᵀ(k)N⁻¹(k)R(k) (the
  normalised innovation squared of the two-state filter, R its innovation, N its variance),
  effective window M = 1/(1 − a_f); a maneuver is declared when L(k) exceeds a threshold. The
  seed uses two thresholds, I1 and I2, without saying how they are chosen or what I2 is for
  (Table 3 lists them as 8-bit constants "like 7.5" and "like 11.04").
- Bar-Shalom, Y. and Birmiwal, K. (1982), "Variable dimension filter for maneuvering target
  tracking", IEEE Trans. AES-18(5), 621-629 (seed 002 ref. [1]); the same scheme in
  Bar-Shalom, Li & Kirubarajan (2001), "Estimation with Applications to Tracking and
  Navigation", §11.6: detection on the fading-memory average of the innovations; the maneuver
  ends when the acceleration estimate is no longer statistically significant, tested on the sum
  of â²/P_aa over a sliding window of the last M updates.

Reconstruction (documented in docs/filters.md):
- eq. (33) and Table 4 (U114) print "L = (a_f + L) + …"; read as eq. (11), a_f·L: an added
  a_f would make L grow without bound and would not be a fading memory.
- I1 is the detection threshold on L(k); I2 the end-of-maneuver threshold on the windowed
  acceleration significance. With a_f = 0.8 (M = 5) the 95 % point of χ² with M = 5 degrees of
  freedom is 11.07, the seed's "like 11.04"; that reading makes I2 > I1 meaningful.
- Where the seed is silent the thresholds come from the χ² quantile (``i1 = 0`` or
  ``i2 = 0`` asks for them): under no maneuver d is χ² with n_y degrees of freedom, and the
  fading sum L is approximated by c·χ²_ν with the same mean n_y/(1 − a_f) and variance
  2n_y/(1 − a_f²), i.e. c = 1/(1 + a_f), ν = n_y(1 + a_f)/(1 − a_f) (moment matching); so
  I1 = χ²_ν⁻¹(1 − P_fa)/(1 + a_f). The windowed acceleration statistic is χ² with M·n_a
  degrees of freedom when the true acceleration is zero: I2 = χ²_{M}⁻¹(1 − level).

Decision: the maneuver flag is raised when L > I1; what holds it is the reading of I2
(``end``, Tracker parameter ``fmd_end``; docs/filters.md "Two readings of I2"):

- ``"acceleration"`` (Bar-Shalom & Birmiwal's end test): held while the windowed acceleration
  statistic A ≥ I2: ``flag = L > I1 or (flag and A >= I2)``;
- ``"hysteresis"`` (seed 002 Tables 3, 4 and 7 read literally: I1 and I2 are constants of the
  detector unit U11/U01 beside L, d and a_F, and U11 computes nothing but L): two thresholds on
  L, enter above I1, leave below I2: ``flag = L > I1 or (flag and L >= I2)``. A hysteresis
  needs I2 ≤ I1; with I2 > I1 the rule is the single threshold L > I1.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from math import isfinite

#: Quantiser hook of the fixed-point emulation: (register name, value) -> stored value.
Quantiser = Callable[[str, float], float]

#: readings of the second threshold I2 (module docstring)
END_RULES = ("acceleration", "hysteresis")


def window_length(a_f: float) -> int:
    """Effective window M = 1/(1 − a_f) of the fading memory, rounded to an integer ≥ 1.

    # seed 002 eq. (15)
    """
    return max(1, round(1.0 / (1.0 - a_f)))


def detection_threshold(a_f: float, pfa: float, n_y: int = 1) -> float:
    """I1: threshold on L(k) with false-alarm probability ``pfa`` per update (moment-matched χ²,
    see the module docstring) [1]."""
    return _chi2_ppf(1.0 - pfa, n_y * (1.0 + a_f) / (1.0 - a_f)) / (1.0 + a_f)


def end_threshold(window: int, level: float, n_a: int = 1) -> float:
    """I2: threshold on the sum of â²/P_aa over ``window`` updates; the acceleration is
    significant (maneuver goes on) while the sum is ≥ I2 (χ² with window·n_a dof) [1]."""
    return _chi2_ppf(1.0 - level, window * n_a)


def _chi2_ppf(q: float, dof: float) -> float:
    """χ²_dof⁻¹(q), 0 < q ≤ 1, dof > 0 [1]: ``2·gammaincinv(dof/2, q)``, the formula that
    ``scipy.stats.chi2.ppf`` evaluates (same bytes, tested), from scipy.special imported here:
    importing scipy.stats costs ≈ 0.5 s more at every start-up (issue 14, session 6)."""
    from scipy.special import gammaincinv

    return float(2.0 * gammaincinv(dof / 2.0, q))


class FadingMemoryDetector:
    """Fading-memory detector L(k) (seed 002 eqs. 11-15) with the end-of-maneuver test.

    Args:
        a_f: fading factor, 0 ≤ a_f < 1 [1].
        i1: detection threshold on L; 0 = from χ² at ``pfa``.
        i2: end threshold on the windowed acceleration statistic; 0 = from χ² at ``level``.
        pfa: false-alarm probability per update for the default I1.
        level: significance level of the acceleration test for the default I2.
        quant: optional fixed-point hook applied to L (fixed-point emulation only).
        n_y: dimension of the innovation (χ² degrees of freedom of d under no maneuver) for
            the default I1: 1 for one measurement axis, 3 for the seed-000 tracker's 3-D
            normalised innovation (:mod:`axir.models.tracker.maneuver`).
        end: reading of I2, one of :data:`END_RULES` (module docstring): "acceleration"
            (I2 on the windowed â²/P_aa) or "hysteresis" (I2 the leaving threshold on L).

    State: ``L`` (eq. 11), ``flag``, ``acc`` (last M values of â²/P_aa) and their sum ``A``.
    """

    def __init__(self, a_f: float = 0.8, i1: float = 0.0, i2: float = 0.0, pfa: float = 1e-3,
                 level: float = 0.05, quant: Quantiser | None = None, n_y: int = 1,
                 end: str = "acceleration") -> None:
        if not 0.0 <= a_f < 1.0:
            raise ValueError(f"FadingMemoryDetector: a_f = {a_f!r} must be in [0, 1)")
        if not 0.0 < pfa < 1.0 or not 0.0 < level < 1.0:
            raise ValueError(f"FadingMemoryDetector: pfa = {pfa!r} and level = {level!r} "
                             "must be in (0, 1)")
        if i1 < 0.0 or i2 < 0.0 or not (isfinite(i1) and isfinite(i2)):
            raise ValueError(f"FadingMemoryDetector: thresholds i1 = {i1!r}, i2 = {i2!r} "
                             "must be finite and >= 0 (0 = from chi2)")
        if end not in END_RULES:
            raise ValueError(f"FadingMemoryDetector: end = {end!r} must be one of "
                             f"{', '.join(END_RULES)}")
        self.end = end
        self.quant = quant
        self.a_f = a_f if quant is None else quant("a_f", a_f)
        self.window = window_length(a_f)
        i1 = i1 if i1 > 0.0 else detection_threshold(a_f, pfa, n_y)
        i2 = i2 if i2 > 0.0 else end_threshold(self.window, level)
        self.i1 = i1 if quant is None else quant("I1", i1)
        self.i2 = i2 if quant is None else quant("I2", i2)
        self.reset()

    def reset(self) -> None:
        """L = 0 (seed 002: "the initial value for L(k) = 0"), no maneuver."""
        self.L = 0.0
        self.flag = False
        self.acc: list[float] = []
        self.A = 0.0

    def innovation(self, d: float) -> None:
        """Add one normalised innovation squared d(k) = R²/N [1].

        # seed 002 eq. (11): L(k) = a_f·L(k − 1) + d(k)   (eq. 33 reconstructed, see module)
        """
        if isfinite(d):
            v = self.a_f * self.L + d
            self.L = v if self.quant is None else self.quant("L", v)

    def acceleration(self, e: float) -> None:
        """Add one acceleration significance term e = â²/P_aa [1] to the window of M."""
        if isfinite(e):
            acc = self.acc
            acc.append(e)
            if len(acc) > self.window:
                del acc[0]
            self.A = math.fsum(acc)

    def decide(self) -> bool:
        """Update and return the maneuver flag: raised on L > I1; held while A ≥ I2
        ("acceleration") or while L ≥ I2 ("hysteresis")."""
        stat = self.L
        held = self.A if self.end == "acceleration" else stat
        # seed 002 §2.2: "two threshold are used, I1 ... and I2" (eq. 11 statistic L)
        self.flag = stat > self.i1 or (self.flag and held >= self.i2)
        return self.flag
