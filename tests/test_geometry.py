"""Shared geometry module: spherical <-> Cartesian positions, total differences, boresight."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.radar.geometry import (
    boresight_offsets,
    cart_to_sph,
    cart_to_sph_and_diff,
    cart_to_sph_diff,
    sph_to_cart,
    sph_to_cart_and_diff_cs,
    sph_to_cart_diff,
    wrap_pi,
)

RNG = np.random.default_rng(12345)


def _random_points(n: int) -> list[tuple[float, float, float]]:
    rho = RNG.uniform(100.0, 50_000.0, n)
    az = RNG.uniform(0.0, 2 * math.pi, n)
    el = RNG.uniform(-1.4, 1.4, n)
    return list(zip(rho.tolist(), az.tolist(), el.tolist(), strict=True))


def test_frame_convention_enu() -> None:
    # SYSTEM.md: az from North toward East; X East, Y North, Z Up
    x, y, z = sph_to_cart(1000.0, math.pi / 2, 0.0)
    assert (x, y, z) == pytest.approx((1000.0, 0.0, 0.0), abs=1e-9)
    x, y, z = sph_to_cart(1000.0, 0.0, math.pi / 6)
    assert (x, y, z) == pytest.approx((0.0, 1000.0 * math.cos(math.pi / 6), 500.0), abs=1e-9)


def test_round_trip_random_points() -> None:
    for rho, az, el in _random_points(500):
        x, y, z = sph_to_cart(rho, az, el)
        r2, a2, e2 = cart_to_sph(x, y, z)
        assert abs(r2 - rho) < 1e-9 * max(1.0, rho)
        assert abs(wrap_pi(a2 - az)) < 1e-9
        assert abs(e2 - el) < 1e-9
        # and back
        assert np.allclose(sph_to_cart(r2, a2, e2), (x, y, z), rtol=0, atol=1e-9 * rho)


@pytest.mark.parametrize("point", _random_points(20))
def test_sph_to_cart_diff_is_first_order_difference(point: tuple[float, float, float]) -> None:
    rho, az, el = point
    d = np.array([3.0, 2e-3, -1.5e-3])  # (dρ, dθ, dφ) direction of the step
    base = np.array(sph_to_cart(rho, az, el))
    errs = []
    for h in (1.0, 0.1, 0.01):
        dr, da, de = h * d
        fd = np.array(sph_to_cart(rho + dr, az + da, el + de)) - base
        lin = np.array(sph_to_cart_diff(rho, az, el, dr, da, de))
        errs.append(np.linalg.norm(fd - lin))
    # second-order remainder: ×10 smaller step → ≈ ×100 smaller error
    assert errs[1] / errs[0] == pytest.approx(0.01, rel=0.1)
    assert errs[2] / errs[1] == pytest.approx(0.01, rel=0.1)


@pytest.mark.parametrize("point", _random_points(20))
def test_cart_to_sph_diff_is_first_order_difference(point: tuple[float, float, float]) -> None:
    rho, az, el = point
    x, y, z = sph_to_cart(rho, az, el)
    d = np.array([5.0, -3.0, 4.0])
    base = np.array(cart_to_sph(x, y, z))
    errs = []
    for h in (1.0, 0.1, 0.01):
        dx, dy, dz = h * d
        r2, a2, e2 = cart_to_sph(x + dx, y + dy, z + dz)
        fd = np.array([r2 - base[0], wrap_pi(a2 - base[1]), e2 - base[2]])
        lin = np.array(cart_to_sph_diff(x, y, z, dx, dy, dz))
        errs.append(np.linalg.norm(fd - lin))
    assert errs[1] / errs[0] == pytest.approx(0.01, rel=0.1)
    assert errs[2] / errs[1] == pytest.approx(0.01, rel=0.1)


def test_diffs_are_mutual_inverses() -> None:
    # The two Jacobians must be inverse matrices at any point (off the zenith).
    for rho, az, el in _random_points(50):
        x, y, z = sph_to_cart(rho, az, el)
        d = RNG.normal(size=3) * np.array([10.0, 1e-3, 1e-3])
        back = cart_to_sph_diff(x, y, z, *sph_to_cart_diff(rho, az, el, *d))
        assert np.allclose(back, d, rtol=1e-9, atol=1e-15)


def test_boresight_offsets_small_and_zero() -> None:
    for _, az, el in _random_points(50):
        assert boresight_offsets(az, el, az, el) == pytest.approx((0.0, 0.0), abs=1e-12)
        daz, de = 2e-4, -3e-4
        lat, elo = boresight_offsets(az + daz, el + de, az, el)
        assert lat == pytest.approx(daz * math.cos(el), abs=2e-7)
        assert elo == pytest.approx(de, abs=2e-7)


def test_boresight_offsets_signs() -> None:
    # target east (clockwise) of boresight → lateral > 0; above → elevation > 0 (SYSTEM.md)
    lat, elo = boresight_offsets(0.31, 0.2, 0.3, 0.2)
    assert lat > 0.0
    lat, elo = boresight_offsets(0.3, 0.21, 0.3, 0.2)
    assert elo > 0.0
    assert abs(lat) < 1e-12


def test_combined_conversions_equal_the_separate_ones_bit_for_bit() -> None:
    """The one-call forms (issue 14) return exactly what the two functions they combine return,
    including the undefined total difference (origin, vertical axis) as zeros."""
    rng = np.random.default_rng(99)
    for _ in range(5000):
        rho, az, el = rng.uniform(1.0, 9e4), rng.uniform(-7.0, 7.0), rng.uniform(-1.6, 1.6)
        d = rng.normal(0.0, [30.0, 0.01, 0.01]).tolist()
        got = sph_to_cart_and_diff_cs(rho, math.cos(az), math.sin(az), math.cos(el),
                                      math.sin(el), *d)
        assert got == (*sph_to_cart(rho, az, el), *sph_to_cart_diff(rho, az, el, *d))
        x, y, z, vx, vy, vz = rng.normal(0.0, [1e4, 1e4, 3e3, 300.0, 300.0, 50.0]).tolist()
        assert cart_to_sph_and_diff(x, y, z, vx, vy, vz) == (
            *cart_to_sph(x, y, z), *cart_to_sph_diff(x, y, z, vx, vy, vz))
    for x, y, z in ((0.0, 0.0, 0.0), (0.0, 0.0, 1000.0), (0.0, 0.0, -5.0)):
        with pytest.raises(ZeroDivisionError):
            cart_to_sph_diff(x, y, z, 1.0, 2.0, 3.0)
        assert cart_to_sph_and_diff(x, y, z, 1.0, 2.0, 3.0) == (*cart_to_sph(x, y, z), 0.0,
                                                                 0.0, 0.0)
