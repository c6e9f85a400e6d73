"""Beam-common clutter residue in a Doppler filter: its share of the filter's power and the
threshold factor of the effective looks it leaves (issue 11, session 21; docs/clutter.md
"Partly common clutter residue").

Seed 000 is silent on clutter; every choice here is a designer's choice and a parameter of the
manager (``residue_share_looks``, ``confirm_loss_mti_order``).

Behind the MTI canceller the ground clutter's residue is white, like the receiver noise, but it
is one signal seen by the four beams. A SUM cell S = Σ_b Σ_n |y_{b,n}| then holds fewer
independent looks per PRI than beams. With the residue's power share f = C/(C + N) of a beam
(C the common residue, N the beam's own thermal noise, the same in every beam: a designer's
assumption), the L beams' covariance (unit power) is (1 − f)·I + f·11ᵀ: one eigenvalue
1 + (L − 1)·f (the common direction), L − 1 eigenvalues 1 − f. The tail of the sum is ruled by
the largest, so the manager takes the looks per PRI whose Gamma law has that scale at the same
mean power (tail-matched):

    L_eff = L / (1 + (L − 1)·f)        (L = ``looks_per_pri``),

from L (f = 0, independent beams) down to 1 (f = 1, one common signal: the former
``common_mode_factor``). The threshold factor is the exact dwell-sum ratio
(:func:`.thresholds.dwell_sum_factors`) at the integer looks around L_eff, interpolated
linearly in L (the ratio is convex and decreasing in L, so the chord lies above it).
Checked against a Monte-Carlo simulation of the four beams through the one-pole filter
(tests/test_manager_residue.py; K = 16, ρ = 0.9): the looks that match the simulated
q/median ratio are, at f = 0.2 / 0.3 / 0.45 / 0.6, 3.29 / 2.75 / 1.97 / 1.70 at Pfa 10⁻³ and
3.11 / 2.60 / 1.94 / 1.66 at 10⁻⁴ (falling toward the tail-matched 2.50 / 2.11 / 1.70 / 1.43
as Pfa falls), so L_eff errs on the side of a lower false-alarm rate: the factor is 4-8 % above
the simulated one at 10⁻³. Variance matching (L/(1 + (L − 1)·κ(f)), κ the magnitudes'
correlation) gave 3.60 / 3.21 / 2.57 / 2.01: too many looks, 5.5 % low at f = 0.3.

The share needs each filter's thermal level. Behind the canceller it is shaped by the
canceller's response: the filtered noise power of a filter centred at ν_c (cycles per PRI) is
G(ν_c) = ∫|H_mti(ν)|²·|H_f(ν − ν_c)|² dν / ∫|H_f(ν)|² dν (:func:`class_thermal_gains`,
|H_mti|² of :func:`~axir.models.radar.mti.mti_power_gain`, |H_f|² ∝ 1/|1 − ρe^{j2πν}|² the
one-pole Doppler filter): 0.10 at 0 Hz, 1.9 at PRF/2 for the two-pulse canceller. The manager
does not see the canceller's switch (it is the generator's, by antenna elevation), so it infers
it from its own levels (:func:`mti_inferred`): with the canceller on, the levels of the filters
away from 0 Hz (G ≥ 1) rise with G (slope of level² against G ≈ the thermal power, whatever the
white residue adds); with it off they are flat. Measured (direct loop, target-free, 20 km
designation, 2 × 5 s per elevation): before, 1.4-2.5 % of the acquisition dwells at 2-3.5°
raised a false alarm (design 4.8·10⁻⁴: the filters 1-2 kHz from the clutter line were below
the 1.6 × thermal switch with a residue 1-5 × their own thermal noise); with the share's looks
1 false alarm in 18 096 dwells at 0.5-10°.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..radar.mti import mti_power_gain
from .thresholds import dwell_sum_factors

#: slope of level² (in thermal units) against G above which the canceller is inferred on: the
#: thermal part of the slope is 1 with the canceller, 0 without (designer's choice: midway)
MTI_SLOPE = 0.5
#: power above a class's thermal level not counted as common residue (the level's estimation
#: noise and calibration: a 16-cell median ±5 %, the EMA ±1.3 %, the calibration ±2.5 %)
SHARE_MARGIN = 0.1
#: the residue share is rounded up to this step for the factor's cache (a lower factor never)
SHARE_STEP = 1.0 / 256.0
_QUAD = 4096  # quadrature points of class_thermal_gains over one PRF


def class_thermal_gains(n_classes: int, step: float, pole: float, order: int) -> list[float]:
    """G per filter position class: the filtered thermal power behind the canceller of
    ``order`` relative to no canceller, for a one-pole filter (pole radius ``pole``) centred
    at c·``step`` cycles per PRI, c = 0 … ``n_classes`` − 1 (the manager's position classes:
    distance from 0 Hz in grid steps of ``step``·PRF). All 1 without a
    canceller (``order`` ≤ 0) or a selective filter (``pole`` ≤ 0: white noise stays white)."""
    if order <= 0 or pole <= 0.0:
        return [1.0] * n_classes
    nu = (np.arange(_QUAD) + 0.5) / _QUAD
    m2 = mti_power_gain(nu, order)
    out = []
    for c in range(n_classes):
        h = 1.0 / np.abs(1.0 - pole * np.exp(2j * math.pi * (nu - c * step))) ** 2
        out.append(float(np.sum(m2 * h) / np.sum(h)))
    return out


def mti_inferred(levels2: list[float], gains: list[float]) -> bool:
    """Whether the canceller is on, from the classes' level² [thermal units] (NaN: not
    measured): least-squares slope of level² against G over the classes with G ≥ 1 (away from
    the clutter line) above :data:`MTI_SLOPE`; False with fewer than 3 such classes or no
    spread of G (no canceller)."""
    pts = [(g, v) for g, v in zip(gains, levels2, strict=True) if g >= 1.0 and v == v]
    n = len(pts)
    if n < 3:
        return False
    mg = sum(g for g, _ in pts) / n
    mv = sum(v for _, v in pts) / n
    sgg = sum((g - mg) * (g - mg) for g, _ in pts)
    if sgg <= 1e-12:
        return False
    return sum((g - mg) * (v - mv) for g, v in pts) / sgg > MTI_SLOPE


def share_looks(share: float, looks: int) -> float:
    """Tail-matched looks per PRI of ``looks`` beams whose power holds the common share
    ``share`` ∈ [0, 1]: L / (1 + (L − 1)·share) (module docstring)."""
    return looks / (1.0 + (looks - 1) * min(max(share, 0.0), 1.0))


@lru_cache(maxsize=4096)
def _share_factor(q: int, looks: int, dwell: int, pole: float, pfa: float, which: int) -> float:
    ll = share_looks(q * SHARE_STEP, looks)
    lo = max(1, min(math.floor(ll), looks))
    f_lo = dwell_sum_factors(lo, dwell, pole, pfa)[which]
    if lo >= looks:
        return float(f_lo)
    f_hi = dwell_sum_factors(lo + 1, dwell, pole, pfa)[which]
    w = ll - lo
    return float(f_lo * (1.0 - w) + f_hi * w)


def share_factor(share: float, looks: int, dwell: int, pole: float, pfa: float,
                 which: int) -> float:
    """Threshold factor (q/median for ``which`` 0, q/mean for 1) of a dwell of ``dwell`` PRIs
    whose beams hold the common share ``share``: the exact dwell-sum ratio interpolated
    linearly in the looks at :func:`share_looks` (the share rounded up to :data:`SHARE_STEP`;
    cached)."""
    q = min(math.ceil(min(max(share, 0.0), 1.0) / SHARE_STEP), round(1.0 / SHARE_STEP))
    return _share_factor(q, looks, dwell, pole, pfa, which)


def class_shares(levels: list[float], thermal_level: float, gains: list[float]) -> list[float]:
    """Beam-common share 1 − (1 + m)·T/level² of every position class (T its thermal power: G
    of its class if :func:`mti_inferred`, else 1; m = :data:`SHARE_MARGIN`; ``levels`` the
    classes' acquisition levels in SUM units, NaN: not measured; ``thermal_level`` > 0 the
    calibrated thermal level); 0 where level² is at or below (1 + m)·T or not measured. The
    manager recomputes it when a level changes (an acquisition dwell's end)."""
    lv2 = [(v / thermal_level) ** 2 for v in levels]
    t = gains if mti_inferred(lv2, gains) else [1.0] * len(gains)
    m = 1.0 + SHARE_MARGIN
    return [1.0 - m * ti / v2 if v2 == v2 and v2 > m * ti else 0.0
            for v2, ti in zip(lv2, t, strict=True)]


def residue_floors(shares: list[float], pos: list[int], looks: int, dwell: int, pole: float,
                   pfa: float, which: int) -> list[float]:
    """Threshold factor floors of the filters at position classes ``pos``: the
    :func:`share_factor` of their class's share (:func:`class_shares`), 0 for no share."""
    return [share_factor(shares[p], looks, dwell, pole, pfa, which) if shares[p] > 0.0 else 0.0
            for p in pos]
