"""Issue 14, the TargetGenerator's one-pulse path: its helpers give the same numbers as the
forms they replace (models/radar/pulse1.py, radar/straddle.py, radar/mti.py, radar/geometry.py),
and the one-pulse path the beams of the vectorised path (round 3 reorders floating-point
operations: equal to rounding)."""

from __future__ import annotations

import json
import math
import struct

import numpy as np

# the one-pulse path's former helpers, kept with the reference of tests/test_tg_round8.py
from test_tg_round8 import boresight_offsets_cart, two_adjacent_bins

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import BIN_M, N_BINS
from axir.models.radar.geometry import boresight_offsets, cart_to_sph
from axir.models.radar.mti import MTI_TAPS, MTI_TAPS_0D, cancel_pulse_into
from axir.models.radar.pulse1 import (
    FLOOR_EL_MAX,
    PulseCache,
    ar1_rows,
    clutter_floor_elevation,
    clutter_gains_tuple,
    complex0d,
)
from axir.models.radar.straddle import straddle_bins
from axir.models.target_generator import _DRAW_BLOCK, _N_DRAW, _N_NOISE, TargetGenerator


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


def test_boresight_offsets_cart_equals_the_angle_form():
    """The unit vector p/ρ gives the offsets of boresight_offsets(az, el of cart_to_sph) to
    rounding (|elevation offset| < 1.5 rad: asin's slope stays below 15 there)."""
    rng = np.random.default_rng(5)
    n_cmp = 0
    for _ in range(3000):
        p = rng.standard_normal(3) * 10.0 ** rng.uniform(0.0, 5.0, 3)
        az_a, el_a = rng.uniform(-7.0, 7.0), rng.uniform(-1.6, 1.6)
        r, az, el = cart_to_sph(*p)
        ref = boresight_offsets(az, el, az_a, el_a)
        got = boresight_offsets_cart(*p, r, az_a, el_a)
        if abs(ref[1]) < 1.5:
            n_cmp += 1
            assert abs(math.remainder(got[0] - ref[0], 2.0 * math.pi)) < 1e-12
            assert abs(got[1] - ref[1]) < 1e-12
    assert n_cmp > 2500
    assert boresight_offsets_cart(0.0, 0.0, 0.0, 0.0, 0.3, 0.2) == boresight_offsets(
        0.0, 0.0, 0.3, 0.2)  # no direction: (az, el) = (0, 0) as cart_to_sph gives


def _offsets_with_builtin_clamp(x, y, z, rho, az_a, el_a):
    """boresight_offsets_cart as it was before issue 14 round 5 (asin of max(−1, min(1, u)))."""
    ux, uy, uz = (x / rho, y / rho, z / rho) if rho > 0.0 else (0.0, 1.0, 0.0)
    ca, sa, ce, se = math.cos(az_a), math.sin(az_a), math.cos(el_a), math.sin(el_a)
    b = ux * ce * sa + uy * ce * ca + uz * se
    r = ux * ca - uy * sa
    u = -ux * se * sa - uy * se * ca + uz * ce
    return math.atan2(r, b), math.asin(max(-1.0, min(1.0, u)))


def test_boresight_offsets_cart_clamp_is_the_builtin_clamp_bit_for_bit():
    """The clamp of the up component written as comparisons (round 5) gives the bytes of
    max(−1, min(1, u)): random points and points ±90° above boresight (|u| at 1 ± rounding,
    where the clamp acts), a NaN input (the builtins' NaN → 1, asin(1) = π/2) included."""
    rng = np.random.default_rng(17)
    clamped = 0
    for k in range(6000):
        az_a, el_a = float(rng.uniform(-7.0, 7.0)), float(rng.uniform(-1.6, 1.6))
        if k % 2:  # the target straight above / below boresight: u = ±1 up to rounding
            sgn = 1.0 if k % 4 == 1 else -1.0
            el_t = el_a + sgn * math.pi / 2.0
            d = 10.0 ** rng.uniform(0.0, 5.0)
            p = (d * math.cos(el_t) * math.sin(az_a), d * math.cos(el_t) * math.cos(az_a),
                 d * math.sin(el_t))
        else:
            p = tuple((rng.standard_normal(3) * 10.0 ** rng.uniform(0.0, 5.0, 3)).tolist())
        r = math.sqrt(p[0] ** 2 + p[1] ** 2 + p[2] ** 2)
        ref = _offsets_with_builtin_clamp(*p, r, az_a, el_a)
        clamped += abs(ref[1]) == math.pi / 2.0
        assert struct.pack("2d", *boresight_offsets_cart(*p, r, az_a, el_a)) == struct.pack(
            "2d", *ref)
    assert clamped > 100
    nan = boresight_offsets_cart(math.nan, 1.0, 0.0, 1.0, 0.0, 0.0)
    assert nan[1] == _offsets_with_builtin_clamp(math.nan, 1.0, 0.0, 1.0, 0.0, 0.0)[1]


def test_two_adjacent_bins_is_straddle_bins_when_it_answers():
    """The usual-case straddle gives straddle_bins' bins and weights exactly (a zero weight
    on bin k + 1 is the one straddle_bins leaves out), and answers most random cases."""
    rng = np.random.default_rng(8)
    answered = 0
    for _ in range(20000):
        ru = rng.uniform(N_BINS * BIN_M, 40_000.0)
        r = rng.uniform(0.0, 3.0 * ru)
        gate = rng.uniform(-ru, ru)
        if rng.random() < 0.1:  # on a bin sample
            r = gate + BIN_M * rng.integers(0, N_BINS)
        fast = two_adjacent_bins(r, gate, ru)
        if fast is None:
            continue
        answered += 1
        k, w0, w1 = fast
        assert [(k, w0)] + ([(k + 1, w1)] if w1 > 0.0 else []) == straddle_bins(r, gate, ru)
    assert answered > 1000


def test_block_clutter_is_the_per_pulse_recursion_bit_for_bit():
    """PulseCache.fill runs c = ρc c + b u over the block (lfilter) with the bytes of the
    per-pulse recursion, also when rebuilt from a row i (a PRI change, a restored state)."""
    rng = np.random.default_rng(2)
    blk = rng.standard_normal((_DRAW_BLOCK, _N_DRAW)) * math.sqrt(0.5)
    c0 = _cplx(rng, N_BINS) * 30.0
    rho_c, b_c, s = math.exp(-2.0 * math.pi * 15.0 * 1e-4), 0.3, 0.1
    pc = PulseCache(blk, _N_NOISE)
    pc.fill(0, s, c0, (rho_c, b_c), (0.0,) * 4, True)
    u = blk[:, : _N_NOISE + 2 * N_BINS].view(complex)[:, _N_NOISE // 2 :]
    c = c0.copy()
    for k in range(_DRAW_BLOCK):
        c *= rho_c
        c += u[k] * b_c
        assert pc.cb[k].tobytes() == c.tobytes()
    noise = blk[:, : _N_NOISE].view(complex).reshape(_DRAW_BLOCK, 4, N_BINS)
    assert pc.xb.tobytes() == (noise * s).tobytes()  # no clutter gains pre-added
    full = pc.cb.copy()
    gp = (0.5, 0.25, 0.125, 0.0625)
    pc.fill(7, s, full[6], (rho_c, b_c), gp, True)
    assert pc.cb[7:].tobytes() == full[7:].tobytes()
    np.testing.assert_allclose(pc.xb[7:], noise[7:] * s + (np.array(gp) * s)[None, :, None]
                               * full[7:, None, :], rtol=1e-13, atol=1e-13)


def test_pre_added_clutter_rows_equal_the_complex_product_bit_for_bit():
    """Round 4: fill's (s·gp) ⊗ c, formed on the float64 parts into a kept buffer, has the
    bytes of the complex form s·w + array(s·gp)[:, None] · c (round 3's expression), from
    row 0 and rebuilt from a row i, with gains down to the sidelobe floor and one zero."""
    rng = np.random.default_rng(41)
    blk = rng.standard_normal((_DRAW_BLOCK, _N_DRAW)) * math.sqrt(0.5)
    noise = blk[:, : _N_NOISE].view(complex).reshape(_DRAW_BLOCK, 4, N_BINS)
    rho_c, b_c, s = math.exp(-2.0 * math.pi * 15.0 * 1e-4), 0.7, 0.1
    pc = PulseCache(blk, _N_NOISE)
    for i, gp in [(0, (0.9, 0.031, 1e-3, 0.0316)), (11, (0.0316,) * 4), (31, (0.0, 0.5, 2.0, 1.0)),
                  (0, tuple(rng.uniform(0.0, 1.0, 4)))]:
        c0 = _cplx(rng, N_BINS) * 30.0
        pc.fill(i, s, c0, (rho_c, b_c), gp, True)
        cb = ar1_rows(blk[i:, : _N_NOISE + 2 * N_BINS].view(complex)[:, _N_NOISE // 2 :] * b_c,
                      rho_c, c0)
        assert pc.cb[i:].tobytes() == cb.tobytes()
        ref = noise[i:] * s
        ref += np.array([g * s for g in gp]).reshape(1, 4, 1) * cb[:, None, :]
        assert pc.xb[i:].tobytes() == ref.tobytes(), (i, gp)


def test_ar1_rows_gives_the_bytes_of_scipy_lfilter():
    """ar1_rows (numpy rows, no scipy.signal in the models) = lfilter([1], [1, −ρ], x,
    zi=ρ·c) byte for byte: random blocks of 1 … 40 rows, ρ from white to nearly 1."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(14)
    for n, rho in [(1, 0.3), (2, 0.999), (32, math.exp(-2.0 * math.pi * 15.0 * 1e-4)),
                   (40, 0.0), (32, 0.5), (7, 1.0 - 1e-12)]:
        x = _cplx(rng, n, N_BINS) * rng.uniform(0.01, 100.0)
        c = _cplx(rng, N_BINS) * 30.0
        ref = lfilter([1.0], [1.0, -rho], x, axis=0, zi=(rho * c)[None, :])[0]
        got = ar1_rows(x.copy(), rho, c)
        assert got.tobytes() == ref.tobytes(), (n, rho)
    wide = _cplx(rng, 2 * N_BINS)  # a strided c (every other value) gives the same
    x = _cplx(rng, 5, N_BINS)
    ref = lfilter([1.0], [1.0, -0.7], x, axis=0, zi=(0.7 * wide[::2])[None, :])[0]
    assert ar1_rows(x.copy(), 0.7, wide[::2]).tobytes() == ref.tobytes()


def test_block_refill_from_its_own_last_row():
    """A new draw block refills the rows from c = the previous block's last row, a view of
    the very buffer being refilled: the recursion must start from its old value."""
    rng = np.random.default_rng(5)
    blk = rng.standard_normal((_DRAW_BLOCK, _N_DRAW)) * math.sqrt(0.5)
    rho_c, b_c = 0.9, 0.3
    pc = PulseCache(blk, _N_NOISE)
    pc.fill(0, 0.1, _cplx(rng, N_BINS), (rho_c, b_c), (0.0,) * 4, True)
    last = pc.crows[-1]
    c = last.copy()
    blk[:] = rng.standard_normal(blk.shape) * math.sqrt(0.5)  # the next block's draws
    pc.fill(0, 0.1, last, (rho_c, b_c), (0.0,) * 4, True)
    u = blk[:, : _N_NOISE + 2 * N_BINS].view(complex)[:, _N_NOISE // 2 :]
    for k in range(_DRAW_BLOCK):
        c *= rho_c
        c += u[k] * b_c
        assert pc.cb[k].tobytes() == c.tobytes()


def test_one_pulse_path_equals_vectorised_path_with_moving_antenna():
    """Round 3 reorders floating-point operations: one-pulse steps give the beams of the
    vectorised path fed one pulse at a time (same draws) to rounding, through every branch:
    clutter gains pre-added (antenna still above the horizon), corrected per pulse (antenna
    moving down to the horizon, canceller on), PRI and Doppler-centre changes mid-block,
    Swerling 1. A wrong row, gain or (1 − ρ) factor differs at the 1e-2 level or more."""
    spec = json.dumps({"type": "cv", "position": [1000.0, 9000.0, 300.0],
                       "velocity": [20.0, -150.0, 5.0]})
    kw = {"trajectory": spec, "seed": 21, "swerling": 1, "dwell_pulses": 5, "mti": 1,
          "rcs": 50.0}
    a, b = TargetGenerator(**kw), TargetGenerator(**kw)
    pre_added = corrected = 0
    for n in range(150):
        el = 0.12 if n < 45 else max(0.005, 0.12 - 0.004 * (n - 45))  # still, then down
        pri = 100e-6 if n < 60 or n > 100 else 91e-6  # PRI changes inside blocks
        u = {"antenna.az": 0.1, "antenna.el": el, "gate.start": 8_900.0,
             "doppler.centre": 300.0 + 50.0 * (n // 17), "pri": pri}
        out = a.step(pri, u)  # the one-pulse path
        ub = b._hold_valid(u)
        b.t += pri
        b._pulses(np.array([b.t]), ub)  # the vectorised path, one pulse
        # rtol 1e-7 as test_target_generator's path tests: the carrier phase 4πR/λ ≈ 4e6 rad
        # turns the paths' last-bit difference in R (trajectory, array vs scalar) into ≈ 1e-9
        np.testing.assert_allclose(out["beam"], np.abs(b._y), rtol=1e-7, atol=1e-9)
        pre_added += any(a._gp)
        corrected += a._cg_vals is not a._gp
    assert a._mti_on and pre_added > 20 and corrected > 20  # every branch was taken


def test_two_pulse_canceller_memory_through_copies_blocks_and_long_steps():
    """The two-pulse canceller's memory is a view of the last row of the one-pulse path's
    buffers (round 3, no copy per pulse): a deep copy and a set_state mid-block continue
    bit-identically across block boundaries, and a multi-pulse step in between gives the
    beams of one-pulse steps (to rounding)."""
    import copy

    u = {"pri": 100e-6, "antenna.el": 0.01, "antenna.az": 0.0, "gate.start": 9_900.0}
    kw = {"seed": 6, "mti": 1, "rcs": 20.0}
    gen = TargetGenerator(**kw)
    for _ in range(30):  # two pulses before a block boundary
        gen.step(100e-6, u)
    assert gen._mti_on and gen._xh.base is not None  # the memory is a view
    twin = copy.deepcopy(gen)
    other = TargetGenerator(seed=0)
    other.set_state(gen.get_state())
    ref = [gen.step(100e-6, u)["beam"].tobytes() for _ in range(70)]
    assert [twin.step(100e-6, u)["beam"].tobytes() for _ in range(70)] == ref
    assert [other.step(100e-6, u)["beam"].tobytes() for _ in range(70)] == ref
    a, b = TargetGenerator(**kw), TargetGenerator(**kw)
    for _ in range(40):
        a.step(100e-6, u)
        b.step(100e-6, u)
    a.step(5 * 100e-6, u)  # the vectorised path reads and replaces the memory
    for _ in range(5):
        b.step(100e-6, u)
    for _ in range(30):
        oa, ob = a.step(100e-6, u), b.step(100e-6, u)
    np.testing.assert_allclose(oa["beam"], ob["beam"], rtol=1e-7, atol=1e-9)


def test_parameters_changed_between_steps_rebuild_the_rows():
    """A parameter set between steps (Unit.configure, no reset) takes effect at the next pulse
    although the rows of the block were built before: noise off gives exactly the noise-free
    generator's beams from then on (no clutter), whatever the row of the block."""
    u = {"pri": 100e-6, "antenna.el": 0.2, "antenna.az": 0.0, "gate.start": 9_900.0}
    gen = TargetGenerator(seed=3, mti=0, clutter=False)
    for _ in range(5):
        gen.step(100e-6, u)
    quiet = dict(gen.params(), noise=False)
    gen.configure(quiet)
    ref = TargetGenerator(**quiet)
    ref._y = gen._y.copy()  # the same filter state, then the same noise-free input
    ref.t, ref._pulse = gen.t, gen._pulse
    for _ in range(40):
        np.testing.assert_allclose(gen.step(100e-6, u)["beam"], ref.step(100e-6, u)["beam"],
                                   rtol=1e-12, atol=1e-12)


def test_generator_pickles_and_continues_bit_identically():
    """The one-pulse buffers (PulseCache: a memoryview, a struct method) pickle as None, as
    they deep-copy; an unpickled generator rebuilds them and gives the original's beams."""
    import pickle

    u = {"antenna.az": 0.3, "antenna.el": 0.02, "gate.start": 9000.0}
    a = TargetGenerator(seed=4)
    for _ in range(45):  # into the second draw block
        a.step(1e-4, u)
    b = pickle.loads(pickle.dumps(a))
    assert b._v is None
    for _ in range(40):
        oa, ob = a.step(1e-4, u), b.step(1e-4, u)
        assert oa["beam"].tobytes() == ob["beam"].tobytes()


def test_replicated_rows_and_target_row_equal_the_broadcast_adds_bit_for_bit():
    """Issue 14 (spd13): the one-pulse path keeps each row x[n] replicated over the 3 Doppler
    filters (PulseCache.x3b, made by fill) and adds the target as a whole (4, 16, 3) row that
    is zero outside bins j, j + 1 (t3_lo[j], t3_hi[j]: beams 0-1 and 2-3, the bytes of one
    pack of the whole row); the filters then add a same-shape row. On random
    rows, gains, weights and filter states, for every j: the same bytes as the former path —
    the (4, 2) block added into x[:, j : j + 2], then y·P + x[:, :, None]."""
    from axir.models.radar.pulse1 import PulseCache, target_row_struct

    rng = np.random.default_rng(31)
    blk = np.empty((_DRAW_BLOCK, _N_DRAW))
    pc = PulseCache(blk, _N_NOISE)
    for k in range(3000):
        rng.standard_normal(out=blk)
        blk *= 10.0 ** rng.uniform(-6, 6)
        gp = (0.0,) * 4 if k % 2 else tuple(float(v) for v in rng.uniform(0.0, 0.1, 4))
        i = int(rng.integers(_DRAW_BLOCK))
        c = rng.standard_normal(16) + 1j * rng.standard_normal(16)
        pc.fill(i, 0.1, c, (0.99, 3.0) if k % 3 else None, gp, bool(k % 5))
        assert pc.x3b[i:].tobytes() == np.repeat(pc.xb[i:, :, :, None], 3, axis=3).tobytes()
        j = int(rng.integers(N_BINS - 1))
        vals = [float(v) for v in rng.normal(0.0, 10.0 ** rng.uniform(-3, 3), 16)]
        if k % 11 == 0:
            vals[int(rng.integers(16))] = 0.0
        y0 = rng.standard_normal((4, 16, 3)) + 1j * rng.standard_normal((4, 16, 3))
        P = np.broadcast_to(0.9 * np.exp(1j * rng.uniform(-3, 3, 3)), (4, 16, 3)).copy()
        # the former path: the (4, 2) block into x, the filters broadcast x over (4, 16, 1)
        x_old = pc.xb[i].copy()
        tb = np.array(vals).view(complex).reshape(4, 2)
        x_old[:, j : j + 2] += tb
        y_old = y0.copy()
        y_old *= P
        y_old += x_old[:, :, None]
        # the replicated path
        e = [vals[4 * b + q] for b in range(4) for q in range(4)]  # (re, im) of bin j, j + 1
        args = []
        for b in range(4):
            re0, im0, re1, im1 = e[4 * b : 4 * b + 4]
            args += [re0, im0] * 3 + [re1, im1] * 3
        pc.t3_lo[j](*args[:24])  # beams 0-1
        pc.t3_hi[j](*args[24:])  # beams 2-3
        whole = np.ones((4, 16, 3), dtype=complex)  # the whole row in one pack: the same bytes
        target_row_struct(j).pack_into(memoryview(whole).cast("B"), 0, *args)
        assert whole.tobytes() == pc.t3.tobytes(), (k, j)
        x3 = pc.x3rows[i]
        x3 += pc.t3
        y_new = y0.copy()
        y_new *= P
        y_new += x3
        assert y_new.tobytes() == y_old.tobytes(), (k, j)
        assert pc.xrows[i].tobytes() == x_old.tobytes()  # the canceller's x (4, 16)
        nz = np.zeros((4, 16, 3), dtype=bool)
        nz[:, j : j + 2, :] = True
        assert not pc.t3[~nz].any() and not np.signbit(pc.t3.view(float)).reshape(
            4, 16, 3, 2)[~nz].any()  # +0.0 outside the two bins


def test_one_pulse_clutter_gains_and_canceller_switch_written_out():
    """Issue 14, round 7: ``_pulse1`` keeps the clutter gains (formerly ``_clutter_vals``) and
    switches the canceller (``mti.mti_switch``) written out. With the antenna elevation going
    up and down through the sidelobe floor's band, the horizon and the canceller's hysteresis
    band (repeated elevations included), after every one-pulse step the switch state is
    mti_switch's over the same sequence, and the gains tuple, its identity and the ``moved``
    flag are those of the former method (reference below)."""
    from axir.models.radar.mti import mti_switch
    from axir.models.radar.pulse1 import FLOOR_EL_MAX, clutter_gains_tuple

    gen = TargetGenerator(mti=1, seed=3)
    lo, hyst = gen.mti_max_el, gen.mti_hysteresis
    rng = np.random.default_rng(9)
    els = np.concatenate([np.linspace(0.2, -0.05, 60), np.linspace(-0.05, 0.2, 60),
                          lo + hyst * rng.uniform(-1.5, 2.5, 200)])
    els = np.repeat(els, rng.integers(1, 3, els.size))  # some elevations twice in a row
    edges = [lo - 0.01, lo + hyst, lo, lo + hyst, lo + hyst + 0.01, lo, lo - 0.01]  # on the
    els = np.concatenate([els, np.array(edges)])  # thresholds exactly: the comparisons' sides
    on = gen._mti_on
    key, vals, moved = math.nan, (), True
    switches = floors = 0
    for el in els.tolist():
        gen.step(1e-4, {"antenna.az": 0.3, "antenna.el": el, "gate.start": 8_900.0,
                        "pri": 1e-4})
        was, on = on, mti_switch(on, el, lo, hyst)
        switches += was != on
        # the former _clutter_vals
        if el != key:
            g = (gen._cg_floor if gen._cg_lo < el < FLOOR_EL_MAX
                 else clutter_gains_tuple(gen._antenna, el, gen._sidelobe))
            floors += g is gen._cg_floor
            moved = g != vals
            if moved:
                vals = g
            key = el
        elif moved:
            moved = False
        assert gen._mti_on is on
        assert gen._cg_vals == vals and gen._cg_moved is moved and gen._cg_key == key
        assert (gen._cg_vals is gen._cg_floor) == (vals is gen._cg_floor)
    assert gen.clutter and switches > 10 and floors > 20
