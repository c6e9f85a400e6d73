"""Adaptive Radar Manager (AXIR_C, seed 000): modes, thresholds, PRIs, ambiguity, gains, servo.

The manager runs the three AXIR modes (seed 000 "Operating Modes"):

**Acquisition** (mode 0). Seed: "The magnitudes of the … four squinted beams are accumulated … for
the three Doppler filters and for the sixteen range gates. Each channel is compared to a threshold.
If one result is trespassing this level, the target is declared present in the cell providing the
largest number." The Tracker sends SUM(R, f) (seed eq. 1); the manager accumulates it
non-coherently over a dwell of ``dwell_acq`` PRIs, estimates the noise level of each Doppler filter
as the median of its 16 accumulated range cells (robust to one target, and to clutter confined to
some filters), smoothed over dwells (``noise_avg_dwells``), and sets Th1_f = c1_f·noise_f with c1_f
the ratio of the (1 − pfa_acq) quantile to the median of the accumulated statistic (exact law
of the IIR-filtered noise, or one look in a clutter-dominated filter: see *Thresholds*); the
target is the largest cell above its Th1. The gate search steps ``gate.command`` across
±``search_extent`` around the designated range (taken modulo the acquisition PRI's Ru), one
window per dwell, ``search_step_bins`` apart (16-bin windows, so 16 − step bins overlap), centre
first then alternately farther / nearer; a whole-Ru search when the extent covers Ru. On a Th1
crossing the gate is re-centred so the detected bin becomes bin 7 and the manager goes tentative.

**Tentative** (mode 1). Seed: "Several Doppler measurements (coherent bursts) are operated with
at least 3 different PRIs in order to solve the range-Doppler ambiguities … 'target present' is
determined by the central range gates and the threshold (Th2). Side range bins are accumulated to
give the ambient noise level used to determine Th2 … R = Ro + N*75 m. It is the Radar Manager
which calculates this value". The manager measures the apparent range at each of the 3 PRIs
(acquisition PRI first). Per dwell (``dwell_tent`` PRIs) and per Doppler filter,
Th2_f = c2_f·(mean of side bins 1-3, 11-16 of that filter); "target present" when a cell of
bins 6-8 exceeds its filter's Th2 (assumption: per filter rather than Σ_f, so clutter in one
filter does not mask or fake the target); the apparent bin is that of the largest central cell
relative to Th2. *Finding the target after a PRI change* (assumption: hypothesis windows): the
candidate true range bins B consistent with the measurements so far (±``tol_bins``) predict the
apparent bin B mod k at the new PRI; the predictions are merged into 3-bin clusters, each visited
with a window centred on it (nearest to the designated / last known range first), and
``range.offset`` is set to that hypothesis' N·Ru so "true = apparent + offset" stays physically
consistent while the window is on it. After two PRIs the candidates are usually reduced to one
cluster (the first two default PRIs are ghost-free to 285 km), so the third PRI is a single
window: the seed's coherence check. The three measurements go to
:func:`axir.models.ambiguity.resolve_bins`; inconsistent → acquisition. The resolved range sets
the PRI kept for confirmed tracking (``confirm_pri_index``; 0 = automatic: the PRI whose apparent
range is farthest from the eclipse at 0 / Ru), its gate and ``range.offset`` = N·Ru; then
``confirm_m`` detections out of ``confirm_n`` dwells → confirmed, else acquisition. Tentative
also falls back after ``tent_timeout_pris`` PRIs or after ``tent_window_cycles`` unsuccessful
passes over a PRI's hypothesis windows.

**Confirmed** (mode 2). Seed: "The bandwidths of the servo-loops are progressively reduced up to
a certain limit … the Doppler frequency is calculated by the Radar Manager and only the central
Doppler filter is used". One PRI is kept (assumption: no PRI switching while confirmed, so the
gate, ``range.offset`` and the Doppler filters never see a PRI change; the generator does not
model eclipsing, and the kept PRI is chosen with the largest eclipse margin). Per dwell
(``dwell_conf``) Th2 is applied on the central filter only (bins 6-8 vs side bins);
``miss_limit`` consecutive missed dwells → track lost → acquisition, searching around the last
track range. ``bandwidth`` falls log-linearly (geometrically) from ``bw_start`` to ``bw_floor``
over ``bw_decay_time`` and then holds (monotonic; assumption: the seed gives no law).
``doppler.centre`` is the centre of the Doppler filter that held the target in tentative until
``doppler_track_delay`` seconds of confirmed tracking ("As the trajectory is perfectly
smoothed"), then fold(−2ṙ/λ, PRF) from ``track.range_rate`` (radar.py convention), re-computed
at each dwell end and held in between. Steady α-β gains (seed: "The Radar Manager is
responsible for updating the Alpha-Beta coefficients"; "the unknown target manoeuvres must
influence the Alpha-Beta parameters") come from the tracking index Λ = σ_m·T²/σ_n (Kalata 1984,
:func:`axir.models.alphabeta.kalata_gains`), T = the current PRI (assumption: the tracker
updates once per PRI, seed 000 Conclusion), σ_m = ``sigma_man``, or ``sigma_man_high`` while
``maneuver`` is True and for ``maneuver_hold`` s after it. They are sent throughout mode 2 and
are 0 in modes 0-1 (SYSTEM.md: evolutive gains "until the manager's steady gains take over"):
the Tracker uses max(evolutive α(n), steady α) per gain (alphabeta.AlphaBeta3.gains), so it
hands over by itself once its α(n) = 2(2n − 1)/(n(n + 1)) has fallen below the steady value.

**Timing.** Every command change (gate, PRI, mode) is followed by ``latency_pris`` +
⌈settle_db / (−20·log10 doppler_pole)⌉ ignored PRIs (3 + 44 = 47 by default): the co-simulation
loop manager → tracker → generator → tracker → manager lags a few steps, and the generator's
IIR Doppler filters (pole ρ) keep the previous gate's echoes for ~1/(1 − ρ) PRIs. In modes 0
and 1 a sample is also ignored while the ``gate.start`` reported by the Tracker differs (modulo
Ru) from ``gate.command`` (the Tracker has not taken the command); if no sample comes for
``stall_pris`` PRIs the dwell counts as a miss. A non-finite or misshaped ``sum`` (or a
non-finite ``gate.start``) marks the current dwell as a miss and is never accumulated; non-finite
``track.*``/``maneuver``/``dt`` inputs are ignored (previous values held, dt → PRI).

**Thresholds.** A SUM cell of a dwell is S = Σ_{b ≤ 4} Σ_{n ≤ K} |y_{b,n}|, y the output of a
Doppler filter (pole radius ρ = ``doppler_pole``) fed with white complex Gaussian noise; the
beams (``looks_per_pri``) are independent receivers. y is a stationary complex AR(1) process
(the settling wait makes it stationary at the dwell start), so by circular symmetry its envelope
is a Markov chain with a Rice transition, |y_n| given |y_{n−1}| = r ~ Rice(ρr, σ² = (1 − ρ²)/2)
(E|y|² = 1), started from the stationary Rayleigh law. :func:`envelope_sum_pmf` propagates the
joint law of (|y_n|, Σ_{m≤n}|y_m|) on a grid, :func:`dwell_sum_factors` convolves the beams and
returns the (1 − Pfa) quantile over the median (Th1, scaled on the median of the 16 range cells)
and over the mean (Th2, scaled on the side-bin mean). This is exact up to the grid (checked
against a 4·10⁵-dwell Monte Carlo: q/median 1.6335 vs 1.6295 at 10⁻³, 1.785 vs 1.778 at 10⁻⁴,
slightly conservative). The former model (K·4 PRI-looks reduced to L = 9 independent Rayleigh
looks by the ρ^(2k) correlation, then rounded to 10 on the grid, or L estimated from the
range-cell spread) had a lighter tail than the correlated sum: variance-matched looks are 9.8
(exact magnitude correlation, :func:`dwell_sum_looks`) but the tail at 10⁻³-10⁻⁴ is that of
≈ 8 iid looks, so the design Pfa was exceeded (measured 12 % / 23 % per dwell vs 4.7 % at
Pfa 10⁻³). Dwells too long for the grid fall back to the variance-matched looks rounded down.
*Clutter* (``adaptive_looks``): clutter is narrowband and the same signal in the 4 beams, so a
clutter-dominated filter (the 0 Hz filter with the default CNR: 0 dB per beam and pulse through
the −30 dB sidelobes, 13 dB above the filtered noise) holds ≈ 1 Rayleigh look per range cell.
Each filter's looks are estimated from the spread of its range cells, L_f ≈ 0.705²/(IQR/median)²
(EMA over ``noise_avg_dwells`` dwells, robust to a target in a few cells); a filter with
L_f < ½ of the thermal variance-matched looks is clutter-dominated and gets the iid
Rayleigh-sum ratio at L_f rounded *down* on the grid (1 look for the default clutter: measured
99.9 % quantile 3.03 × median vs 3.16 for one look, i.e. conservative); the others keep the
exact thermal ratio (no estimation noise). Measured with the real TargetGenerator in the direct
loop (target removed, Pfa 10⁻³ per cell, 48 cells: design 4.69 % per dwell, 1500 dwells):
noise only 4.47 %, default clutter 3.00 % (the thermal filters at design, the clutter filter
below). Neglected: the CFAR loss of the noise estimate (EMA of 16-cell medians, ≈ 1.3 % rms:
≲ 10 % on Pfa) and, for Th2, of the 9-side-bin mean of one dwell (Th2's real Pfa is higher).

**Integration contract** (what the other units must do):

- ``gate.command`` [m] is the *gate start* (range of bin 1, as models/tracker.py reads it) in
  apparent range for the current PRI, on the 75 m grid: the gate centre (bin 7) is
  ``gate.command + 6·75 m`` and its true range ``gate.command + 6·75 m + range.offset``. In
  modes 0 and 1 the Tracker sets ``gate.start = gate.command``; in mode 2 it gates on its own
  prediction, ``gate.start = R_pred − range.offset − 6·75 m`` (models/tracker.py), and the
  manager reports ``gate.command`` = ``track.range − range.offset − 6·75 m`` for information.
  ``range.offset`` = N·Ru of the current PRI at all times and is constant while confirmed.
- ``pri`` is the master's communication step; ``doppler.centre`` and ``pri`` go to the
  TargetGenerator, ``bandwidth`` to the Pedestal, ``mode``/``alpha``/``beta``/``range.offset``/
  ``gate.command`` to the Tracker; the Tracker's ``sum``, ``gate.start``, ``track.range``,
  ``track.range_rate`` and ``maneuver`` come back.
- Set ``doppler_pole`` = TargetGenerator ``pole``, ``wavelength`` = the generator's λ, and
  ``designation_range`` = the scenario's designated range.
- Declarations of the unit's ports: :data:`INPUTS`, :data:`OUTPUTS` (:class:`Port`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import lru_cache
from typing import Any, ClassVar

import numpy as np

from . import ambiguity as amb
from .filters.gains import kalata_gains
from .radar.conventions import (
    ACQUISITION,
    BIN_M,
    CONFIRMED,
    DEFAULT_WAVELENGTH,
    GATE_BIN,
    N_BINS,
    N_DOPPLER,
    TENTATIVE,
    fold_doppler,
)
from .radar.params import Param
from .radar.ports import Port
from .radar.unit import Unit

_C = GATE_BIN - 1  # 0-based index of bin 7
_CENTRAL = slice(_C - 1, _C + 2)  # bins 6, 7, 8
# Side range bins for Th2 (seed: "Side range bins are accumulated to give the ambient noise
# level"): bins at least 4 bins from the gate centre, 1-3 and 11-16 (assumption: clear of the
# straddle of a target anywhere in bins 6-8).
_SIDE = np.array([r for r in range(N_BINS) if abs(r - _C) >= 4])
_CF = 1  # 0-based central Doppler filter

#: Public inputs of ``step``.
INPUTS: tuple[Port, ...] = (
    Port("sum", float, "1", "SUM(R, f) = B1 + B2 + B3 + B4 from the Tracker (seed 000 eq. 1)",
         shape=(N_BINS, N_DOPPLER)),
    Port("gate.start", float, "m", "range of bin 1 of the gate the Tracker uses (optional)"),
    Port("track.range", float, "m", "Tracker's filtered true range"),
    Port("track.range_rate", float, "m/s", "Tracker's filtered range rate"),
    Port("maneuver", bool, "1", "Tracker's maneuver flag"),
)

#: Public outputs of ``step``.
OUTPUTS: tuple[Port, ...] = (
    Port("mode", int, "1", "0 acquisition, 1 tentative, 2 confirmed"),
    Port("pri", float, "s", "pulse repetition interval (master communication step)"),
    Port("alpha", float, "1", "steady α gain (0 in modes 0-1: evolutive gains)"),
    Port("beta", float, "1", "steady β gain (0 in modes 0-1: evolutive gains)"),
    Port("bandwidth", float, "Hz", "pedestal servo bandwidth"),
    Port("range.offset", float, "m", "N·Ru: true range = apparent range + range.offset"),
    Port("gate.command", float, "m", "gate start (range of bin 1), apparent range"),
    Port("doppler.centre", float, "Hz", "centre of Doppler filter 2"),
    Port("threshold", float, "1", "last threshold (Th1 in mode 0, Th2 in modes 1-2), NaN before"),
    Port("noise.level", float, "1", "last noise estimate the threshold was scaled on, NaN before"),
    Port("detection", bool, "1", "a dwell ended in this step with a threshold crossing"),
    Port("dwell.done", bool, "1", "a dwell ended in this step"),
    Port("ambiguity.resolved", bool, "1", "the true range has been resolved"),
    Port("range.resolved", float, "m", "resolved true range (R0 + N·Ru, 75 m bins), NaN before"),
    Port("tracking.index", float, "1", "tracking index Λ = σ_m·T²/σ_n in use"),
)


@lru_cache(maxsize=128)
def rayleigh_sum_factors(looks: int, pfa: float) -> tuple[float, float]:
    """Threshold ratios for a sum of ``looks`` iid Rayleigh magnitudes.

    Returns ``(q/median, q/mean)`` where ``q`` is the (1 − ``pfa``) quantile of the sum. The
    density of the sum is the ``looks``-fold convolution of the Rayleigh density (computed by FFT
    on a 2¹⁶-point grid extending 20 standard deviations past the mean); both ratios are scale
    free (independent of σ).
    """
    L = int(looks)
    mean1 = math.sqrt(math.pi / 2.0)
    sd1 = math.sqrt((4.0 - math.pi) / 2.0)
    n = 1 << 16
    xmax = L * mean1 + 20.0 * sd1 * math.sqrt(L) + 20.0
    h = xmax / n
    edges = np.arange(n + 1) * h
    cdf1 = -np.expm1(-0.5 * edges**2)
    p1 = np.diff(cdf1)  # mass of cell j, value (j + 1/2)·h
    pl = np.fft.irfft(np.fft.rfft(p1) ** L, n)
    np.clip(pl, 0.0, None, out=pl)
    pl /= pl.sum()
    # index i of pl ↔ value (i + L/2)·h
    sf = np.cumsum(pl[::-1])[::-1]  # P(X ≥ value_i)
    cdf = 1.0 - sf + pl  # P(X ≤ value_i)

    def quantile_upper(p: float) -> float:
        i = int(np.searchsorted(-sf, -p, side="left"))  # first i with sf[i] ≤ p
        i = min(max(i, 1), n - 1)
        # linear interpolation of the survival function between i−1 and i
        s0, s1 = sf[i - 1], sf[i]
        frac = 0.0 if s0 == s1 else (s0 - p) / (s0 - s1)
        return (i - 1 + frac + 0.5 * L) * h

    q = quantile_upper(pfa)
    i_med = int(np.searchsorted(cdf, 0.5))
    median = (i_med + 0.5 * L) * h
    return q / median, q / (L * mean1)


# Looks at which threshold factors are computed (the estimate is rounded to the nearest in log).
_LOOKS_GRID = np.array([1, 2, 3, 4, 5, 6, 7, 8, 10, 12, 14, 16, 20, 24, 28, 32, 40, 48, 56, 64,
                        80, 96, 112, 128, 160, 192, 224, 256, 320, 384, 448, 512, 640, 768, 896,
                        1024, 1536, 2048, 3072, 4096, 6144, 8192, 12288, 16384])
_LOG_GRID = np.log(_LOOKS_GRID)
# (IQR/median)² of a sum of L Rayleigh looks ≈ _IQR2 / L (Gaussian limit 1.349·0.5227 = 0.705;
# 0.770 at L = 1, so L is under-estimated by ≤ 16 % for single looks).
_IQR2 = 0.705**2
_CV2_RAYLEIGH = (4.0 - math.pi) / math.pi  # squared coefficient of variation of one Rayleigh look
# Clutter switch (adaptive_looks): a Doppler filter whose measured looks fall below this
# fraction of the thermal-noise model's is treated as clutter-dominated (see Thresholds).
_CLUTTER_LOOKS_FRACTION = 0.5
# Envelope Markov chain grid: magnitudes up to _R_MAX (E|y|² = 1: P(|y| > 7.5) = e^−56),
# step ≤ 0.04 and ≤ 1/5 of the Rice kernel's σ, at most _NR_MAX cells; exact chain while
# dwell·cells ≤ _CHAIN_BUDGET, else the variance-matched fallback.
_R_MAX = 7.5
_NR_MAX = 400
_CHAIN_BUDGET = 60_000


def grid_looks(L: float) -> int:
    """``L`` rounded to the nearest (in log) entry of the threshold-factor grid."""
    return int(_LOOKS_GRID[int(np.argmin(np.abs(_LOG_GRID - math.log(max(1.0, L)))))])


def grid_looks_floor(L: float) -> int:
    """Largest entry of the threshold-factor grid ≤ ``L`` (1 at least): conservative looks."""
    i = int(np.searchsorted(_LOOKS_GRID, max(1.0, L) * (1.0 + 1e-12), side="right")) - 1
    return int(_LOOKS_GRID[max(i, 0)])


def effective_looks(looks_per_pri: int, dwell: int, pole: float) -> int:
    """Independent Rayleigh looks in a dwell of ``dwell`` PRIs (legacy approximation) [1].

    # assumption: the envelope of a first-order IIR Doppler filter output (pole radius ρ) has
    # PRI-to-PRI correlation ρ^(2k) (exact for the squared envelope); a sum of K such samples has
    # the variance of K / (1 + 2 Σ_{k=1}^{K−1} (1 − k/K) ρ^(2k)) independent ones. The beams
    # (``looks_per_pri``) are independent receivers. Superseded for thresholds by
    # :func:`dwell_sum_factors` (exact distribution; this rounding gave 9 looks where the real
    # tail is that of ≈ 8, see the module docstring).
    """
    k = np.arange(1, dwell)
    f = 1.0 + 2.0 * float(np.sum((1.0 - k / dwell) * pole ** (2.0 * k))) if dwell > 1 else 1.0
    return max(1, round(looks_per_pri * dwell / f))


def envelope_correlation(gamma: float) -> float:
    """Correlation coefficient of |x| and |y| for circular complex Gaussians x, y of complex
    correlation coefficient of modulus ``gamma``: (₂F₁(−½, −½; 1; γ²) − 1)/(4/π − 1)
    (exact; ≈ 0.915·γ² for small γ, 1 at γ = 1)."""
    from scipy.special import hyp2f1

    return float((hyp2f1(-0.5, -0.5, 1.0, gamma * gamma) - 1.0) / (4.0 / math.pi - 1.0))


def dwell_sum_looks(looks_per_pri: int, dwell: int, pole: float) -> float:
    """Variance-matched looks of the dwell sum S = Σ_beams Σ_{n<K} |y_n| (exact moments):
    L_var = looks·K / (1 + 2 Σ_{k=1}^{K−1} (1 − k/K) r(ρ^k)), r = :func:`envelope_correlation`
    (9.8 for the default 4 beams, K = 16, ρ = 0.9)."""
    if dwell <= 1 or pole <= 0.0:
        return float(looks_per_pri * dwell)
    k = np.arange(1, dwell)
    r = np.array([envelope_correlation(pole**kk) for kk in k])
    return looks_per_pri * dwell / (1.0 + 2.0 * float(np.sum((1.0 - k / dwell) * r)))


@lru_cache(maxsize=32)
def envelope_sum_pmf(dwell: int, pole: float) -> tuple[np.ndarray, float] | None:
    """Distribution of T = Σ_{n=1}^{K} |y_n| for one beam, K = ``dwell``, y the stationary
    output of the Doppler filter (pole radius ρ = ``pole``) fed with white complex Gaussian
    noise, normalised E|y|² = 1.

    y_n = ρ e^{jω} y_{n−1} + √(1 − ρ²) w_n (w ~ CN(0, 1)) is a complex AR(1) process; by
    circular symmetry its envelope r_n = |y_n| is a Markov chain whose transition is Rice:
    r_n | r_{n−1} ~ Rice(ν = ρ r_{n−1}, s² = (1 − ρ²)/2), started from the stationary
    Rayleigh law (the manager waits for the filters to settle). The joint mass of
    (r_n, Σ_{m≤n} r_m) is propagated on a grid of step h in both (the sum index is the sum of
    the cell indices, so the new sum is an integer shift): P_n(j', i + j') = Σ_j K(j'|j)
    P_{n−1}(j, i). Returns ``(pmf, h)``, pmf[i] the mass at T = (i + K/2)·h, or None when the
    grid would be too large (very long dwells: see :func:`dwell_sum_factors`).
    """
    from scipy.special import i0e

    s2 = 0.5 * (1.0 - pole * pole)
    h = max(min(0.04, math.sqrt(s2) / 5.0), _R_MAX / _NR_MAX)
    nr = math.ceil(_R_MAX / h)
    if dwell * nr > _CHAIN_BUDGET:
        return None
    edges = np.arange(nr + 1) * h
    r = (np.arange(nr) + 0.5) * h
    p0 = -np.diff(np.exp(-(edges**2)))  # stationary Rayleigh mass per cell (E|y|² = 1)
    nu = pole * r
    # kernel[j', j] ∝ Rice density of r_{j'} given r_j (i0e keeps it finite), columns sum to 1
    ker = (r[:, None] / s2) * np.exp(-((r[:, None] - nu[None, :]) ** 2) / (2.0 * s2)) * i0e(
        r[:, None] * nu[None, :] / s2)
    ker /= ker.sum(axis=0, keepdims=True)
    p = np.diag(p0)  # P_1(j, i): r_1 in cell j, sum index i = j
    for _ in range(1, dwell):
        q = ker @ p
        pn = np.zeros((nr, p.shape[1] + nr))
        for j in range(nr):
            pn[j, j : j + q.shape[1]] = q[j]
        p = pn
    pmf = p.sum(axis=0)
    return pmf / pmf.sum(), h


def _sum_quantile_ratios(pmf: np.ndarray, offset: float, h: float, mean: float,
                         pfa: float) -> tuple[float, float]:
    """(q/median, q/mean) of a lattice law: mass pmf[i] at value (i + offset)·h; q is the
    (1 − pfa) quantile, the survival function interpolated linearly between lattice points."""
    sf = np.cumsum(pmf[::-1])[::-1]  # P(X ≥ value_i)
    cdf = 1.0 - sf + pmf
    n = pmf.size
    i = int(np.searchsorted(-sf, -pfa, side="left"))
    i = min(max(i, 1), n - 1)
    s0, s1 = sf[i - 1], sf[i]
    frac = 0.0 if s0 == s1 else (s0 - pfa) / (s0 - s1)
    q = (i - 1 + frac + offset) * h
    j = int(np.searchsorted(cdf, 0.5))
    c0 = cdf[j - 1] if j > 0 else 0.0
    frac_m = 0.0 if cdf[j] == c0 else (0.5 - c0) / (cdf[j] - c0)
    median = (j - 1 + frac_m + offset) * h
    return q / median, q / mean


@lru_cache(maxsize=128)
def dwell_sum_factors(looks_per_pri: int, dwell: int, pole: float,
                      pfa: float) -> tuple[float, float]:
    """Exact threshold ratios ``(q/median, q/mean)`` of the thermal-noise dwell sum
    S = Σ_{b ≤ looks} Σ_{n ≤ K} |y_{b,n}| (q: (1 − ``pfa``) quantile), the beams independent.

    The law of one beam's sum comes from :func:`envelope_sum_pmf`; the ``looks_per_pri``
    independent beams are convolved by FFT; the mean is exact, looks·K·√π/2. ρ = 0 is the
    iid case, :func:`rayleigh_sum_factors` (looks·K). Dwells too long for the chain grid fall
    back to L = :func:`dwell_sum_looks` rounded down on the grid (variance-matched looks,
    rounded down because the correlated sum's tail is heavier than the iid one's).
    """
    if pole <= 0.0 or dwell <= 1:
        return rayleigh_sum_factors(looks_per_pri * dwell, pfa)
    res = envelope_sum_pmf(dwell, pole)
    if res is None:
        return rayleigh_sum_factors(grid_looks_floor(dwell_sum_looks(looks_per_pri, dwell, pole)),
                                    pfa)
    pmf1, h = res
    n = 1 << math.ceil(math.log2(pmf1.size * looks_per_pri + 1))
    pl = np.fft.irfft(np.fft.rfft(pmf1, n) ** looks_per_pri, n)
    np.clip(pl, 0.0, None, out=pl)
    pl /= pl.sum()
    mean = looks_per_pri * dwell * 0.5 * math.sqrt(math.pi)
    return _sum_quantile_ratios(pl, 0.5 * looks_per_pri * dwell, h, mean, pfa)


def resonator_gain(offset_cycles: np.ndarray | float, pole: float) -> np.ndarray:
    """|H| of the generator's Doppler filter, a first-order complex resonator with unit gain at
    its centre (models/target_generator.py): |H(δ)| = (1 − ρ) / |1 − ρ·e^{j2πδ·PRI}|, with the
    frequency offset δ·PRI from the filter centre given in cycles per PRI (fraction of the PRF).
    """
    w = 2.0 * np.pi * np.asarray(offset_cycles, dtype=np.float64)
    return (1.0 - pole) / np.sqrt(1.0 - 2.0 * pole * np.cos(w) + pole * pole)


_DISC_STEP = 1.0 / 720.0  # search grid of the discriminator [cycles per PRI]


def doppler_offset(excess: np.ndarray, spacing: float, pole: float,
                   weights: np.ndarray | None = None) -> float:
    """Doppler discriminator: offset of the target from the centre filter's centre, as a
    fraction of the PRF in [−spacing/2, spacing/2], from the target's excess amplitude in the
    three Doppler filters.

    ``excess[f]`` (f = 0, 1, 2; centre filter 1) is the target's mean SUM amplitude in filter
    f after that filter's noise/clutter level is removed; filter f is centred (f − 1)·``spacing``
    [cycles per PRI] from the centre filter. Across the filters the amplitude follows each
    filter's resonator gain (:func:`resonator_gain`) up to an unknown scale: the offset δ is the
    one whose gain profile h(δ) best fits the measured profile in weighted least squares over
    the scale, i.e. it maximises (Σ w·e·h)/√(Σ w·h²) (``weights`` w, default equal; a weight 0
    drops a filter) on a 1/720-PRF grid, refined by a parabola. The search is limited to the
    centre filter's own half-spacing: the target was detected in the filter nearest to it.
    Assumption (the seed only says the manager computes the Doppler frequency): an
    amplitude-comparison discriminator across the filters, the frequency-domain analogue of the
    monopulse deviation.
    """
    e = np.maximum(np.asarray(excess, dtype=np.float64), 0.0)
    w = np.ones(N_DOPPLER) if weights is None else np.asarray(weights, dtype=np.float64)
    n_half = int(0.5 * spacing / _DISC_STEP)
    grid = np.arange(-n_half, n_half + 1) * _DISC_STEP
    h = resonator_gain(grid[:, None] - spacing * (np.arange(N_DOPPLER) - _CF)[None, :], pole)
    score = (h @ (w * e)) / np.sqrt((h * h) @ w)
    i = int(np.argmax(score))
    d = grid[i]
    if 0 < i < len(grid) - 1:
        s0, s1, s2 = score[i - 1], score[i], score[i + 1]
        den = s0 - 2.0 * s1 + s2
        if den < 0.0:
            d += 0.5 * (s0 - s2) / den * _DISC_STEP
    return float(d)


class RadarManager(Unit):
    """AXIR_C adaptive radar manager (see the module docstring for the logic and the contract).

    ``step(dt, inputs)``: ``dt`` [s] is the communication step (nominally ``pri``; time in
    confirmed mode and the maneuver hold advance by ``dt``); ``inputs`` and the returned outputs
    are keyed as in :data:`INPUTS` / :data:`OUTPUTS`.
    """

    INPUTS = INPUTS
    OUTPUTS = OUTPUTS

    PARAMS: ClassVar[tuple[Param, ...]] = (
        Param("pri1_bins", amb.DEFAULT_PRI_BINS[0], "1",
              "PRI 1 in 0.5 µs range-bin durations (PRI = k·BIN_S, Ru = k·75 m)", 20, 20000),
        Param("pri2_bins", amb.DEFAULT_PRI_BINS[1], "1", "PRI 2 in range-bin durations", 20, 20000),
        Param("pri3_bins", amb.DEFAULT_PRI_BINS[2], "1", "PRI 3 in range-bin durations", 20, 20000),
        Param("acq_pri_index", 1, "", "PRI (1..3) used in acquisition", choices=(1, 2, 3)),
        Param("confirm_pri_index", 0, "",
              "PRI kept in confirmed tracking (0: largest eclipse margin)", choices=(0, 1, 2, 3)),
        Param("max_range", 150_000.0, "m", "largest true range resolved", 0.0, low_open=True),
        Param("tol_bins", 1, "1", "accepted apparent-range error per PRI [bins]", 0, 5),
        Param("designation_range", 10_000.0, "m", "operator-designated true range", 0.0),
        Param("search_extent", 3_000.0, "m",
              "half-width of the acquisition range search (≥ Ru/2: whole Ru)", 0.0),
        Param("search_step_bins", 12, "1", "gate step between search windows [bins]", 1, 16),
        Param("dwell_acq", 16, "1", "PRIs accumulated per acquisition dwell", 1, 4096),
        Param("dwell_tent", 16, "1", "PRIs accumulated per tentative dwell", 1, 4096),
        Param("dwell_conf", 16, "1", "PRIs accumulated per confirmed dwell", 1, 4096),
        Param("latency_pris", 3, "1",
              "loop latency manager → tracker → generator → tracker → manager [PRIs]", 0, 1000),
        Param("settle_db", 40.0, "dB",
              "Doppler-filter transient decay waited for after a command change", 0.0, 200.0),
        Param("stall_pris", 64, "1",
              "PRIs a dwell waits for a matching gate.start before it counts as a miss", 1),
        Param("looks_per_pri", 4, "1",
              "independent Rayleigh looks per SUM cell per PRI (4 beams)", 1, 64),
        Param("doppler_pole", 0.9, "1",
              "pole radius of the generator's IIR Doppler filters (TargetGenerator.pole)",
              0.0, 1.0, high_open=True),
        Param("pfa_acq", 1e-5, "1", "design false-alarm probability per cell per dwell (Th1)",
              1e-9, 0.1),
        Param("pfa_track", 1e-4, "1", "design false-alarm probability per cell per dwell (Th2)",
              1e-9, 0.1),
        Param("adaptive_looks", True, "",
              "estimate each Doppler filter's effective looks from the range-cell spread "
              "(clutter-aware thresholds); false: doppler_pole model only"),
        Param("noise_avg_dwells", 8.0, "1",
              "averaging length of the acquisition noise level [dwells]", 1.0),
        Param("tent_window_cycles", 2, "1",
              "passes over a PRI's hypothesis windows before tentative fails", 1, 100),
        Param("tent_timeout_pris", 4000, "1", "tentative-mode time limit [PRIs]", 1),
        Param("confirm_m", 3, "1", "detections needed (M of N) to confirm", 1, 100),
        Param("confirm_n", 4, "1", "dwells (N) of the M-of-N confirmation", 1, 100),
        Param("miss_limit", 5, "1", "consecutive missed dwells that drop a confirmed track", 1),
        Param("bw_start", 5.0, "Hz", "servo bandwidth in acquisition / tentative", 0.0,
              low_open=True),
        Param("bw_floor", 1.0, "Hz", "servo bandwidth limit in confirmed", 0.0, low_open=True),
        Param("bw_decay_time", 2.0, "s", "time to reduce the bandwidth to its floor", 0.0),
        Param("sigma_meas", 15.0, "m", "measurement noise σ_n of the tracking index", 0.0,
              low_open=True),
        Param("sigma_man", 5.0, "m/s2", "maneuver noise σ_m (non-maneuvering)", 0.0,
              low_open=True),
        # assumption: ≈ 3× the 30 m/s² of a 3 g turn; measured: holds the default 3 g turn
        # in the closed loop (range lag ≤ 25 m) where 20 m/s² lost the gate
        Param("sigma_man_high", 100.0, "m/s2", "maneuver noise σ_m while maneuvering", 0.0,
              low_open=True),
        Param("maneuver_hold", 1.0, "s", "time the gains stay open after a maneuver", 0.0),
        Param("wavelength", DEFAULT_WAVELENGTH, "m", "carrier wavelength λ", 0.0, low_open=True),
        Param("doppler_search_centre", 0.0, "Hz",
              "Doppler centre in acquisition / tentative (filters tile the folded band)"),
        Param("doppler_spacing_fraction", 1.0 / 3.0, "1",
              "Doppler filter spacing as a fraction of the PRF (generator setting)",
              0.0, 1.0, low_open=True),
        Param("doppler_track_delay", 0.5, "s",
              "confirmed time before the Doppler centre follows the track range rate", 0.0),
        Param("doppler_loop_gain", 1.0, "1",
              "confirmed: fraction of the discriminator's Doppler offset corrected per dwell "
              "(0: centre from the track range rate only)", 0.0, 1.0),
        Param("doppler_disc_snr", 3.0, "1",
              "confirmed: discriminator used only when the target's excess amplitude in its "
              "best filter exceeds this multiple of that filter's noise level", 0.0),
        Param("doppler_disc_clutter", 2.0, "1",
              "confirmed: the discriminator is not used while a Doppler filter's side-bin "
              "level exceeds this multiple of the quietest filter's (clutter)", 1.0),
    )

    # -------------------------------------------------------------------------------- set-up
    def _check(self) -> None:
        ks = (self.pri1_bins, self.pri2_bins, self.pri3_bins)
        if len(set(ks)) != 3:
            raise ValueError(f"RadarManager: pri1_bins, pri2_bins, pri3_bins must differ: {ks}")
        if self.bw_floor > self.bw_start:
            raise ValueError(
                f"RadarManager: bw_floor = {self.bw_floor} Hz exceeds bw_start = {self.bw_start} Hz"
            )
        if self.confirm_m > self.confirm_n:
            raise ValueError(
                f"RadarManager: confirm_m = {self.confirm_m} exceeds confirm_n = {self.confirm_n}"
            )
        if self.sigma_man_high < self.sigma_man:
            raise ValueError("RadarManager: sigma_man_high must be ≥ sigma_man")
        if self.designation_range > self.max_range:
            raise ValueError(
                f"RadarManager: designation_range = {self.designation_range} m exceeds "
                f"max_range = {self.max_range} m"
            )
        max_bin = amb.range_to_bin(self.max_range)
        span = amb.ghost_free_span_bins(ks, self.tol_bins, limit=max_bin + 2 * self.tol_bins + 2)
        if span <= max_bin + 2 * self.tol_bins:
            raise ValueError(
                f"RadarManager: the PRI set {ks} with tol_bins = {self.tol_bins} is ambiguous "
                f"beyond {span * BIN_M:.0f} m < max_range = {self.max_range} m"
            )

    def reset(self) -> None:
        ks = (self.pri1_bins, self.pri2_bins, self.pri3_bins)
        self._ks: tuple[int, int, int] = ks
        self._pris = tuple(amb.pri_seconds(k) for k in ks)
        self._max_bin = amb.range_to_bin(self.max_range)
        # independent fraction φ of the looks_per_pri·K looks of a dwell, per Doppler filter:
        # model value from doppler_pole, then (adaptive_looks) estimated from the data
        k0 = self.dwell_acq
        phi0 = dwell_sum_looks(self.looks_per_pri, k0, self.doppler_pole) / (
            self.looks_per_pri * k0)
        for k in {self.dwell_acq, self.dwell_tent, self.dwell_conf}:  # warm the factor caches
            dwell_sum_factors(self.looks_per_pri, k, self.doppler_pole, self.pfa_acq)
            dwell_sum_factors(self.looks_per_pri, k, self.doppler_pole, self.pfa_track)
        # EMA of the normalised spread s_f = (IQR/median)·√(looks_per_pri·K) = 0.705/√φ_f
        self._spread = np.full(N_DOPPLER, math.sqrt(_IQR2 / phi0))
        self._noise_f = np.full(N_DOPPLER, math.nan)  # acquisition noise level per filter
        # PRIs ignored after a command change: loop latency + IIR transient below settle_db
        ring = 0
        if self.doppler_pole > 0.0:
            ring = math.ceil(self.settle_db / (-20.0 * math.log10(self.doppler_pole)))
        self._settle_pris = self.latency_pris + ring
        # dwell accumulator and counters
        self._acc = np.zeros((N_BINS, N_DOPPLER))
        self._n_seen = 0
        self._bad = False
        self._settle = self._settle_pris
        self._stall = 0
        # outputs / shared state
        self.mode = ACQUISITION
        self._pri_idx = self.acq_pri_index - 1
        self._gate = 0.0
        self._offset = 0.0
        self._doppler = self.doppler_search_centre
        self._threshold = math.nan
        self._noise = math.nan
        self._detection = False
        self._dwell_done = False
        self._resolved_bin = -1
        self._bw = self.bw_start
        self._alpha = 0.0
        self._beta = 0.0
        self._lambda = math.nan
        self._gains_key: tuple[float, float] = (math.nan, math.nan)
        self._gains = (0.0, 0.0)
        # maneuver
        self._maneuver = False
        self._since_maneuver = math.inf
        # tracking bookkeeping
        self._conf_time = 0.0
        self._misses = 0
        self._last_range = math.nan
        self._last_rate = math.nan
        self._doppler_base = self._doppler  # track (or tentative filter) Doppler [Hz]
        self._doppler_bias = 0.0  # discriminator correction added to the base [Hz]
        # tentative state
        self._tent_steps = 0
        self._order: list[int] = []
        self._order_pos = 0
        self._meas: list[tuple[int, int]] = []
        self._cands = np.zeros(0, dtype=np.int64)
        self._windows: list[tuple[int, int]] = []  # (apparent centre bin, hypothesis true bin)
        self._win_pos = 0
        self._cycles = 0
        self._confirming = False
        self._hits = 0
        self._nmiss = 0
        self._filter_energy = np.zeros(N_DOPPLER)
        # acquisition search
        self._search_centre_true = self.designation_range
        self._search: list[int] = []
        self._search_pos = 0
        self._enter_acquisition(self.designation_range)
        self._settle = self._settle_pris

    # ------------------------------------------------------------------------------ helpers
    @property
    def _k(self) -> int:
        return self._ks[self._pri_idx]

    @property
    def pri(self) -> float:
        """Current PRI [s]."""
        return self._pris[self._pri_idx]

    def _command(self, gate_bin: int, pri_idx: int, offset_bins: int) -> None:
        """Set gate (apparent bin of the gate centre), PRI and offset; restart the dwell."""
        changed = (gate_bin * BIN_M != self._gate or pri_idx != self._pri_idx
                   or offset_bins * BIN_M != self._offset)
        self._gate = gate_bin * BIN_M
        self._pri_idx = pri_idx
        self._offset = offset_bins * BIN_M
        self._restart_dwell(settle=changed)

    def _restart_dwell(self, settle: bool = True) -> None:
        self._acc.fill(0.0)
        self._n_seen = 0
        self._bad = False
        self._stall = 0
        if settle:
            self._settle = self._settle_pris

    def _enter_acquisition(self, centre_true: float) -> None:
        """Mode 0: search windows around ``centre_true`` [m] folded modulo the acquisition Ru."""
        self.mode = ACQUISITION
        self._search_centre_true = centre_true
        idx = self.acq_pri_index - 1
        k = self._ks[idx]
        step = self.search_step_bins
        if 2.0 * self.search_extent >= k * BIN_M:
            n_side = math.ceil(0.5 * k / step)
        else:
            n_side = math.ceil(self.search_extent / BIN_M / step)
        offs = [0]
        for i in range(1, n_side + 1):
            offs += [i * step, -i * step]
        d = amb.range_to_bin(centre_true) % k
        self._search = [(d + o) % k for o in offs]
        self._search_pos = 0
        self._resolved_bin = -1
        self._confirming = False
        self._command(self._search[0], idx, 0)
        self._settle = self._settle_pris
        self._doppler = self.doppler_search_centre

    def _enter_tentative(self, m0: int) -> None:
        """Mode 1 from an acquisition detection at apparent bin ``m0`` of the current PRI."""
        self.mode = TENTATIVE
        self._tent_steps = 0
        first = self._pri_idx
        self._order = [first] + [i for i in range(3) if i != first]
        self._order_pos = 0
        self._meas = []
        self._cands = amb.candidates(m0, self._k, self._max_bin, self.tol_bins)
        self._filter_energy.fill(0.0)
        self._confirming = False
        self._start_pri_search()

    def _prior_bin(self) -> int:
        return amb.range_to_bin(self._search_centre_true)

    def _start_pri_search(self) -> None:
        """Hypothesis windows for the PRI ``self._order[self._order_pos]``."""
        idx = self._order[self._order_pos]
        k = self._ks[idx]
        prior = self._prior_bin()
        app = np.mod(self._cands, k)
        order = np.argsort(app, kind="stable")
        windows: list[tuple[int, int, int]] = []  # (priority, centre bin, hypothesis bin)
        i = 0
        n = order.size
        while i < n:
            j = i
            start = int(app[order[i]])
            while j + 1 < n and int(app[order[j + 1]]) - start <= 2:
                j += 1
            members = self._cands[order[i : j + 1]]
            centre = (start + int(app[order[j]])) // 2
            dist = np.abs(members - prior)
            best = int(members[int(np.argmin(dist))])
            windows.append((int(dist.min()), centre, best))
            i = j + 1
        windows.sort()
        self._windows = [(c, b) for _, c, b in windows]
        self._win_pos = 0
        self._cycles = 0
        self._goto_window()

    def _goto_window(self) -> None:
        idx = self._order[self._order_pos]
        k = self._ks[idx]
        centre, hyp = self._windows[self._win_pos]
        self._command(centre, idx, hyp - (hyp % k))

    def _enter_confirmed(self) -> None:
        self.mode = CONFIRMED
        self._conf_time = 0.0
        self._misses = 0
        f = int(np.argmax(self._filter_energy))
        spacing = self.doppler_spacing_fraction / self.pri
        self._doppler = fold_doppler(self.doppler_search_centre + (f - _CF) * spacing, self.pri)
        self._doppler_base = self._doppler
        self._doppler_bias = 0.0
        self._last_range = self._gate + self._offset
        self._restart_dwell(settle=True)

    # ----------------------------------------------------------------------------- dwell ends
    def _factors(self, pfa: float, which: int) -> np.ndarray:
        """Threshold factors per Doppler filter for the current dwell (``which``: 0 = /median,
        1 = /mean): the exact thermal-noise ratio (:func:`dwell_sum_factors`) for every filter,
        except, with ``adaptive_looks``, a clutter-dominated filter (measured looks
        L_f = φ_f·looks_per_pri·K below ``_CLUTTER_LOOKS_FRACTION`` of the thermal model's
        variance-matched looks): iid Rayleigh-sum ratio at L_f rounded down on the grid (never
        below the thermal ratio). See *Thresholds* in the module docstring."""
        k = self._dwell_length()
        thermal = dwell_sum_factors(self.looks_per_pri, k, self.doppler_pole, pfa)[which]
        out = np.full(N_DOPPLER, thermal)
        if not self.adaptive_looks:
            return out
        n = self.looks_per_pri * k
        l_thermal = dwell_sum_looks(self.looks_per_pri, k, self.doppler_pole)
        phi = _IQR2 / self._spread**2
        for f, p in enumerate(phi):
            lf = min(float(n), max(1.0, p * n))
            if lf < _CLUTTER_LOOKS_FRACTION * l_thermal:
                out[f] = max(thermal, rayleigh_sum_factors(grid_looks_floor(lf), pfa)[which])
        return out

    def _update_shape(self, cells: np.ndarray) -> None:
        """EMA of the normalised spread (IQR/median)·√n of ``cells`` (m, 3), n the looks of an
        uncorrelated dwell; the effective looks are L_f = 0.705²·n/spread_f².

        # assumption: a sum of L Rayleigh looks has IQR/median ≈ 0.705/√L; averaging the spread
        # (not its inverse square) over dwells keeps the 16-sample estimate nearly unbiased.
        """
        if not self.adaptive_looks:
            return
        q25, q50, q75 = np.percentile(cells, (25.0, 50.0, 75.0), axis=0)
        n = self.looks_per_pri * self._dwell_length()
        with np.errstate(divide="ignore", invalid="ignore"):
            est = (q75 - q25) / q50 * math.sqrt(n)
        lo = math.sqrt(_IQR2)  # φ ≤ 1
        est = np.clip(np.nan_to_num(est, nan=lo, posinf=lo, neginf=lo), lo, lo * math.sqrt(n))
        self._spread += (est - self._spread) / self.noise_avg_dwells

    def _end_acquisition_dwell(self, ok: bool) -> None:
        if ok:
            # seed 000: accumulated cells compared to Th1; noise level per Doppler filter
            # (assumption: median over the 16 range bins, robust to one target and to clutter
            # confined to a filter), smoothed over dwells
            self._update_shape(self._acc)
            med = np.median(self._acc, axis=0)
            if np.isnan(self._noise_f[0]):
                self._noise_f[:] = med
            else:
                self._noise_f += (med - self._noise_f) / self.noise_avg_dwells
            th = self._factors(self.pfa_acq, 0) * self._noise_f
            ratio = self._acc / th
            i = int(np.argmax(ratio))
            f = i % N_DOPPLER
            self._noise = float(self._noise_f[f])
            self._threshold = float(th[f])
            if ratio.flat[i] > 1.0:
                # seed 000: "the target is declared present in the cell providing the largest
                # number" among the cells above Th1
                i = int(np.argmax(np.where(ratio > 1.0, self._acc, -np.inf)))
                self._threshold = float(th[i % N_DOPPLER])
                self._detection = True
                r = i // N_DOPPLER
                m0 = (amb.range_to_bin(self._gate) + r - _C) % self._k
                self._enter_tentative(m0)
                return
        self._search_pos = (self._search_pos + 1) % len(self._search)
        self._command(self._search[self._search_pos], self._pri_idx, 0)

    def _track_test(self, filters: slice) -> tuple[int, int]:
        """Th2 test (seed 000: "target present" from the central range bins 6-8, Th2 from the
        ambient noise of the side range bins), per Doppler filter in ``filters``.

        Returns the 0-based (bin, filter) of the largest central cell relative to its filter's
        Th2, or (−1, −1) if none exceeds it; sets ``threshold`` / ``noise.level``.
        """
        acc = self._acc[:, filters]
        self._update_shape(self._acc[_SIDE])
        noise = acc[_SIDE].mean(axis=0)
        th = self._factors(self.pfa_track, 1)[filters] * noise
        ratio = acc[_CENTRAL] / th
        i = int(np.argmax(ratio))
        j, f = divmod(i, ratio.shape[1])
        self._noise = float(noise[f])
        self._threshold = float(th[f])
        f += filters.start or 0
        if ratio.flat[i] > 1.0:
            self._detection = True
            return _C - 1 + j, f
        return -1, -1

    def _end_tentative_dwell(self, ok: bool) -> None:
        r = -1
        if ok:
            r, f = self._track_test(slice(0, N_DOPPLER))
            if r >= 0:
                self._filter_energy[f] += 1.0
        if self._confirming:
            if r >= 0:
                self._hits += 1
            else:
                self._nmiss += 1
            if self._hits >= self.confirm_m:
                self._enter_confirmed()
            elif self._nmiss > self.confirm_n - self.confirm_m:
                self._enter_acquisition(self._search_centre_true)
            else:
                self._restart_dwell(settle=False)
            return
        idx = self._order[self._order_pos]
        k = self._ks[idx]
        if r >= 0:
            m = (amb.range_to_bin(self._gate) + r - _C) % k
            self._meas.append((k, m))
            self._cands = amb.consistent(self._cands, m, k, self.tol_bins)
            if self._cands.size == 0:
                self._enter_acquisition(self._search_centre_true)
                return
            self._order_pos += 1
            if self._order_pos < 3:
                self._start_pri_search()
                return
            b = amb.resolve_bins([mm for _, mm in self._meas], [kk for kk, _ in self._meas],
                                 self._max_bin, self.tol_bins)
            if b is None:
                self._enter_acquisition(self._search_centre_true)
                return
            self._resolved_bin = b
            self._search_centre_true = b * BIN_M
            if self.confirm_pri_index == 0:
                margins = [min(b % kk, kk - b % kk) for kk in self._ks]
                ci = int(np.argmax(margins))
            else:
                ci = self.confirm_pri_index - 1
            kc = self._ks[ci]
            self._confirming = True
            self._hits = 0
            self._nmiss = 0
            self._command(b % kc, ci, b - b % kc)
            return
        self._win_pos += 1
        if self._win_pos >= len(self._windows):
            self._win_pos = 0
            self._cycles += 1
            if self._cycles >= self.tent_window_cycles:
                self._enter_acquisition(self._search_centre_true)
                return
        self._goto_window()

    def _end_confirmed_dwell(self, ok: bool) -> None:
        r = -1
        if ok:
            r, _ = self._track_test(slice(_CF, _CF + 1))
        self._misses = 0 if r >= 0 else self._misses + 1
        if self._misses >= self.miss_limit:
            centre = self._last_range if math.isfinite(self._last_range) else (
                self._gate + self._offset)
            self._enter_acquisition(min(max(centre, 0.0), self.max_range))
            return
        self._follow_doppler(ok)
        self._restart_dwell(settle=False)

    def _follow_doppler(self, ok: bool) -> None:
        """Confirmed-mode Doppler centre (seed 000: "the Doppler frequency is calculated by the
        Radar Manager and only the central Doppler filter is used"): base = the tentative
        filter's centre, then, after ``doppler_track_delay``, fold(−2ṙ/λ) from the track range
        rate (radar.py convention); plus a bias closed on the measured Doppler offset of the
        target (:func:`doppler_offset`), bias += ``doppler_loop_gain``·offset per dwell. The
        bias absorbs what the track range rate lags under acceleration (α-β lag ≈ a·T·α/β),
        which would otherwise slide the target out of the narrow central filter.
        """
        prf = 1.0 / self.pri
        # pole 0: the filters have no frequency selectivity, nothing to discriminate
        if ok and self.doppler_loop_gain > 0.0 and self.doppler_pole > 0.0:
            acc = self._acc
            noise = acc[_SIDE].mean(axis=0)
            excess = acc[_CENTRAL].sum(axis=0) - (_CENTRAL.stop - _CENTRAL.start) * noise
            f = int(np.argmax(excess / np.maximum(noise, 1e-300)))
            # a clutter filter's level is nearly constant over a dwell and does not average
            # out, so its excess is unreliable; with one side filter left out the two-filter
            # amplitude ratio no longer tells the sign of the offset: the bias is held while
            # any filter's side-bin level exceeds doppler_disc_clutter × the quietest filter's
            # (e.g. while the target crosses the clutter Doppler)
            clean = noise.max() <= self.doppler_disc_clutter * noise.min()
            if clean and excess[f] > self.doppler_disc_snr * noise[f]:
                d = doppler_offset(excess, self.doppler_spacing_fraction, self.doppler_pole)
                self._doppler_bias = fold_doppler(
                    self._doppler_bias + self.doppler_loop_gain * d * prf, self.pri)
        if self._conf_time >= self.doppler_track_delay and math.isfinite(self._last_rate):
            self._doppler_base = fold_doppler(-2.0 * self._last_rate / self.wavelength, self.pri)
        self._doppler = fold_doppler(self._doppler_base + self._doppler_bias, self.pri)

    # ----------------------------------------------------------------------------------- step
    def _read_sum(self, s: Any) -> np.ndarray | None:
        if s is None:
            return None
        try:
            a = np.asarray(s, dtype=np.float64)
        except (TypeError, ValueError):
            return None
        if a.size != N_BINS * N_DOPPLER:
            return None
        if a.shape != (N_BINS, N_DOPPLER):
            a = a.reshape(N_BINS, N_DOPPLER)
        if not math.isfinite(float(a.sum())):
            return None
        return a

    @staticmethod
    def _finite(x: Any) -> float | None:
        try:
            v = float(x)
        except (TypeError, ValueError):
            return None
        return v if math.isfinite(v) else None

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """Advance one communication step ``dt`` [s] (nominally one PRI); see class docstring."""
        dtv = self._finite(dt)
        dt_eff = dtv if dtv is not None and dtv > 0.0 else self.pri
        self._detection = False
        self._dwell_done = False

        # track inputs (held when non-finite)
        rng = self._finite(inputs.get("track.range"))
        if rng is not None:
            self._last_range = rng
        rate = self._finite(inputs.get("track.range_rate"))
        if rate is not None:
            self._last_rate = rate
        man = inputs.get("maneuver")
        if man is not None:
            mv = self._finite(man)
            if mv is not None:
                self._maneuver = mv != 0.0
        if self._maneuver:
            self._since_maneuver = 0.0
        else:
            self._since_maneuver += dt_eff

        if self.mode == TENTATIVE:
            self._tent_steps += 1
        elif self.mode == CONFIRMED:
            self._conf_time += dt_eff
            if rng is not None:
                self._gate = rng - self._offset

        # sample
        s = self._read_sum(inputs.get("sum"))
        if self._settle > 0:
            self._settle -= 1
        else:
            gate_ok = True
            if self.mode != CONFIRMED and "gate.start" in inputs:
                gs = self._finite(inputs.get("gate.start"))
                if gs is None:
                    s = None
                else:
                    ru = self._k * BIN_M
                    d = (gs - (self._gate - _C * BIN_M)) % ru
                    gate_ok = min(d, ru - d) <= 0.5 * BIN_M
            if not gate_ok:
                self._stall += 1
                if self._stall >= self.stall_pris:
                    self._n_seen = self._dwell_length()
                    self._bad = True
            else:
                self._n_seen += 1
                if s is None:
                    self._bad = True
                else:
                    np.add(self._acc, s, out=self._acc)
            if self._n_seen >= self._dwell_length():
                self._end_dwell()

        if self.mode == TENTATIVE and self._tent_steps > self.tent_timeout_pris:
            self._enter_acquisition(self._search_centre_true)

        self._update_bandwidth()
        self._update_gains()
        return self._outputs()

    def _dwell_length(self) -> int:
        if self.mode == ACQUISITION:
            return self.dwell_acq
        if self.mode == TENTATIVE:
            return self.dwell_tent
        return self.dwell_conf

    def _end_dwell(self) -> None:
        ok = not self._bad
        self._dwell_done = True
        mode = self.mode
        if mode == ACQUISITION:
            self._end_acquisition_dwell(ok)
        elif mode == TENTATIVE:
            self._end_tentative_dwell(ok)
        else:
            self._end_confirmed_dwell(ok)
        if self._n_seen:  # the handler did not restart the dwell
            self._restart_dwell(settle=False)

    def _update_bandwidth(self) -> None:
        if self.mode != CONFIRMED:
            self._bw = self.bw_start
            return
        if self.bw_decay_time <= 0.0 or self._conf_time >= self.bw_decay_time:
            self._bw = self.bw_floor
            return
        x = self._conf_time / self.bw_decay_time
        self._bw = self.bw_start * (self.bw_floor / self.bw_start) ** x

    def _update_gains(self) -> None:
        opened = self._since_maneuver <= self.maneuver_hold
        sigma_m = self.sigma_man_high if opened else self.sigma_man
        t = self.pri
        key = (sigma_m, t)
        if key != self._gains_key:
            self._gains_key = key
            self._lambda = sigma_m * t * t / self.sigma_meas
            self._gains = kalata_gains(self._lambda)
        # SYSTEM.md: evolutive gains until the manager's steady gains take over. The Tracker
        # (alphabeta.AlphaBeta3.gains) uses max(evolutive(n), steady) per gain, so the steady
        # gains are sent throughout confirmed tracking and the tracker hands over itself when
        # its α(n) falls below them; 0 in acquisition / tentative (evolutive only, seed 000:
        # "Alpha-Beta filters with a short time constant").
        if self.mode != CONFIRMED:
            self._alpha = self._beta = 0.0
        else:
            self._alpha, self._beta = self._gains

    def outputs(self) -> dict[str, Any]:
        """Current outputs (at the initial state right after reset)."""
        return self._outputs()

    def _outputs(self) -> dict[str, Any]:
        return {
            "mode": self.mode,
            "pri": self.pri,
            "alpha": self._alpha,
            "beta": self._beta,
            "bandwidth": self._bw,
            "range.offset": self._offset,
            "gate.command": self._gate - _C * BIN_M,
            "doppler.centre": self._doppler,
            "threshold": self._threshold,
            "noise.level": self._noise,
            "detection": self._detection,
            "dwell.done": self._dwell_done,
            "ambiguity.resolved": self._resolved_bin >= 0,
            "range.resolved": self._resolved_bin * BIN_M if self._resolved_bin >= 0 else math.nan,
            "tracking.index": self._lambda,
        }
