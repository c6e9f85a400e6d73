"""Maneuver tests of the Tracker: the seed-000 3-D test and the summary of per-axis detectors.

Seed-000 configuration (α-β on the three Cartesian axes): one fading-memory detector
(:class:`~axir.models.filters.fmd.FadingMemoryDetector`, Bar-Shalom, Li & Kirubarajan 2001
§11.2; the same L(k) = ρ·L(k − 1) + q(k) as seed 002 eq. 11) on the normalised innovation
squared q = νᵀS⁻¹ν of the 3-D innovation ν of the α-β filters (:func:`nis`), with n_y = 3
degrees of freedom: under no maneuver (1 + ρ)·L is approximately χ² with 3(1 + ρ)/(1 − ρ)
degrees of freedom (moment matching), and the flag is raised when L exceeds that quantile at
1 − P_fa. α-β innovations with non-optimal gains are mildly correlated, so P_fa is
approximate. No acceleration term is fed, so the flag is simply L > I1.

S is *model-based*, not a running estimate of the innovation variance (a running estimate
would absorb the maneuver it should detect): S = f·R where R is the Cartesian measurement
covariance from the declared measurement accuracies (σ_range in range, σ_angle × range across
the beam) and f the prediction factor of the gains in use
(:func:`~axir.models.filters.gains.innovation_factor`; the same gains on each axis make the
prediction covariance proportional to R). Because the spherical unit vectors are orthonormal,
q = ((u_ρ·ν)²/σ_ρ² + (u_θ·ν)²/(ρσ_a)² + (u_φ·ν)²/(ρσ_a)²)/f.

Other filters: each axis filter carries its own detector (seed 002 eqs. 11-15);
:func:`axis_summary` combines them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ..filters.base import AxisFilter, Vec3
from ..filters.fmd import FadingMemoryDetector


def seed000_detector(fading: float, pfa: float) -> FadingMemoryDetector:
    """The 3-D NIS detector of the seed-000 tracker: fading factor ρ = ``fading`` [1],
    false-alarm probability ``pfa`` per update [1] (threshold from χ², n_y = 3)."""
    return FadingMemoryDetector(a_f=fading, pfa=pfa, n_y=3)


def nis(nu: Vec3, az: float, el: float, rho: float, sigma_range: float, sigma_angle: float,
        factor: float) -> float:
    """Normalized innovation squared q = νᵀS⁻¹ν [1] (see the module docstring).

    Args:
        nu: innovation (X, Y, Z) [m]; az, el: direction of the measurement [rad];
        rho: range [m]; sigma_range [m], sigma_angle [rad]: measurement accuracies;
        factor: S/R prediction factor [1].
    """
    return nis_cs(nu, math.cos(az), math.sin(az), math.cos(el), math.sin(el), rho,
                  sigma_range, sigma_angle, factor)


def nis_cs(nu: Vec3, ca: float, sa: float, ce: float, se: float, rho: float,
           sigma_range: float, sigma_angle: float, factor: float) -> float:
    """:func:`nis` from the cosines and sines of the measurement's azimuth (``ca``, ``sa``)
    and elevation (``ce``, ``se``) [1], for a caller that already has them."""
    nx, ny, nz = nu
    q_r = ce * sa * nx + ce * ca * ny + se * nz  # along u_ρ
    q_a = ca * nx - sa * ny  # along u_θ
    q_e = -se * sa * nx - se * ca * ny + ce * nz  # along u_φ
    sc2 = (rho * sigma_angle) ** 2
    if sc2 == 0.0:  # a measurement at range 0 (a target at the radar): undefined, inf
        return math.inf
    return (q_r * q_r / (sigma_range * sigma_range) + (q_a * q_a + q_e * q_e) / sc2) / factor


def axis_summary(filters: Sequence[AxisFilter]) -> tuple[bool, float, float]:
    """(flag, statistic, threshold) over per-axis detectors: flag = any axis; statistic and
    threshold of the axis with the largest L/I1."""
    flag = False
    best, stat, thr = -math.inf, 0.0, 0.0
    for f in filters:
        flag = flag or f.maneuver
        t = f.threshold
        ratio = f.statistic / t if t > 0.0 else f.statistic
        if ratio > best:
            best, stat, thr = ratio, f.statistic, t
    return flag, stat, thr
