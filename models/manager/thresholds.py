"""Threshold statistics of the radar manager (seed 000: Th1 in acquisition, Th2 in tentative
and confirmed tracking): exact dwell-sum law of the Doppler-filtered noise, iid Rayleigh sums,
and the clutter-aware (adaptive-looks) factors per Doppler filter.

A SUM cell of a dwell is S = Σ_{b ≤ 4} Σ_{n ≤ K} |y_{b,n}|, y the output of a
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

*Partly cluttered filters* (issue 11): with the Doppler steps (:mod:`.doppler_search`) filters
sit a few hundred Hz from the clutter line, where clutter and noise are comparable; a filter
whose level exceeds the thermal floor (the manager passes ``excess``) gets at least
:func:`clutter_noise_factor`, the exact ratio of a power-additive clutter (one Rayleigh look
per dwell) + thermal law fitted to its IQR/median (docs/doppler_coverage.md: 3.8 % per dwell
measured at a design of 4.7 %, 12 % without it).

The manager's state machine (:mod:`.machine`) keeps the per-filter spread estimate
(:func:`initial_spread`, :func:`update_spread`, per Doppler position class) and asks
:func:`threshold_factors` for the factors of the current dwell.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..radar.conventions import N_DOPPLER

# Looks at which iid Rayleigh-sum factors are computed (estimates are rounded down onto it).
_LOOKS_GRID = np.array([1, 2, 3, 4, 5, 6, 7, 8, 10, 12, 14, 16, 20, 24, 28, 32, 40, 48, 56, 64,
                        80, 96, 112, 128, 160, 192, 224, 256, 320, 384, 448, 512, 640, 768, 896,
                        1024, 1536, 2048, 3072, 4096, 6144, 8192, 12288, 16384])
# (IQR/median)² of a sum of L Rayleigh looks ≈ IQR2 / L (Gaussian limit 1.349·0.5227 = 0.705;
# 0.770 at L = 1, so L is under-estimated by ≤ 16 % for single looks).
IQR2 = 0.705**2
# Clutter switch (adaptive_looks): a Doppler filter whose measured looks fall below this
# fraction of the thermal-noise model's is treated as clutter-dominated (see Thresholds).
CLUTTER_LOOKS_FRACTION = 0.5
# Envelope Markov chain grid: magnitudes up to _R_MAX (E|y|² = 1: P(|y| > 7.5) = e^−56),
# step ≤ 0.04 and ≤ 1/5 of the Rice kernel's σ, at most _NR_MAX cells; exact chain while
# dwell·cells ≤ _CHAIN_BUDGET, else the variance-matched fallback.
_R_MAX = 7.5
_NR_MAX = 400
_CHAIN_BUDGET = 60_000


def grid_looks_floor(L: float) -> int:
    """Largest entry of the threshold-factor grid ≤ ``L`` (1 at least): conservative looks."""
    i = int(np.searchsorted(_LOOKS_GRID, max(1.0, L) * (1.0 + 1e-12), side="right")) - 1
    return int(_LOOKS_GRID[max(i, 0)])


def envelope_correlation(gamma: float) -> float:
    """Correlation coefficient of |x| and |y| for circular complex Gaussians x, y of complex
    correlation coefficient of modulus ``gamma``: (₂F₁(−½, −½; 1; γ²) − 1)/(4/π − 1)
    (exact; ≈ 0.915·γ² for small γ, 1 at γ = 1)."""
    from scipy.special import hyp2f1

    return float((hyp2f1(-0.5, -0.5, 1.0, gamma * gamma) - 1.0) / (4.0 / math.pi - 1.0))


@lru_cache(maxsize=128)
def dwell_sum_looks(looks_per_pri: int, dwell: int, pole: float) -> float:
    """Variance-matched looks of the dwell sum S = Σ_beams Σ_{n<K} |y_n| (exact moments):
    L_var = looks·K / (1 + 2 Σ_{k=1}^{K−1} (1 − k/K) r(ρ^k)), r = :func:`envelope_correlation`
    (9.8 for the default 4 beams, K = 16, ρ = 0.9). Cached: a pure function of its arguments,
    asked at every dwell end (issue 14)."""
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


def _quantile_ratios(pmf: np.ndarray, offset: float, h: float, mean: float, pfa: float,
                     interpolate_median: bool = True) -> tuple[float, float]:
    """(q/median, q/mean) of a lattice law: mass pmf[i] at value (i + offset)·h; q is the
    (1 − pfa) quantile, the survival function interpolated linearly between lattice points;
    the median is interpolated likewise on the CDF, or (``interpolate_median`` False) the
    first lattice point where the CDF reaches ½."""
    sf = np.cumsum(pmf[::-1])[::-1]  # P(X ≥ value_i)
    cdf = 1.0 - sf + pmf  # P(X ≤ value_i)
    n = pmf.size
    i = int(np.searchsorted(-sf, -pfa, side="left"))  # first i with sf[i] ≤ pfa
    i = min(max(i, 1), n - 1)
    s0, s1 = sf[i - 1], sf[i]
    frac = 0.0 if s0 == s1 else (s0 - pfa) / (s0 - s1)
    q = (i - 1 + frac + offset) * h
    j = int(np.searchsorted(cdf, 0.5))
    if not interpolate_median:
        return q / ((j + offset) * h), q / mean
    c0 = cdf[j - 1] if j > 0 else 0.0
    frac_m = 0.0 if cdf[j] == c0 else (0.5 - c0) / (cdf[j] - c0)
    median = (j - 1 + frac_m + offset) * h
    return q / median, q / mean


@lru_cache(maxsize=128)
def rayleigh_sum_factors(looks: int, pfa: float) -> tuple[float, float]:
    """Threshold ratios for a sum of ``looks`` iid Rayleigh magnitudes.

    Returns ``(q/median, q/mean)`` where ``q`` is the (1 − ``pfa``) quantile of the sum. The
    density of the sum is the ``looks``-fold convolution of the Rayleigh density (computed by FFT
    on a 2¹⁶-point grid extending 20 standard deviations past the mean); both ratios are scale
    free (independent of σ). The median is the lattice point where the CDF reaches ½ (not
    interpolated, unlike :func:`dwell_sum_factors`).
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
    return _quantile_ratios(pl, 0.5 * L, h, L * mean1, pfa, interpolate_median=False)


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
    return _quantile_ratios(pl, 0.5 * looks_per_pri * dwell, h, mean, pfa)


def initial_spread(looks_per_pri: int, dwell: int, pole: float) -> np.ndarray:
    """Model value of the per-filter normalised spread s_f = (IQR/median)·√(looks_per_pri·K)
    = 0.705/√φ, φ the independent fraction of the dwell's looks (from ``pole``), for every
    Doppler filter: the start of the :func:`update_spread` estimate."""
    phi0 = dwell_sum_looks(looks_per_pri, dwell, pole) / (looks_per_pri * dwell)
    return np.full(N_DOPPLER, math.sqrt(IQR2 / phi0))


def update_spread(spread: np.ndarray, cells: np.ndarray, looks: int, avg_dwells: float,
                  est: np.ndarray | None = None) -> None:
    """EMA (``avg_dwells`` dwells, in place) of the normalised spread (IQR/median)·√n of
    ``cells`` (m, 3), n = ``looks`` of an uncorrelated dwell; the effective looks are
    L_f = 0.705²·n/spread_f². ``est``: :func:`spread_estimate` of these cells, when the
    caller already has it (issue 14: one percentile per dwell).

    # assumption: a sum of L Rayleigh looks has IQR/median ≈ 0.705/√L; averaging the spread
    # (not its inverse square) over dwells keeps the 16-sample estimate nearly unbiased.
    """
    if est is None:
        est = spread_estimate(cells, looks)
    spread += (est - spread) / avg_dwells


def _quartiles(cells: np.ndarray) -> np.ndarray:
    """``np.percentile(cells, (25, 50, 75), axis=0)`` (linear interpolation). When the
    quartile positions q·(m − 1) are whole numbers (m = 9 side bins: 2, 4, 6) and the cells
    finite, the percentiles are the order statistics themselves (interpolation weight 0), read
    from one sort (issue 14: np.percentile's overhead at every dwell end)."""
    m = cells.shape[0]
    if m % 4 == 1 and np.isfinite(cells).all():
        s = cells.copy(order="K")  # np.sort(cells, axis=0) without its Python wrapper
        s.sort(axis=0)
        return s[[(m - 1) // 4, (m - 1) // 2, 3 * (m - 1) // 4]]
    return np.percentile(cells, (25.0, 50.0, 75.0), axis=0)


def _spread_columns(cells: np.ndarray, looks: int) -> np.ndarray | None:
    """:func:`spread_estimate` in Python floats, column by column (issue 14, session 8: the
    dwell end's ≈ 10 numpy calls on (3,) arrays and the ``errstate`` context cost ≈ 12 µs).
    Only for m = 4j + 1 rows of finite cells, where the quartiles are order statistics (as
    :func:`_quartiles`); None otherwise (the caller takes the numpy path). The same IEEE
    operations per filter: (q75 − q25)/q50·√n, a non-finite value (q50 = 0) → lo, then
    max(·, lo) and min(·, lo·√n); Python's sort gives the same order statistics as numpy's."""
    m = cells.shape[0]
    if m % 4 != 1 or cells.ndim != 2:
        return None
    i1, i2, i3 = (m - 1) // 4, (m - 1) // 2, 3 * (m - 1) // 4
    sq = math.sqrt(looks)
    lo = math.sqrt(IQR2)
    hi = lo * sq
    isfinite = math.isfinite
    out = []
    for col in cells.T.tolist():
        if not isfinite(sum(col)):  # a NaN/inf cell (or an overflowing sum): numpy path
            return None
        col.sort()
        q50 = col[i2]
        e = (col[i3] - col[i1]) / q50 * sq if q50 != 0.0 else lo  # x/0: inf or NaN → lo
        if not isfinite(e):
            e = lo
        out.append(min(max(e, lo), hi))
    return np.array(out)


def spread_estimate(cells: np.ndarray, looks: int) -> np.ndarray:
    """One dwell's normalised spread (IQR/median)·√n per Doppler filter of ``cells`` (m, 3),
    n = ``looks``, clipped to [0.705, 0.705·√n] (non-finite → 0.705): the sample that
    :func:`update_spread` averages."""
    fast = _spread_columns(cells, looks)
    if fast is not None:
        return fast
    q25, q50, q75 = _quartiles(cells)
    n = looks
    with np.errstate(divide="ignore", invalid="ignore"):
        est = (q75 - q25) / q50 * math.sqrt(n)
    lo = math.sqrt(IQR2)  # φ ≤ 1
    # issue 14: np.clip(np.nan_to_num(est, nan=lo, posinf=lo, neginf=lo), lo, lo·√n) without
    # the two Python wrappers (the same values: non-finite → lo, then max/min of finite floats)
    est[~np.isfinite(est)] = lo
    return np.minimum(np.maximum(est, lo), lo * math.sqrt(n))


def threshold_factors(looks_per_pri: int, dwell: int, pole: float, pfa: float, which: int,
                      spread: np.ndarray | list[float] | None,
                      excess: np.ndarray | list[bool] | None = None,
                      common: np.ndarray | list[bool] | None = None) -> np.ndarray:
    """Threshold factors per Doppler filter for a dwell of ``dwell`` PRIs (``which``: 0 =
    /median, 1 = /mean): the exact thermal-noise ratio (:func:`dwell_sum_factors`) for every
    filter, except, given the ``spread`` estimate (``adaptive_looks``; None: thermal model
    only), a clutter-dominated filter (measured looks L_f = φ_f·looks_per_pri·K below
    ``CLUTTER_LOOKS_FRACTION`` of the thermal model's variance-matched looks): iid
    Rayleigh-sum ratio at L_f rounded down on the grid (never below the thermal ratio); and a
    filter flagged in ``excess`` (level above the thermal floor): at least
    :func:`clutter_noise_factor` of its spread (issue 11); a filter flagged in ``common``
    (level far above the thermal level: clutter residue after the MTI canceller, which is
    white, like the thermal noise, but the same signal in every beam): at least the exact
    dwell-sum ratio with ONE independent look per PRI, ``dwell_sum_factors(1, …)``
    (:func:`common_mode_factor`)."""
    # issue 14 (session 8): per filter in Python floats (the same IEEE operations as the
    # former (3,)-array code: max of the thermal and common-mode ratios, φ = IQR2/(s·s)),
    # made one array at the end
    k = dwell
    thermal = dwell_sum_factors(looks_per_pri, k, pole, pfa)[which]
    floor = [thermal] * N_DOPPLER  # the thermal or common-mode ratio: never lowered below
    if common is not None and any(common):
        cm = common_mode_factor(k, pole, pfa, which)
        floor = [max(thermal, cm) if c else thermal for c in common]
    if spread is None:
        return np.array(floor)
    out = list(floor)
    n = looks_per_pri * k
    l_thermal = dwell_sum_looks(looks_per_pri, k, pole)
    clutter_looks = CLUTTER_LOOKS_FRACTION * l_thermal
    for f, s in enumerate(spread.tolist() if isinstance(spread, np.ndarray) else spread):
        p = IQR2 / (s * s)
        lf = min(float(n), max(1.0, p * n))
        if lf < clutter_looks:
            out[f] = max(floor[f], rayleigh_sum_factors(grid_looks_floor(lf), pfa)[which])
        # partly clutter-dominated filters (issue 11: the Doppler steps put filters a few
        # hundred Hz from the clutter line, their level above the thermal floor): power-additive
        # clutter + noise law, never below the thermal ratio
        if excess is not None and excess[f]:
            r = s / math.sqrt(n)
            out[f] = max(out[f], clutter_noise_factor(r, pfa, which))
    return np.array(out)


def common_mode_factor(dwell: int, pole: float, pfa: float, which: int) -> float:
    """Threshold ratio (q/median for ``which`` 0, q/mean for 1) of a dwell sum dominated by a
    white process common to the beams: the MTI canceller's clutter residue (issue 11,
    docs/clutter.md). The AR(1) clutter c[n] = ρc c[n−1] + u[n] through the two-pulse
    canceller is ≈ the innovation u (white, CNR·(1 − ρc) per pulse: 9.7 dB at CNR 30 dB),
    so each beam's filter output has the envelope law of filtered white noise, but the 4 beams
    carry the same signal: the SUM has one look per PRI, not ``looks_per_pri``. Exact law of
    :func:`dwell_sum_factors` with one look (3.23 × median at Pfa 1e-5, K = 16, ρ = 0.9,
    against 1.92 for 4 independent beams; measured in the direct loop at 1° elevation,
    MTI on, target-free: the 0.3 % per-cell quantile of the acquisition cells is 2.3 ×
    median, the one-look law's 2.33)."""
    return dwell_sum_factors(1, dwell, pole, pfa)[which]


#: −ln(1 − p) − ln 2 at the midpoints p = (i + ½)/4000 of :func:`clutter_noise_factor`'s
#: quadrature of E[X]/median (constant: computed once, issue 14)
_MEAN_NODES = -np.log1p(-((np.arange(4000) + 0.5) / 4000)) - math.log(2.0)


def clutter_noise_factor(r: float, pfa: float, which: int) -> float:
    """Threshold factor (q/median for ``which`` 0, q/mean for 1) of a cell X with
    X² = A² + B²·R², R Rayleigh (σ = 1): power-additive thermal part (A², constant over the
    dwell) and slowly fluctuating clutter (one Rayleigh look per dwell: it decorrelates in
    ≈ 100 PRIs), fitted to the measured IQR/median ``r`` of the cells (designer's model,
    issue 11). With u = B²/median²: X_p/median = √(1 + 2u·(ln(1/(1 − p)) − ln 2)) for the
    p-quantile; u solves r = √(1 + 2u ln 2) − √(1 − 2u ln 1.5) (bisection, u ≤ 1/(2 ln 2):
    A² ≥ 0; r ≥ 0.770, the pure Rayleigh value, gives the one-look ratio
    √(ln(1/Pfa)/ln 2)); exact P(X > q) = Pfa for that law. The mean uses E[X] by quadrature."""
    ln2, ln15 = math.log(2.0), math.log(1.5)
    u_max = 0.5 / ln2

    def iqr(u: float) -> float:
        return math.sqrt(1.0 + 2.0 * u * ln2) - math.sqrt(max(1.0 - 2.0 * u * ln15, 0.0))

    lo, hi = 0.0, u_max
    if r >= iqr(u_max):
        lo = hi
    else:
        sqrt = math.sqrt
        for _ in range(60):  # issue 14 (session 8): iqr(mid) inlined, the same operations
            mid = 0.5 * (lo + hi)
            if sqrt(1.0 + 2.0 * mid * ln2) - sqrt(max(1.0 - 2.0 * mid * ln15, 0.0)) < r:
                lo = mid
            else:
                hi = mid
    u = 0.5 * (lo + hi)
    q = math.sqrt(1.0 + 2.0 * u * (math.log(1.0 / pfa) - ln2))
    if which == 0:
        return q
    # E[X]/median by the quantile function (midpoint rule, 4000 points: _MEAN_NODES)
    mean = float(np.mean(np.sqrt(np.maximum(1.0 + 2.0 * u * _MEAN_NODES, 0.0))))
    return q / mean
