"""RadarManager plausibility (issue 11): a resolved range outside the designation window is
never accepted; a confirmed track faster than ``max_speed`` is dropped and re-acquired around
its last plausible range. Synthetic scene: tests/manager_scene.py."""

from __future__ import annotations

import math

import pytest
from manager_scene import Scene, make, run

from axir.models.radar import conventions as radar


def _modes(outs: list[dict]) -> list[int]:
    return [o["mode"] for o in outs]


def test_target_one_ru_beyond_the_designation_window_is_not_confirmed() -> None:
    """Designated 37 km; the target is at 52 km (37 km + one Ru of PRI 1: the same apparent
    range at the acquisition PRI). Default window (5 km): never resolved nor confirmed.
    Control with the window opened to 1000 km: the resolver accepts 52 km and confirms it,
    as before issue 11."""
    outs = run(make(), Scene(52_000.0, seed=3), 6000)
    assert radar.CONFIRMED not in _modes(outs)
    assert not any(o["ambiguity.resolved"] for o in outs)
    outs = run(make(designation_window=1.0e6), Scene(52_000.0, seed=3), 6000)
    assert radar.CONFIRMED in _modes(outs)
    resolved = [o["range.resolved"] for o in outs if o["ambiguity.resolved"]]
    assert abs(resolved[-1] - 52_000.0) < 3 * radar.BIN_M


def test_target_inside_the_window_is_still_resolved() -> None:
    outs = run(make(), Scene(39_000.0, seed=4), 6000,
               until=lambda o: o["mode"] == radar.CONFIRMED)
    assert outs[-1]["mode"] == radar.CONFIRMED
    assert abs(outs[-1]["range.resolved"] - 39_000.0) < 3 * radar.BIN_M


def test_track_faster_than_max_speed_is_dropped_around_its_last_plausible_range() -> None:
    mgr = make()
    scene = Scene(37_000.0, seed=5)
    outs = run(mgr, scene, 6000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert outs[-1]["mode"] == radar.CONFIRMED
    run(mgr, scene, 200)
    last_good = scene.truth()
    # the track runs away (as the false track did: 1e6 m/s, 84 → 104 km)
    outs = run(mgr, scene, 3, extra=lambda i, _: {"track.range_rate": 1.0e6,
                                                   "track.range": last_good + 2.0e4 * (i + 1)})
    assert outs[0]["mode"] == radar.ACQUISITION
    ru = radar.unambiguous_range(outs[0]["pri"])
    centre = outs[0]["gate.command"] + 6 * radar.BIN_M
    d = (centre - last_good) % ru
    assert min(d, ru - d) < 2 * radar.BIN_M  # the search starts on the last plausible range
    # control: within the bound nothing happens
    mgr2 = make()
    scene2 = Scene(37_000.0, seed=5)
    run(mgr2, scene2, 6000, until=lambda o: o["mode"] == radar.CONFIRMED)
    outs = run(mgr2, scene2, 3, extra=lambda i, _: {"track.range_rate": 1.4e3})
    assert all(o["mode"] == radar.CONFIRMED for o in outs)
    assert math.isfinite(outs[-1]["range.resolved"])


def test_detection_resolved_at_zero_doppler_is_rejected_as_clutter() -> None:
    """Doppler coherence (issue 11): a stationary reflector (ground clutter, a target at a
    blind speed) is coherent over the three PRIs at 0 Hz; its resolution reaches the clutter
    notch and is rejected. Control: without the notch it is confirmed."""
    outs = run(make(clutter_notch_speed=5.0), Scene(37_000.0, rdot=0.0, seed=6), 6000)
    assert radar.CONFIRMED not in _modes(outs)
    assert radar.TENTATIVE in _modes(outs)  # it was detected and tried
    outs = run(make(), Scene(37_000.0, rdot=0.0, seed=6), 6000,
               until=lambda o: o["mode"] == radar.CONFIRMED)
    assert outs[-1]["mode"] == radar.CONFIRMED


def test_confirmed_doppler_bias_is_bounded_and_dropped_after_misses() -> None:
    """Issue 11 (c): the discriminator's bias ran away (−66 → −1776 Hz) in clutter. It is now
    bounded by 2·doppler_bias_max_speed/λ and dropped after doppler_bias_reset_misses missed
    dwells, the centre returning to the track range rate's Doppler."""
    mgr = make(doppler_track_delay=0.0)
    scene = Scene(37_000.0, rdot=-150.0, seed=8)
    outs = run(mgr, scene, 6000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert outs[-1]["mode"] == radar.CONFIRMED
    lam = mgr.wavelength
    b_max = 2.0 * mgr.doppler_bias_max_speed / lam
    mgr._track.doppler_bias = 5.0e3  # a diverged bias
    outs = run(mgr, scene, 40, until=lambda o: o["dwell.done"])
    assert abs(mgr._track.doppler_bias) <= b_max + 1e-9
    scene.present = False  # the target fades: misses
    outs = run(mgr, scene, 200, until=lambda o: mgr._track.misses >= 2)
    assert mgr._track.doppler_bias == 0.0
    pri = outs[-1]["pri"]
    fd = radar.fold_doppler(-2.0 * (-150.0) / lam, pri)
    assert outs[-1]["doppler.centre"] == pytest.approx(fd, abs=1e-6)
