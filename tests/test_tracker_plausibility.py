"""Tracker plausibility (issue 11): a change of range hypothesis re-initialises the track
filters; the confirmed gate never leaves the instrumented range [0, max_range]."""

from __future__ import annotations

import numpy as np
from test_tracker import inputs, make_beams

from axir.models.radar.geometry import sph_to_cart
from axir.models.tracker import Tracker

AZ, EL, DT = 0.3, 0.1, 1e-4


def _track(trk: Tracker, gate: float, offset: float, n: int, mode: int = 1) -> dict:
    """``n`` steps with a still target on the centre of the gate (true gate start
    ``gate + offset``)."""
    target = sph_to_cart(gate + offset + 450.0, AZ, EL)
    out: dict = {}
    for _ in range(n):
        out = trk.step(DT, inputs(make_beams(target, AZ, EL, gate, offset), AZ, EL, mode, gate,
                                  offset))
    return out


def test_new_range_hypothesis_reinitialises_the_filters() -> None:
    trk = Tracker()
    _track(trk, 4000.0, 0.0, 20)
    assert trk.core.axes[0].n == 20
    # the manager moves the window to another hypothesis, 15 km (one Ru) farther: the target
    # seen there is a new track, not a 15 km jump of the old one (no 1.5e8 m/s velocity)
    out = _track(trk, 4000.0, 15_000.0, 3)
    # gate_latency 1: the first of the 3 steps still measures with the old gate; the new
    # hypothesis enters at the second, which re-initialises (n = 1), the third makes n = 2
    assert trk.core.axes[0].n == 2
    assert abs(out["track.range_rate"]) < 1e3
    assert abs(out["track.range"] - 19_450.0) < 75.0


def test_same_hypothesis_at_another_pri_keeps_the_track() -> None:
    """Re-centred by one bin (same true range, apparent bin of another PRI): no re-init."""
    trk = Tracker()
    _track(trk, 4000.0, 0.0, 20)
    _track(trk, 4075.0, -75.0, 5)
    assert trk.core.axes[0].n == 25


def test_confirmed_gate_stays_within_the_instrumented_range() -> None:
    trk = Tracker(max_range=4200.0)
    out = _track(trk, 4000.0, 0.0, 30, mode=2)  # target at 4450 m, beyond max_range
    assert out["gate.start"] + 450.0 <= 4200.0 + 1e-9
    trk = Tracker()
    out = _track(trk, 4000.0, 0.0, 30, mode=2)  # control: inside, the gate follows the track
    assert abs(out["gate.start"] + 450.0 - 4450.0) < 5.0
    assert np.isfinite(out["gate.start"])
