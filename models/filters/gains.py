"""Gain laws of the α-β (g-h) filter: evolutive gains, Kalata's steady gains, their schedule.

Sources
-------
- seed 000 "Evolutive coefficients": α(n) = 2(2n − 1)/(n(n + 1)), β(n) = 6/(n(n + 1)),
  n = 1, 2, … — exactly the recursive least-squares straight-line fit for uniform sampling
  (SYSTEM.md; filterpy ``least_squares_parameters(n − 1)``).
- Kalata, P. R. (1984), "The tracking index: a generalized parameter for α-β and α-β-γ target
  trackers", IEEE Trans. Aerospace and Electronic Systems AES-20(2), 174-182: steady-state
  α-β gains of the Kalman filter for the constant-velocity model with piecewise-constant
  (discrete white-noise) acceleration of standard deviation σ_w and position noise σ_n, as a
  function of the tracking index Λ = σ_w T²/σ_n.
- Brookner, E. (1998), "Tracking and Kalman Filtering Made Easy", Wiley, eq. (1.2-19): variance
  reduction ratio of the one-step prediction of a g-h filter in white measurement noise,
  σ²(x̂ₙ₊₁,ₙ)/σ² = (2g² + 2h + gh)/(g(4 − 2g − h)).

Used by the α-β filter (:mod:`.alphabeta`) and by the radar manager (Kalata's steady gains).
"""

from __future__ import annotations

import math


def evolutive_gains(n: int) -> tuple[float, float]:
    """Evolutive gains (α(n), β(n)) for the n-th measurement, n = 1, 2, … [1].

    # seed 000 "Evolutive coefficients": α(n) = 2(2n−1)/(n(n+1)), β(n) = 6/(n(n+1))
    """
    if n < 1:
        raise ValueError(f"evolutive_gains: n = {n} must be >= 1")
    den = n * (n + 1.0)
    return 2.0 * (2.0 * n - 1.0) / den, 6.0 / den


def prior_gains(n: int, q: float) -> tuple[float, float]:
    """Gains (α, β) [1] for the n-th measurement of the least-squares straight-line fit with a
    prior on the velocity: the Kalman gains of the two-state model without process noise for
    a flat prior on the position and a velocity prior of variance σv², with n measurements of
    variance r a sample interval T apart, q = r/(σv² T²) [1] (issue 11, session 17).

    Batch form (the recursive gains equal those of the batch posterior after n samples): ages
    k = 0 … n − 1, information (r units) [[n, −T·S1], [−T·S1, T²(S2 + q)]] with S1 = Σk =
    n(n − 1)/2, S2 = Σk² = (n − 1)n(2n − 1)/6; the gain of the newest sample is the first
    column of its inverse: α = (S2 + q)/D, β = T·K_v = S1/D, D = n(S2 + q) − S1² =
    n²(n² − 1)/12 + n·q. q = 0 gives seed 000's evolutive gains (:func:`evolutive_gains`); a
    first measurement sets the position and leaves the velocity (α = 1, β = 0).
    """
    if n < 1:
        raise ValueError(f"prior_gains: n = {n} must be >= 1")
    m = float(n)
    if q == math.inf:  # T = 0: the samples carry no velocity information, their mean
        return 1.0 / m, 0.0
    den = m * m * (m * m - 1.0) / 12.0 + m * q
    if not den > 0.0:  # n = 1 with q = 0: the seed's α(1) = 1 (β(1) = 6/2 multiplies ν = 0)
        return evolutive_gains(n)
    return ((m - 1.0) * m * (2.0 * m - 1.0) / 6.0 + q) / den, 0.5 * m * (m - 1.0) / den


def prior_q(k: float, T: float) -> float:
    """q = k/T² [1] of :func:`prior_gains` for ``k`` = r/σv² [s²] and the interval T [s]; inf
    for T = 0 (or T² below the smallest float); 0 (no prior) for k = 0."""
    if not k > 0.0:
        return 0.0
    t2 = T * T
    return k / t2 if t2 > 0.0 else math.inf


def tracking_index(sigma_accel: float, T: float, sigma_meas: float) -> float:
    """Kalata's tracking index Λ = σ_w T² / σ_n [1] (Kalata 1984).

    Args:
        sigma_accel: σ_w, standard deviation of the target acceleration (piecewise constant over
            a sample interval) [m/s²].
        T: sample interval [s].
        sigma_meas: σ_n, standard deviation of the position measurement noise [m].
    """
    if sigma_meas <= 0.0 or T <= 0.0 or sigma_accel < 0.0:
        raise ValueError("tracking_index: need sigma_meas > 0, T > 0, sigma_accel >= 0")
    return sigma_accel * T * T / sigma_meas


def kalata_gains(lam: float) -> tuple[float, float]:
    """Steady-state α-β gains (α, β) [1] for the tracking index Λ = ``lam`` (Kalata 1984).

    Kalata's closed form, α = −(Λ² + 8Λ − (Λ + 4)√(Λ² + 8Λ))/8,
    β = (Λ² + 4Λ − Λ√(Λ² + 8Λ))/4, is evaluated through the damping parameter
    r = √(1 − α) = (4 + Λ − √(Λ² + 8Λ))/4 (root of 2r² − (4 + Λ)r + 2 = 0), computed as
    r = 4/(4 + Λ + √(Λ² + 8Λ)) to avoid cancellation for small Λ; then
    α = 1 − r², β = 2(1 − r)². These satisfy Kalata's relations Λ² = β²/(1 − α) and
    β = 2(2 − α) − 4√(1 − α) (the Kalman steady state of the discrete white-noise acceleration
    model; note they are *not* the Benedict-Bordner pair β = α²/(2 − α), which minimises a
    different criterion — the two differ by a few percent).
    """
    if not (lam >= 0.0 and math.isfinite(lam)):
        raise ValueError(f"kalata_gains: tracking index {lam!r} must be finite and >= 0")
    s = math.sqrt(lam * lam + 8.0 * lam)
    one_minus_r = (lam + s) / (4.0 + lam + s)
    r = 1.0 - one_minus_r
    return one_minus_r * (1.0 + r), 2.0 * one_minus_r * one_minus_r


def prediction_vrr(alpha: float, beta: float) -> float:
    """One-step prediction variance reduction ratio of a steady α-β filter [1].

    σ²(pred)/σ² = (2α² + 2β + αβ)/(α(4 − 2α − β)) for white measurement noise of variance σ²
    and no target maneuver (Brookner 1998, eq. 1.2-19). Infinite outside the stability region
    0 < α < 2, 0 < β < 4 − 2α.
    """
    den = alpha * (4.0 - 2.0 * alpha - beta)
    if alpha <= 0.0 or beta <= 0.0 or den <= 0.0:
        return math.inf
    return (2.0 * alpha * alpha + 2.0 * beta + alpha * beta) / den


def stable_gains(alpha: float, beta: float) -> bool:
    """True when (α, β) are finite and inside the α-β stability triangle (Kalata 1984)."""
    return (
        math.isfinite(alpha) and math.isfinite(beta)
        and 0.0 < alpha < 2.0 and 0.0 < beta < 4.0 - 2.0 * alpha
    )


def scheduled_gains(n: int, n_max: int, alpha_ss: float, beta_ss: float, q: float = 0.0
                    ) -> tuple[float, float, bool]:
    """(α, β, evolutive) for the n-th measurement: max(evolutive, steady) per gain.

    The evolutive index is capped at ``n_max`` when 0 < n_max < n (a capped schedule is a
    fixed-gain filter, not evolutive); steady gains count only when :func:`stable_gains`.
    ``evolutive`` is True while both gains are the (uncapped) evolutive ones. ``q`` > 0: the
    evolutive velocity gain is that of the fit with a velocity prior (:func:`prior_gains`'s β,
    q [1], always below the seed's β(n)); the position gain stays the seed's α(n) (session 17:
    the fit's own α ≈ 1/n kept the biases of a young track's first readings).
    """
    capped = 0 < n_max < n
    m = n_max if capped else n
    if m < 1:
        raise ValueError(f"evolutive_gains: n = {m} must be >= 1")
    # evolutive_gains(m) and stable_gains written out (the Tracker calls this every PRI in the
    # mixed phase, issue 14): the same operations; the finiteness tests of stable_gains are
    # implied by the bounds (NaN fails every comparison, ±inf a bound); tested equal
    den = m * (m + 1.0)
    a = 2.0 * (2.0 * m - 1.0) / den  # seed 000 "Evolutive coefficients": α(n)
    b = 6.0 / den  # β(n)
    if q > 0.0:  # the velocity gain of the fit with a velocity prior (session 17)
        b = prior_gains(m, q)[1]
    evolutive = not capped
    if 0.0 < alpha_ss < 2.0 and 0.0 < beta_ss < 4.0 - 2.0 * alpha_ss:
        if alpha_ss >= a:
            a, evolutive = alpha_ss, False
        if beta_ss >= b:
            b, evolutive = beta_ss, False
    return a, b, evolutive


def innovation_factor(alpha: float, beta: float, evolutive: bool) -> float:
    """S/σ² of an α-β update with gains (α, β) [1].

    Evolutive (least-squares) phase: the LS gain is α(n) = P/(P + σ²) with P the prediction
    variance from n − 1 points, so S/σ² = 1/(1 − α(n)) (equal to 1 + 2(2m + 1)/(m(m − 1)),
    m = n − 1, the LS line-extrapolation variance); steady or mixed gains: 1 + VRR(α, β)
    (Brookner eq. 1.2-19). Infinite when undefined (n ≤ 2).
    """
    if evolutive:
        return 1.0 / (1.0 - alpha) if alpha < 1.0 else math.inf
    return 1.0 + prediction_vrr(alpha, beta)
