"""MTI canceller and its elevation switch (models/radar/mti.py, issue 11)."""

from __future__ import annotations

import math

import numpy as np

from axir.models.radar.mti import (
    MTI_TAPS,
    cancel_chunk,
    cancel_pulse,
    cancel_pulse_into,
    mti_switch,
)
from axir.models.target_generator import TargetGenerator


def test_switch_has_hysteresis():
    lim, hyst = math.radians(4.5), math.radians(0.25)
    assert mti_switch(False, math.radians(4.4), lim, hyst)
    assert mti_switch(True, math.radians(4.6), lim, hyst)  # inside the band: kept on
    assert not mti_switch(False, math.radians(4.6), lim, hyst)  # inside the band: kept off
    assert not mti_switch(True, math.radians(4.8), lim, hyst)


def test_two_pulse_canceller_removes_a_constant_and_passes_history_when_off():
    x = np.full((4, 16), 3.0 + 1.0j)
    hist = np.zeros((1, 4, 16), dtype=complex)
    y, hist = cancel_pulse(x, hist, MTI_TAPS[1], True)
    np.testing.assert_allclose(y, x / math.sqrt(2.0))  # first pulse: nothing to cancel
    y, hist = cancel_pulse(x.copy(), hist, MTI_TAPS[1], True)
    np.testing.assert_allclose(y, 0.0, atol=1e-15)  # a 0-Hz echo is cancelled
    y, hist2 = cancel_pulse(2.0 * x, hist, MTI_TAPS[1], False)
    np.testing.assert_allclose(y, 2.0 * x)  # off: untouched, memory still updated
    np.testing.assert_allclose(hist2[0], 2.0 * x)
    chunk = np.stack([x, 2 * x, 2 * x])
    yc, _ = cancel_chunk(chunk, hist2, MTI_TAPS[1], True)
    np.testing.assert_allclose(yc[0], -x / math.sqrt(2.0))
    np.testing.assert_allclose(yc[1], x / math.sqrt(2.0))
    np.testing.assert_allclose(yc[2], 0.0, atol=1e-15)


def test_generator_applies_the_canceller_only_below_its_elevation_limit():
    """Clutter only, boresight at 1° (main-beam clutter) and at 10°: with the default
    switch the 0-Hz filter's clutter is cancelled at 1° (≥ 20 dB below mti = 0) and the same
    as without the canceller at 10° (identical stream: same seed)."""
    def power(el_deg: float, mti: int) -> float:
        g = TargetGenerator(rcs=0.0, noise=False, seed=4, mti=mti)
        inp = {"antenna.az": 0.0, "antenna.el": math.radians(el_deg), "gate.start": 9000.0,
               "doppler.centre": 0.0, "pri": 100e-6}
        g.step(300e-4, inp)
        return float(np.mean([np.mean(g.step(1e-3, inp)["beam"][:, :, 1] ** 2)
                              for _ in range(40)]))

    assert power(1.0, 1) < 1e-2 * power(1.0, 0)
    assert power(10.0, 1) == power(10.0, 0)


def test_in_place_canceller_is_bit_identical_to_the_pure_one():
    """Issue 14: cancel_pulse_into (preallocated buffers, history updated in place) gives the
    same bytes as cancel_pulse, orders 1 and 2, switched on and off along the pulses."""
    rng = np.random.Generator(np.random.PCG64(5))
    for order in (1, 2):
        taps = MTI_TAPS[order]
        h_ref = np.zeros((order, 4, 16), dtype=complex)
        h_new = h_ref.copy()
        out, tmp = np.empty((4, 16), dtype=complex), np.empty((4, 16), dtype=complex)
        for k in range(12):
            raw = rng.standard_normal((4, 16)) + 1j * rng.standard_normal((4, 16))
            keep = raw.copy()
            apply = k % 5 != 3
            y_ref, h_ref = cancel_pulse(raw.copy(), h_ref, taps, apply)
            y_new = cancel_pulse_into(raw, h_new, taps, apply, out, tmp)
            assert y_new.tobytes() == y_ref.tobytes()
            assert h_new.tobytes() == h_ref.tobytes()
            assert raw.tobytes() == keep.tobytes()  # the raw samples are not modified
