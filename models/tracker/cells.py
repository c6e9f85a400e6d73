"""Per-PRI arithmetic of the beams tracker's gate cells and measurement (seed 000), moved out
of :mod:`.beams` (issue 14, round 4: that module was at the 600-line limit).

- :func:`background_sum`: the noise level of the weak-signal check in Python floats;
- :func:`_early_late_corrected`: the range discriminator with the noise removed (issue 11);
- :func:`_cartesian_variances`: the diagonal of the Cartesian measurement covariance;
- :func:`edge_reading`: a confirmed reading beyond the edge ratio read across the other pair
  (issue 11, session 23);
- :func:`bg_removed`: the elevation pair's own background powers removed from a confirmed
  reading (issue 11, session 29; it reads two beam rows of the array and updates its
  average in place).

Otherwise pure functions of floats: no state, no numpy call per PRI.
"""

from __future__ import annotations

import math
from math import sqrt

import numpy as np

from ..radar.conventions import GATE_BIN
from .deviations import early_late

_C = GATE_BIN - 1  # 0-based index of bin 7
#: background bins of the weak-signal check, 1-4 and 10-16 (0-based), away from the gate cells
#: 6-8 and their neighbours: their mean SUM is the noise level (seed 000)
_BACKGROUND_BINS = np.r_[0:_C - 2, _C + 3:16]
_N_BACKGROUND = _BACKGROUND_BINS.size


def background_sum(col: list[float]) -> float:
    """Sum of the background bins 1-4 and 10-16 (0-based 0-3, 9-15: ``_BACKGROUND_BINS``) of
    one SUM column (16 values), in the order numpy sums those 11 contiguous values (pairwise:
    eight partial sums, then the last three), so it equals ``col[_BACKGROUND_BINS].sum()`` bit
    for bit (tests/test_tracker_speedups.py) without two numpy calls per PRI (issue 14)."""
    c = col
    return ((((c[0] + c[1]) + (c[2] + c[3])) + ((c[9] + c[10]) + (c[11] + c[12])))
            + c[13] + c[14] + c[15])



#: E|n|² / (E|n|)² of a Rayleigh magnitude: the noise power under a SUM cell from the mean
#: noise magnitude of the background bins (4/π)
_NOISE_POWER_RATIO = 4.0 / math.pi


def _early_late_corrected(s6: float, s7: float, s8: float, noise: float) -> float:
    """Early/late ratio ε_R [1] of the gate cells with the noise removed in power (issue 11,
    designer's choice; the seed gives the ratio, not its noise handling).

    A SUM cell is a magnitude, E[s²] ≈ A² + σ² with σ² = (4/π)·n̄² (n̄ the mean SUM of the
    background bins, Rayleigh). Uncorrected, the noise adds to the three cells and dilutes
    the ratio: at a filtered SNR of 17 dB a 20 m offset read ≈ 0.6 × its value, the closed
    range loop then has a gain of ≈ 0.6 and a fresh track's error decays over ≈ 1 s instead
    of ≈ 0.1 s (42 km, docs/filters.md). Each cell becomes √max(s² − σ², 0); the plain
    :func:`.deviations.early_late` when the corrected cells sum to 0 or noise is not finite."""
    n2 = _NOISE_POWER_RATIO * noise * noise
    a6, a7, a8 = s6 * s6 - n2, s7 * s7 - n2, s8 * s8 - n2
    c6 = sqrt(a6) if a6 > 0.0 else 0.0
    c7 = sqrt(a7) if a7 > 0.0 else 0.0
    c8 = sqrt(a8) if a8 > 0.0 else 0.0
    den = c6 + c7 + c8
    if den > 0.0 and den < math.inf:
        return (c8 - c6) / den
    return early_late(s6, s7, s8)


def _cartesian_variances(rho: float, az: float, el: float, sigma_range: float,
                         sigma_angle: float) -> tuple[float, float, float]:
    """Diagonal of the Cartesian measurement covariance [m²] of a measurement at (ρ, θ, φ)
    with range σ ``sigma_range`` [m] and angle σ ``sigma_angle`` [rad] (lateral and elevation:
    ρ·σ across the beam): Σ_k (u_k,i σ_k)² over the spherical unit vectors u_ρ, u_θ, u_φ."""
    return _cartesian_variances_cs(rho, math.cos(az), math.sin(az), math.cos(el),
                                   math.sin(el), sigma_range, sigma_angle)


def _cartesian_variances_cs(rho: float, ca: float, sa: float, ce: float, se: float,
                            sigma_range: float, sigma_angle: float
                            ) -> tuple[float, float, float]:
    """:func:`_cartesian_variances` from cos/sin of the azimuth (``ca``, ``sa``) and of the
    elevation (``ce``, ``se``)."""
    sr2 = sigma_range * sigma_range
    sc2 = (rho * sigma_angle) ** 2
    return (
        (ce * sa) ** 2 * sr2 + (ca * ca + (se * sa) ** 2) * sc2,
        (ce * ca) ** 2 * sr2 + (sa * sa + (se * ca) ** 2) * sc2,
        se * se * sr2 + ce * ce * sc2,
    )


def edge_reading(u: float, r: float, d: float, lf: float, noise: float, dev_el: float,
                 dev_lat: float, edge: tuple[float, float, float]) -> tuple[float, float]:
    """The linear-law deviations (``dev_el``, ``dev_lat``) [rad] of one central-filter gate
    cell, an axis read beyond the edge ratio across the other pair (issue 11, session 23;
    designer's choice: the seed gives the DIF/SUM ratios only).

    A pair's ratio saturates where its weaker beam holds mostly noise: a 1 m² target 3.5°
    off the boresight at 10 km reads 1.35-1.55° (ε ≈ 0.75-0.85) whatever its angle. For the
    Gaussian beams of radar/antenna.py the stronger beam against the geometric mean of the
    other pair measures the same angle without the weak beam (the cross terms cancel; beams
    up, right, down, left = ``u``, ``r``, ``d``, ``lf``):
    r/√(u·d) = exp(k_m·lat), l/√(u·d) = exp(−k_m·lat), u/√(r·l) = exp(k_m·el),
    d/√(r·l) = exp(−k_m·el); ``edge`` = (k_m the monopulse slope [1/rad], ``eps_edge``,
    ``snr_strong``). With the noise removed in power, p = b² − σ², σ² = (4/π)(n̄/4)² per
    beam (n̄ = ``noise``, the mean background SUM of the 4 beams): an axis whose ratio
    |ε| = k_m·|dev| exceeds ``eps_edge``, whose stronger beam holds ``snr_strong`` × the noise
    power (p > snr_strong·σ²) and whose other pair both hold more signal than noise (p > σ²)
    reads θ = ±(½ ln p_strong − ¼ ln(p₁·p₂))/k_m, returned as the linear law's noise-free reading
    tanh(k_m·θ)/k_m (the filter averages linear-law readings and the report inverts the
    pattern on them, session 14); otherwise the axis keeps its deviation. Noise-free, the
    3.47°-off target above reads 3.47° this way. Why ``snr_strong`` (``edge_reading_snr``,
    100): at a lower SNR the ratio's own noise (σε ≈ 1/(2√SNR) ≥ 0.05) decides which readings
    cross the edge, and replacing exactly those pushed the readings of weak 42 km targets
    ≈ 1° off the boresight outward (RMS angle +44 % in the design, session 23)."""
    slope, eps_edge, snr_strong = edge
    n2 = _NOISE_POWER_RATIO * (0.25 * noise) ** 2
    pu, pr, pd, pl = u * u - n2, r * r - n2, d * d - n2, lf * lf - n2
    ps = pr if pr > pl else pl  # the stronger beam of each pair
    if abs(slope * dev_lat) > eps_edge and pu > n2 and pd > n2 and ps > snr_strong * n2:
        x = 0.5 * math.log(ps) - 0.25 * math.log(pu * pd)
        dev_lat = math.copysign(math.tanh(x), dev_lat) / slope
    ps = pu if pu > pd else pd
    if abs(slope * dev_el) > eps_edge and pr > n2 and pl > n2 and ps > snr_strong * n2:
        x = 0.5 * math.log(ps) - 0.25 * math.log(pr * pl)
        dev_el = math.copysign(math.tanh(x), dev_el) / slope
    return dev_el, dev_lat


def _background_power(row: list[float]) -> float:
    """Mean power of one beam's background bins 1-4 and 10-16 (0-based 0-3, 9-15:
    ``_BACKGROUND_BINS``) of its 16 amplitudes ``row`` [V²] (written out: per PRI)."""
    return (row[0] * row[0] + row[1] * row[1] + row[2] * row[2] + row[3] * row[3]
            + row[9] * row[9] + row[10] * row[10] + row[11] * row[11] + row[12] * row[12]
            + row[13] * row[13] + row[14] * row[14] + row[15] * row[15]) / _N_BACKGROUND


def bg_removed(beams: np.ndarray, u: float, d: float, frac: float, ema: list[float],
               pole: float) -> tuple[float, float]:
    """The up and down beams' gate-cell amplitudes ``u``, ``d`` [V] of a confirmed reading
    with a fraction ``frac`` of each beam's own background power removed (issue 11, session
    29: ``Tracker.beam_background``, ``beam_background_pole``; designer's choice, the seed
    forms the DIF/SUM ratios of the raw amplitudes).

    Ground clutter below a low beam fills the lower beam far more than the upper one (at
    15 km and 3° elevation its background power is 15-30× the upper beam's). Added in power
    to a weak target's amplitude it pulls the elevation ratio (u − d)/(u + d) down, the
    more so the lower the antenna points: the reading of a target 1° above the boresight
    falls back toward 0 (0.50° at 1.0°, 0.41° at 1.24° measured), so a young track pulled
    down by its velocity error walks into the clutter and the readings cannot bring it back.
    The background power of each beam, b̄ₖ² = mean power of its background bins (1-4,
    10-16, central filter, ``beams[k, :, 1]``), is removed in part from the cell:
    pₖ = aₖ² − frac·b̄ₖ², averaged over the PRIs of the confirmed track in ``ema`` (the
    state (p_u, p_d), updated in place; empty: starts at pₖ): p ← pole·p + (1 − pole)·pₖ;
    the amplitudes returned are √p (0 for p ≤ 0), or ``u``, ``d`` themselves when neither
    is left, or when a beam is not finite (the averages then kept). Only the elevation
    pair: the ground is level, the lateral beams see it alike. The average takes the
    strongest gate cell of each PRI (bin 6, 7 or 8) and restarts with each new track; a
    reading beyond the edge then goes to :func:`edge_reading` with these amplitudes (at 0.3
    ≈ 1 % of the PRIs of a target 1° off the boresight in lower-beam clutter).

    Why a fraction: the clutter decorrelates over ≈ 10 ms (15 Hz spread), so the cell's
    clutter power is one slowly varying draw, not the mean; a full removal clips the weaker
    beam to 0 on the PRIs where the draw is below the mean and reads the target up to twice
    as far off (+0.84-0.88° for a target 0.44° above the boresight), and the noisier readings
    swing young tracks out of the angle gate (docs/filters.md "Each elevation beam's own
    background").

    ``beams``: (4, 16, 3) amplitudes [V] (beams up, right, down, left)."""
    row_u, row_d = beams[0::2, :, 1].tolist()  # the up and down beams' rows, one call
    pu = u * u - frac * _background_power(row_u)
    pd = d * d - frac * _background_power(row_d)
    if not math.isfinite(pu + pd):  # a NaN or ±inf beam: the raw cells (the reading's
        return u, d  # own screening decides), the averages kept
    if ema:
        q = 1.0 - pole
        pu = pole * ema[0] + q * pu
        pd = pole * ema[1] + q * pd
    ema[:] = (pu, pd)
    cu = sqrt(pu) if pu > 0.0 else 0.0
    cd = sqrt(pd) if pd > 0.0 else 0.0
    return (cu, cd) if cu + cd > 0.0 else (u, d)
