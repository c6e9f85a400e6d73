"""Local ENU frame at the antenna and spherical <-> Cartesian conversions (SYSTEM.md, seed 000).

Frame: X = East, Y = North, Z = Up. Azimuth θ from North toward East, elevation φ above the
horizon, range ρ. All angles in rad, lengths in m.

    X = ρ cosφ sinθ,  Y = ρ cosφ cosθ,  Z = ρ sinφ          # seed 000 "Spherical to Cartesian"

Total differences (first-order small changes) in both directions are given, as the seed's
tracker converts deviations to Cartesian errors (steps 3, 6) and filtered Cartesian velocities
back to angle rates (step 8).
"""

from __future__ import annotations

import math
from math import asin, atan2, cos, hypot, sin, sqrt

import numpy as np

TWO_PI = 2.0 * math.pi


def wrap_pi(a: float) -> float:
    """Wrap an angle to [-π, π) [rad]."""
    return (a + math.pi) % TWO_PI - math.pi


def wrap_2pi(a: float) -> float:
    """Wrap an angle to [0, 2π) [rad]."""
    return a % TWO_PI


def sph_to_cart(rho: float, az: float, el: float) -> tuple[float, float, float]:
    """(ρ [m], θ [rad], φ [rad]) -> (X, Y, Z) [m].

    # seed 000 "Spherical to Cartesian Conversion (in Position)"
    """
    ce = cos(el)
    return rho * ce * sin(az), rho * ce * cos(az), rho * sin(el)


def cart_to_sph(x: float, y: float, z: float) -> tuple[float, float, float]:
    """(X, Y, Z) [m] -> (ρ [m], θ in [0, 2π) [rad], φ [rad]).  # seed 000 "Cartesian to Polar"."""
    h = hypot(x, y)
    return sqrt(h * h + z * z), atan2(x, y) % TWO_PI, atan2(z, h)


def sph_to_cart_diff(
    rho: float, az: float, el: float, d_rho: float, d_az: float, d_el: float
) -> tuple[float, float, float]:
    """Total difference (dρ, dθ, dφ) -> (dX, dY, dZ) at (ρ, θ, φ).

    # seed 000 "Spherical to Cartesian Conversion (Total Difference)":
    dX = cosφ sinθ dρ − ρ sinφ sinθ dφ + ρ cosφ cosθ dθ
    dY = cosφ cosθ dρ − ρ sinφ cosθ dφ − ρ cosφ sinθ dθ
    dZ = sinφ dρ + ρ cosφ dφ
    """
    ca, sa, ce, se = cos(az), sin(az), cos(el), sin(el)
    dx = ce * sa * d_rho - rho * se * sa * d_el + rho * ce * ca * d_az
    dy = ce * ca * d_rho - rho * se * ca * d_el - rho * ce * sa * d_az
    dz = se * d_rho + rho * ce * d_el
    return dx, dy, dz


def cart_to_sph_diff(
    x: float, y: float, z: float, dx: float, dy: float, dz: float
) -> tuple[float, float, float]:
    """Total difference (dX, dY, dZ) -> (dρ, dθ, dφ) at (X, Y, Z).

    SYSTEM.md (seed 000 lost equations):
    dρ = (X dX + Y dY + Z dZ)/ρ
    dθ = (Y dX − X dY)/(X² + Y²)
    dφ = ((X² + Y²) dZ − Z (X dX + Y dY)) / (ρ² √(X² + Y²))
    Also converts velocities (dX/dt …) into range rate and angle rates.
    """
    h2 = x * x + y * y
    rho2 = h2 + z * z
    rho = sqrt(rho2)
    h = sqrt(h2)
    d_rho = (x * dx + y * dy + z * dz) / rho
    d_az = (y * dx - x * dy) / h2
    d_el = (h2 * dz - z * (x * dx + y * dy)) / (rho2 * h)
    return d_rho, d_az, d_el


def sph_to_cart_and_diff_cs(
    rho: float, ca: float, sa: float, ce: float, se: float, d_rho: float, d_az: float,
    d_el: float,
) -> tuple[float, float, float, float, float, float]:
    """:func:`sph_to_cart` and :func:`sph_to_cart_diff` at the same (ρ [m], θ, φ) in one call,
    from cos/sin of the azimuth (``ca``, ``sa``) and of the elevation (``ce``, ``se``) the
    caller already has: (X, Y, Z, dX, dY, dZ) [m], the same operations as those two functions
    (seed 000 "Spherical to Cartesian Conversion", in position and total difference); one set
    of sines and cosines instead of two (issue 14, round 3)."""
    rc = rho * ce
    x, y, rs = rc * sa, rc * ca, rho * se
    # the products ρ·cosφ·sinθ (= X), ρ·cosφ·cosθ (= Y), ρ·sinφ (= Z) of the total
    # difference are X, Y, Z themselves (the same left-to-right products): reused
    return (
        x, y, rs,
        ce * sa * d_rho - rs * sa * d_el + y * d_az,
        ce * ca * d_rho - rs * ca * d_el - x * d_az,
        se * d_rho + rc * d_el,
    )


def cart_to_sph_and_diff(
    x: float, y: float, z: float, dx: float, dy: float, dz: float
) -> tuple[float, float, float, float, float, float]:
    """:func:`cart_to_sph` and :func:`cart_to_sph_diff` at the same (X, Y, Z) [m] in one call:
    (ρ [m], θ in [0, 2π), φ [rad], dρ, dθ, dφ), the same operations as those two functions
    (seed 000 "Cartesian to Polar"; SYSTEM.md total difference); the total difference is
    (0, 0, 0) where it is undefined (at the origin or on the vertical axis: a division by
    zero in :func:`cart_to_sph_diff`) (issue 14, round 3)."""
    h = hypot(x, y)
    h2 = x * x + y * y
    rho2 = h2 + z * z
    try:
        rho = sqrt(rho2)
        xy = x * dx + y * dy
        d_rho = (xy + z * dz) / rho
        d_az = (y * dx - x * dy) / h2
        d_el = (h2 * dz - z * xy) / (rho2 * sqrt(h2))
    except ZeroDivisionError:
        d_rho = d_az = d_el = 0.0
    return (sqrt(h * h + z * z), atan2(x, y) % TWO_PI, atan2(z, h),
            d_rho, d_az, d_el)


def boresight_offsets(
    az_t: float, el_t: float, az_a: float, el_a: float
) -> tuple[float, float]:
    """Angles of a target direction in the antenna frame [rad].

    Returns (lateral, elevation) offsets of the direction (az_t, el_t) from boresight
    (az_a, el_a): the target unit vector is expressed in the antenna basis (boresight, right,
    up); lateral = atan2(right, boresight) (> 0: clockwise/east of boresight), elevation =
    asin(up) (> 0: above). For small offsets lateral ≈ (az_t − az_a)·cos(el), which is why the
    tracker divides by cos(El): dAz = dLat / cos(El) (seed 000).
    """
    ct, st = cos(el_t), sin(el_t)
    ux, uy, uz = ct * sin(az_t), ct * cos(az_t), st
    ca, sa, ce, se = cos(az_a), sin(az_a), cos(el_a), sin(el_a)
    b = ux * ce * sa + uy * ce * ca + uz * se  # boresight
    r = ux * ca - uy * sa  # right (east at az = 0)
    u = -ux * se * sa - uy * se * ca + uz * ce  # up
    return atan2(r, b), asin(max(-1.0, min(1.0, u)))


def boresight_offsets_array(
    az_t: np.ndarray, el_t: np.ndarray, az_a: float, el_a: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`boresight_offsets` for arrays of target directions (same equations) [rad]."""
    ct = np.cos(el_t)
    ux, uy, uz = ct * np.sin(az_t), ct * np.cos(az_t), np.sin(el_t)
    ca, sa, ce, se = cos(az_a), sin(az_a), cos(el_a), sin(el_a)
    b = ux * ce * sa + uy * ce * ca + uz * se  # boresight
    r = ux * ca - uy * sa  # right
    u = -ux * se * sa - uy * se * ca + uz * ce  # up
    return np.arctan2(r, b), np.arcsin(np.clip(u, -1.0, 1.0))
