"""Issue 11 (session 12): with ``Tracker.tentative_radial_coast`` (an option, off by default) a
coasting tentative track keeps only the line-of-sight component of its velocity
(models/tracker/beam_helpers.py ``_radial_velocity``; docs/filters.md "A tentative track coasts
in range", which says why it is off, measured again in session 16).

Traced first: 10 km, 2° elevation, +140 m/s (8.78 kHz, in the band blind at the three
acquisition PRIs), 1 m², seed 1. The tentative track's evolutive α-β read velocities of
10³-10⁵ m/s from a few weak readings; each coast between them extrapolated that velocity and
walked the antenna 1.5° below the target, onto the clutter, where the target was confirmed at
the edge of the beam: 2 false confirmations and a drop.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from designation import SESSION18, run_with_tracker
from test_tracker import inputs, make_beams

from axir.models.radar.geometry import cart_to_sph
from axir.models.tracker import Tracker
from axir.orchestrator.envelope import Cell

DT = 1e-4
P0 = np.array([3000.0, 4000.0, 400.0])  # m: 5 km, az 36.9°, el 4.6°
GATE = float(np.linalg.norm(P0)) - 450.0  # bin 7 on the target


def _tentative_track(radial: bool, n: int = 30, **params: Any) -> Tracker:
    """A tracker (``params`` over the defaults) after ``n`` tentative readings of a still
    target, its velocity then set to a known value with a cross-range part (as a young track's
    noisy estimate)."""
    _, az, el = cart_to_sph(*P0)
    trk = Tracker(tentative_radial_coast=radial, **params)
    b = make_beams(tuple(P0), az, el, GATE)
    for _ in range(n):
        trk.step(DT, inputs(b, az, el, 1, GATE))
    return trk


def _coast(trk: Tracker, mode: int, k: int) -> dict:
    """``k`` steps without a usable reading (no signal) in ``mode``; the last outputs."""
    _, az, el = cart_to_sph(*P0)
    out: dict = {}
    for _ in range(k):
        out = trk.step(DT, inputs(np.zeros((4, 16, 3)), az, el, mode, GATE))
    return out


def test_a_coasting_tentative_track_keeps_its_direction_and_its_range_rate() -> None:
    v = np.array([900.0, -700.0, 1200.0])  # m/s: mostly across the line of sight
    u = P0 / np.linalg.norm(P0)
    trk = _tentative_track(True)
    p0 = np.array([f.pos for f in trk.core.axes])
    for f, vi in zip(trk.core.axes, v, strict=True):
        f.vel = float(vi)
    _coast(trk, 1, 200)  # 20 ms of coast
    p = np.array([f.pos for f in trk.core.axes])
    vel = np.array([f.vel for f in trk.core.axes])
    # the velocity is its line-of-sight part (u·v) u, the position moved along u by it
    np.testing.assert_allclose(vel, u * (u @ v), rtol=1e-9)
    np.testing.assert_allclose(p, p0 + u * (u @ v) * 200 * DT, rtol=0, atol=1e-6)
    _, az0, el0 = cart_to_sph(*p0)
    _, az1, el1 = cart_to_sph(*p)
    assert abs(az1 - az0) < 1e-12 and abs(el1 - el0) < 1e-12


def test_off_or_confirmed_the_full_velocity_is_extrapolated() -> None:
    v = np.array([900.0, -700.0, 900.0])  # 1 456 m/s: below max_speed (1 500 m/s)
    for radial, mode in ((False, 1), (True, 2)):
        trk = _tentative_track(radial)
        p0 = np.array([f.pos for f in trk.core.axes])
        for f, vi in zip(trk.core.axes, v, strict=True):
            f.vel = float(vi)
        _coast(trk, mode, 200)
        p = np.array([f.pos for f in trk.core.axes])
        np.testing.assert_allclose(p - p0, v * 200 * DT, rtol=1e-9)


def test_the_traced_cell_confirms_on_the_target_with_the_option() -> None:
    """Seeds 1 and 2 of the traced cell. Since session 16 a coast is bounded to max_speed
    before it moves the track (tests/test_tracker_handover_range.py), which alone removes seed
    1's walk; with the default (the full-velocity coast) seed 2 keeps a false confirmation;
    the velocity prior (an option, session 17) removes it too."""
    assert Tracker.defaults()["tentative_radial_coast"] is False
    cells = [Cell(range_m=10_000.0, speed=140.0, el_deg=2.0, rcs=1.0, seed=s, duration=3.0)
             for s in (1, 2)]
    s_default = [run_with_tracker(cell, **SESSION18) for cell in cells]
    assert s_default[1]["false_confirmations"] > 0  # the walk onto the clutter (as traced)
    for s in [run_with_tracker(cell, **{**SESSION18, "velocity_prior_sigma": 600.0})
              for cell in cells]:
        assert s["false_confirmations"] == 0 and s["drops"] == 0
    s_on = [run_with_tracker(cell, tentative_radial_coast=True, **SESSION18) for cell in cells]
    for s in s_on:
        assert s["false_confirmations"] == 0 and s["drops"] == 0
        assert s["lock_time"] is not None and s["lock_time"] < 1.0
        assert s["held_fraction"] > 0.99
