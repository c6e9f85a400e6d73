"""Issue 11 engagements in the direct loop (tests/engagement.py, clutter on, seeded): each
failure class of the issue, short runs. Marked slow: 5-9 s each, ≈ 40 s together.

Against the models before issue 11 the head-on (b) and receding (c) tests fail (off-target
confirmed PRIs, 4e6 m/s tracks, drops); the far-target and clutter-only tests guard the
properties (no false track, no runaway) but did not reproduce the issue's false track within
their 2-3 s on the old models."""

from __future__ import annotations

import pytest
from engagement import ON_TARGET_M, run

from axir.models.manager.ambiguity import DEFAULT_PRI_BINS
from axir.models.radar import conventions as radar

pytestmark = pytest.mark.slow


def _sane(o) -> None:
    """No false confirmation, no track faster than the manager's max_speed bound (+ the
    tracker's: 1500 m/s) once the track is doppler_track_delay old (the manager's
    plausibility contract; before that a fresh track's α-β rate overshoots: 1869 m/s for a
    −700 m/s target confirmed at 0.036 s, range error ≤ 16 m), never a runaway (the issue's
    1e6 m/s), the confirmed gate inside the instrumented range."""
    assert o.false_confirmations == 0, o.line()
    assert o.off_target_pris == 0, o.line()
    assert o.max_settled_speed <= 1500.0 + 1e-6, o.line()
    assert o.max_track_speed <= 5000.0, o.line()
    assert o.min_gate_true >= 0.0, o.line()


@pytest.mark.parametrize("seed", [1, 2])
def test_far_low_target_beyond_two_ru_never_makes_a_false_track(seed):
    """(a) 42 km (beyond 2·Ru), 1° elevation, clutter below the beam: the issue saw confirmed
    false tracks 25-55 km off running away at 1e6 m/s. Now: none (acquired or not)."""
    o = run(2.0, r0=42_000.0, rdot=-200.0, el_deg=1.0, seed=seed)
    _sane(o)
    if o.confirmed_pris:
        assert o.rms_range < ON_TARGET_M


def test_target_free_clutter_at_half_a_degree_is_never_confirmed():
    o = run(3.0, r0=20_000.0, rdot=0.0, el_deg=0.5, rcs=0.0, seed=3)
    assert o.confirmed_pris == 0 and o.false_confirmations == 0, o.line()
    assert o.tentatives <= 6, o.line()  # issue: 3.6-4.7 tentative attempts per second


def test_fast_head_on_target_is_acquired_on_target():
    """(b) −700 m/s head-on at 20 km, 3°: the issue locked after 8.9 s."""
    o = run(2.5, r0=20_000.0, rdot=-700.0, el_deg=3.0, seed=1)
    _sane(o)
    assert o.on_target_time < 2.5, o.line()


def test_receding_target_held_across_one_ru():
    """(c) receding at +300 m/s across Ru = 15 km (5°): acquired and held, no drop."""
    o = run(3.0, r0=14_000.0, rdot=300.0, el_deg=5.0, seed=1)
    _sane(o)
    assert o.on_target_time < 0.5 and o.drops == 0, o.line()
    assert o.timeline[-1][1] == radar.CONFIRMED
    assert o.rms_range < 10.0, o.line()


# ------------------------------------------------------- main-beam clutter (issue 11, radar5)
def test_low_target_in_main_beam_clutter_is_acquired_within_a_second():
    """20 km, 1° elevation (the beams see the ground through their main lobe), 10 m²,
    −53 m/s: before the elevation-switched MTI and the residue-aware CFAR it was never
    acquired in 1.2 s (clutter leak through the Doppler filters' skirts); now on target
    within 1 s, held, no false confirmation."""
    o = run(1.2, r0=20_000.0, rdot=-53.15, el_deg=1.0, rcs=10.0, seed=1)
    _sane(o)
    assert o.on_target_time < 1.0 and o.drops == 0, o.line()
    assert o.timeline[-1][1] == radar.CONFIRMED


def test_target_free_main_beam_clutter_raises_no_acquisition_false_alarm_burst():
    """Target-free, antenna at 1° (MTI on): the canceller's residue is common to the 4 beams;
    with the thermal (4-look) threshold it raised ≈ 4 false alarms a second (8 in 2 s, design
    0.08/s); the one-look-per-PRI law keeps the tentative attempts near design."""
    o = run(3.0, r0=20_000.0, rdot=0.0, el_deg=1.0, rcs=0.0, seed=1)
    assert o.confirmed_pris == 0 and o.false_confirmations == 0, o.line()
    assert o.tentatives <= 2, o.line()


@pytest.mark.parametrize("el_deg", [2.0, 3.0])
def test_target_free_partly_common_residue_keeps_the_design_false_alarm_rate(el_deg):
    """Target-free at 2-3° (MTI on, the residue 1-5 × the thermal noise of the filters
    1-2 kHz from the clutter line, below the 1.6 × thermal switch): before session 21's
    residue share (models/manager/residue.py) 7 and 9 tentative attempts in 3 s (1.4-2.5 %
    of the acquisition dwells against the design 4.8·10⁻⁴, ≈ 0.2 in 3 s); now at most one."""
    o = run(3.0, r0=20_000.0, rdot=0.0, el_deg=el_deg, rcs=0.0, seed=1)
    assert o.confirmed_pris == 0 and o.false_confirmations == 0, o.line()
    assert o.tentatives <= 1, o.line()


# ------------------------------------------ confirmed Doppler in main-beam clutter (radar6)
@pytest.mark.parametrize("el_deg, rdot", [(3.0, -300.0), (0.5, 400.0)])
def test_target_in_main_beam_clutter_held_without_drop(el_deg, rdot):
    """20 km, 10 m², main-beam clutter: on main at 2ddc2e2 both dropped once in 1.2 s (RMS
    range 16.4 m and 7.1 m): the three-filter Doppler discriminator is blind within
    ±0.05·PRF and random-walked the centre, then the base hand-over to the track range rate
    moved it hundreds of Hz off the target. The dithered centre filter
    (models/manager/doppler_track.py) holds them: no drop, RMS range ≤ 10 m."""
    o = run(1.2, r0=20_000.0, rdot=rdot, el_deg=el_deg, rcs=10.0, seed=1)
    _sane(o)
    assert o.on_target_time < 1.0 and o.drops == 0, o.line()
    assert o.timeline[-1][1] == radar.CONFIRMED
    assert o.rms_range <= 10.0, o.line()


def test_speed_blind_on_the_first_acquisition_pri_is_acquired_within_a_second():
    """−478.4 m/s: the Doppler 30 kHz is 3 × PRF 1, folded onto 0 Hz (the MTI notch) at
    PRI 1 but clear at PRIs 2 and 3 (0.165, 0.345 of their PRF). Acquisition used to try
    the other PRIs only a pass later (≈ 0.5 s); now the window on the designation is
    searched at the three PRIs in a row (acq_all_pri_windows)."""
    lam = radar.DEFAULT_WAVELENGTH
    prf1 = 1.0 / (DEFAULT_PRI_BINS[0] * radar.BIN_S)
    rdot = -3.0 * prf1 * lam / 2.0
    o = run(1.2, r0=20_000.0, rdot=rdot, el_deg=1.0, rcs=10.0, seed=1)
    _sane(o)
    assert o.on_target_time < 0.3 and o.drops == 0, o.line()
