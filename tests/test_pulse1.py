"""Issue 14, the TargetGenerator's one-pulse path: its helpers give the same numbers as the
forms they replace (models/radar/pulse1.py, radar/straddle.py, radar/mti.py)."""

from __future__ import annotations

import math

import numpy as np

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import BIN_M, N_BINS
from axir.models.radar.mti import MTI_TAPS, MTI_TAPS_0D, cancel_pulse_into
from axir.models.radar.pulse1 import (
    FLOOR_EL_MAX,
    clutter_floor_elevation,
    clutter_gains_tuple,
    complex0d,
)
from axir.models.radar.straddle import straddle_bins


def _cplx(rng: np.random.Generator, *shape: int) -> np.ndarray:
    return rng.standard_normal(shape) + 1j * rng.standard_normal(shape)


def test_complex0d_products_are_bit_identical_to_python_float_products():
    """A complex array times complex0d(v) has the bytes of the array times the float v (also
    for zero and signed-zero samples), in place and with out=."""
    rng = np.random.Generator(np.random.PCG64(1))
    a = _cplx(rng, 4, 16)
    a[0, :4] = (0.0, -0.0, 0.0j, complex(-0.0, -0.0))
    for v in (0.9, -3.7e-5, 1.0 - 0.9, math.exp(-2.0 * math.pi * 15.0 * 1e-4), 0.0):
        ref = a * v
        assert (a * complex0d(v)).tobytes() == ref.tobytes()
        out = np.empty_like(a)
        np.multiply(a, complex0d(v), out=out)
        assert out.tobytes() == ref.tobytes()
        b = a.copy()
        b *= complex0d(v)
        assert b.tobytes() == ref.tobytes()


def test_in_place_canceller_with_0d_taps_is_bit_identical():
    """cancel_pulse_into with MTI_TAPS_0D gives the bytes it gives with MTI_TAPS."""
    rng = np.random.Generator(np.random.PCG64(2))
    for order in (1, 2):
        h_a = np.zeros((order, 4, 16), dtype=complex)
        h_b = h_a.copy()
        bufs = [np.empty((4, 16), dtype=complex) for _ in range(4)]
        for k in range(9):
            raw = _cplx(rng, 4, 16)
            apply = k % 4 != 2
            y_a = cancel_pulse_into(raw, h_a, MTI_TAPS[order], apply, bufs[0], bufs[1])
            y_b = cancel_pulse_into(raw, h_b, MTI_TAPS_0D[order], apply, bufs[2], bufs[3])
            assert y_a.tobytes() == y_b.tobytes()
            assert h_a.tobytes() == h_b.tobytes()


def test_clutter_gains_tuple_is_the_floored_pattern_toward_the_horizon():
    """Gains toward (lateral 0 or π, elevation asin(−sin el_a)), floored: np.maximum's values."""
    ant = MonopulseAntenna()
    floor = 10.0 ** (-30.0 / 20.0)
    for el_a in np.linspace(-0.3, 3.4, 41):
        lat = 0.0 if math.cos(el_a) >= 0.0 else math.pi
        ref = np.maximum(ant.gains(lat, math.asin(-math.sin(el_a))), floor)
        assert np.array(clutter_gains_tuple(ant, float(el_a), floor)).tobytes() == ref.tobytes()


def test_straddle_bins_match_the_vectorised_triangle():
    """The non-zero (bin, Λ) of straddle_bins are the triangle of the vectorised path
    (distances folded modulo Ru into [−Ru/2, Ru/2)), to rounding; zero elsewhere."""
    rng = np.random.Generator(np.random.PCG64(3))
    for _ in range(3000):
        ru = float(rng.choice([1_200.0, 15_000.0, 0.5 * 299_792_458.0 * rng.uniform(8e-6, 1e-3)]))
        gate = float(rng.uniform(-2e4, 2e4))
        r = float(rng.uniform(-1e5, 2e5)) if rng.random() < 0.5 else (
            gate + float(rng.uniform(-3.0, 20.0)) * BIN_M)
        dist = r - gate - np.arange(N_BINS) * BIN_M
        dist = (dist + 0.5 * ru) % ru - 0.5 * ru
        tri = np.maximum(1.0 - np.abs(dist) / BIN_M, 0.0)
        got = np.zeros(N_BINS)
        for j, w in straddle_bins(r, gate, ru):
            got[j] += w
        np.testing.assert_allclose(got, tri, atol=1e-7)


def test_every_clutter_gain_is_at_the_floor_above_the_floor_elevation():
    """clutter_floor_elevation: between it and FLOOR_EL_MAX all four gains are the floor,
    and just below it (1e-5 rad) the down beam's gain is above the floor."""
    for bw, sq, db in ((2.5, 1.25, -30.0), (1.0, 0.3, -60.0), (4.0, 2.0, -10.0), (2.5, 1.25, 0.0)):
        ant = MonopulseAntenna(beamwidth=math.radians(bw), squint=math.radians(sq))
        floor = 10.0 ** (db / 20.0)
        lo = clutter_floor_elevation(ant, floor)
        for el_a in np.concatenate((lo + np.geomspace(1e-12, 1e-3, 200),
                                    np.linspace(lo, FLOOR_EL_MAX, 2001)[1:-1])):
            assert clutter_gains_tuple(ant, float(el_a), floor) == (floor,) * 4
        if db < 0.0:
            assert max(clutter_gains_tuple(ant, lo - 1e-5, floor)) > floor
