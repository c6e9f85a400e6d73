"""A confirmed track's coast through the clutter notch (issue 11, session 30;
models/tracker/notch.py, RadarManager ``notch_coast_time``): a target whose radial speed passes
through 0 at low elevation is held, its readings in the notch (the clutter's) not used."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from axir.models.manager import RadarManager
from axir.models.radar import conventions as radar
from axir.models.tracker import Tracker, notch
from axir.models.tracker.notch import NotchCoast
from axir.orchestrator.envelope import Cell, run_cell

LAMBDA = RadarManager.defaults()["wavelength"]
V_N, MAX_EL, T_CROSS = 5.0, math.radians(4.5), 3.0
R, EL = 10_000.0, math.radians(2.0)


def _axes(v_t: float, v_r: float, n: int = notch.MIN_N) -> list[SimpleNamespace]:
    """x, y, z filters of a target at 10 km, az 0, el 2°: radial speed v_r, v_t across (east)."""
    u = (0.0, math.cos(EL), math.sin(EL))
    pos = [R * c for c in u]
    vel = [v_t + v_r * u[0], v_r * u[1], v_r * u[2]]
    return [SimpleNamespace(pos=p, vel=v, n=n) for p, v in zip(pos, vel, strict=True)]


def _radial(axes: list[SimpleNamespace]) -> float:
    p = [f.pos for f in axes]
    return sum(a * f.vel for a, f in zip(p, axes, strict=True)) / math.hypot(*p)


def _tangential(axes: list[SimpleNamespace]) -> float:
    v2 = sum(f.vel * f.vel for f in axes)
    return math.sqrt(v2 - _radial(axes) ** 2)


def _run(nc: NotchCoast, axes: list[SimpleNamespace], rate: float, steps: int = 2000,
         el: float = EL) -> bool:
    on = False
    for _ in range(steps):
        on = nc(axes, rate, el, 1e-4)
    return on


def test_a_crossing_track_coasts_with_the_managers_range_rate():
    # 250 m/s across at 10 km: a_r = 6.25 m/s², −4 → +5 m/s in 1.4 s < 3 s
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    axes = _axes(250.0, -9.0)
    assert _run(nc, axes, -4.0) is True
    assert _radial(axes) == pytest.approx(-4.0, abs=1e-9)  # the manager's, not the filter's
    assert _tangential(axes) == pytest.approx(250.0, rel=1e-9)  # the rest is kept
    # the coast goes on through 0 and up to 1.5 × the speed (hysteresis), then ends
    assert nc(axes, 0.0, EL, 1e-4) and nc(axes, 7.4, EL, 1e-4)
    assert not nc(axes, 7.6, EL, 1e-4) and not nc.on
    assert nc(axes, -4.0, EL, 1e-4)  # a new entry is possible again


@pytest.mark.parametrize(("v_t", "rate", "el", "n", "why"), [
    (250.0, 3.0, EL, notch.MIN_N, "a receding target in the band is leaving it"),
    (250.0, -6.0, EL, notch.MIN_N, "outside the band"),
    (100.0, -4.0, EL, notch.MIN_N, "a_r = 1 m/s²: 9 s to cross, > 3 s"),
    (250.0, -4.0, math.radians(6.0), notch.MIN_N, "above the clutter regime"),
    (250.0, -4.0, EL, notch.MIN_N - 1, "a young track"),
    (250.0, math.nan, EL, notch.MIN_N, "no Doppler from the manager"),
])
def test_no_coast(v_t, rate, el, n, why):
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    axes = _axes(v_t, -9.0, n)
    before = [f.vel for f in axes]
    assert _run(nc, axes, rate, el=el) is False, why
    assert [f.vel for f in axes] == before  # nothing moved


def test_a_coast_that_outlasts_a_crossing_ends_and_waits_for_the_band_to_be_left():
    # the manager keeps reading ≈ 0 m/s (a target that turned to fly across the line of sight)
    nc = NotchCoast(V_N, MAX_EL, 0.5)  # notch_cross_time 0.5 s: at most 1 s of coast
    axes = _axes(400.0, -9.0)  # a_r = 16 m/s²: −4 → +5 m/s in 0.56 s > 0.5 s: no entry
    assert _run(nc, axes, 6.0, steps=1000) is False  # (averaging beside the band)
    assert _run(nc, axes, -4.0, steps=10) is False
    assert _run(nc, axes, -1.0, steps=10) is True  # 6 m/s in 0.375 s: coasts
    assert _run(nc, axes, 0.0, steps=9990) is True  # 1.0 s in all: still
    assert _run(nc, axes, 0.0, steps=20) is False  # past MAX_COASTS × 0.5 s: ended ...
    assert nc(axes, -1.0, EL, 1e-4) is False  # ... and not again while the band holds it
    assert nc(axes, 8.0, EL, 1e-4) is False  # the band is left
    assert nc(axes, -1.0, EL, 1e-4) is True  # a new crossing


def test_the_crossing_time_is_the_straight_flight_kinematics():
    # a_r·t ≥ v_n − ṙ: at −4 m/s the 9 m/s to +5 take 9/a_r; a_r = v_t²/r
    v_t = 200.0  # a_r = 4 m/s²: 2.25 s
    assert _run(NotchCoast(V_N, MAX_EL, 2.3), _axes(v_t, -9.0), -4.0) is True
    assert _run(NotchCoast(V_N, MAX_EL, 2.2), _axes(v_t, -9.0), -4.0) is False


def test_a_noisy_young_velocity_averages_out():
    # a slow radial target (4 m/s closing) whose filter velocity swings ±600 m/s across the line
    # of sight every 5 ms (angle noise × range): the filter's |v_t| says a_r ≈ 36 m/s², the
    # average ≈ 0 — no coast
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    coasts = 0
    for k in range(4000):  # averaged from MIN_N/2 readings on, tested from MIN_N on
        axes = _axes(600.0 if (k // 50) % 2 else -600.0, -4.0, notch.MIN_N // 2 + k)
        coasts += nc(axes, -4.0, EL, 1e-4)
    assert coasts == 0
    assert _tangential(_axes(600.0, -4.0)) ** 2 / R * T_CROSS > V_N + 4.0  # the filter's would


def test_a_restarted_average_and_a_missing_doppler():
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    axes = _axes(250.0, -9.0)
    assert nc(axes, -4.0, math.radians(6.0), 1e-4) is False  # above max_el: nothing averaged
    # below it again: no decision before the average holds MIN_AVERAGE × TAU of steps,
    # Σ dᵏ·dt = TAU·(1 − e^(−k·dt/TAU)) ≥ 0.3·TAU: k ≥ 714 steps of 0.1 ms
    k_min = math.ceil(-notch.TAU / 1e-4 * math.log(1.0 - notch.MIN_AVERAGE))
    assert k_min == 714
    assert _run(nc, axes, -4.0, steps=k_min - 2) is False
    assert _run(nc, axes, -4.0, steps=4) is True
    # a step without the manager's Doppler ends the coast, keeps a time-out's latch
    nc.t_on = 99.0
    assert nc(axes, math.nan, EL, 1e-4) is False and nc.t_on == 99.0
    assert nc(axes, -4.0, EL, 1e-4) is False  # still latched
    # a non-finite filter velocity is left out of the average
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    _run(nc, axes, 9.0, steps=100)
    axes[2].vel = math.nan
    nc(axes, 9.0, EL, 1e-4)
    assert all(math.isfinite(v) for v in nc.vbar)


def test_off_and_reset():
    assert _run(NotchCoast(0.0, MAX_EL, T_CROSS), _axes(250.0, -9.0), -4.0) is False
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    assert _run(nc, _axes(250.0, -9.0), -4.0)
    nc.reset()
    assert nc.on is False and nc.vbar == [0.0, 0.0, 0.0, 0.0]
    # above notch_coast_max_el: no coast, and the average starts again below it
    young = _axes(250.0, -9.0, notch.MIN_N - 1)  # averaged, not yet old enough to coast
    assert _run(nc, young, -4.0, steps=10) is False
    assert nc.vbar[3] > 0.0
    assert nc(young, -4.0, math.radians(6.0), 1e-4) is False
    assert nc.vbar == [0.0, 0.0, 0.0, 0.0]


def _confirmed_manager(**kw) -> RadarManager:
    m = RadarManager(**kw)
    m.mode = radar.CONFIRMED
    tr = m._track
    tr.conf_time, tr.seen_time, tr.last_rate, tr.last_range = 1.0, 0.5, -3.0, 10_000.0
    return m


def test_manager_keeps_a_track_whose_range_rate_is_in_the_notch():
    m = _confirmed_manager()
    assert m._notch_coast() is True and m._track.notch is True
    # beyond 1.5 × clutter_notch_speed, no range rate, confirmed < 0.5 s, 2.5 s unseen
    for attr, value in (("last_rate", 7.6), ("last_rate", math.nan), ("conf_time", 0.4),
                        ("seen_time", -1.5)):
        m = _confirmed_manager()
        setattr(m._track, attr, value)
        assert m._notch_coast() is False and m._track.notch is False, (attr, value)
    m = _confirmed_manager()
    m._track.last_rate = 7.4
    assert m._notch_coast() is True
    assert _confirmed_manager(notch_coast_time=0.0)._notch_coast() is False


def test_manager_searches_around_the_range_rates_doppler_while_coasting():
    m = _confirmed_manager()
    tr = m._track
    # 12 misses: the search cycle (0, −s, +s, −2s, +2s from doppler_bias_reset_misses = 2 on)
    # is back at its centre
    assert (m.miss_limit, m.doppler_bias_reset_misses, m.doppler_search_from_centre) == (
        10, 2, True)
    tr.misses = 12
    assert m._notch_coast()
    tr.good_doppler = 1234.0  # where the target was last seen
    m._follow_doppler(False)
    want = -2.0 * tr.last_rate / LAMBDA  # +188 Hz: the coasting range rate's Doppler
    assert tr.good_doppler == pytest.approx(want)
    assert m.outputs()["doppler.centre"] == pytest.approx(want)


@pytest.mark.parametrize(("rate", "kept"), [(-3.0, True), (20.0, False)])
def test_manager_drop_test_asks_the_notch_coast(rate, kept):
    # the tenth missed dwell: dropped unless the range rate is in the notch
    m = _confirmed_manager()
    m._track.last_rate = rate
    m._track.misses = m.miss_limit - 1
    m._end_confirmed_dwell(False)
    assert (m.mode == radar.CONFIRMED) is kept


def test_tracker_resets_the_coast_for_a_new_track_and_needs_a_velocity_state():
    core = Tracker().core
    for restart in (core._reset_track, lambda: core._start_handover(10_000.0)):
        core._notch.on, core._notch.vbar = True, [1.0, 2.0, 3.0, 4.0]
        restart()
        assert core._notch.on is False and core._notch.vbar == [0.0, 0.0, 0.0, 0.0]
    assert core._notch.speed == V_N
    vd = {f"filter_{a}": "vd" for a in "xyz"}  # no velocity state: no coast
    assert Tracker(**vd).core._notch.speed == 0.0
    s = run_cell(Cell(range_m=10e3, speed=-200.0, el_deg=2.0, rcs=10.0, seed=1, duration=1.0),
                 overrides={"Tracker": vd})
    assert s["lock_time"] is not None and s["drops"] == 0  # (it used to raise AttributeError)


CROSSING = Cell(range_m=10_000.0, speed=-10.0, el_deg=2.0, rcs=10.0, tangential=250.0,
                az_deg=30.0, seed=1, duration=3.0)


@pytest.mark.slow
def test_a_low_crossing_target_is_held_through_zero_doppler():
    # the radial speed runs −10 → +8.8 m/s (through 0 at 1.6 s) at 2° elevation
    s = run_cell(CROSSING)
    assert s["lock_time"] < 0.5
    assert s["held_fraction"] == 1.0 and s["drops"] == 0 and s["false_confirmations"] == 0
    assert s["rms_range_error_m"] < 10.0
    # without the coast, or with either half of it alone, it is dropped in the notch
    tracker_off, manager_off = {"notch_coast_speed": 0.0}, {"notch_coast_time": 0.0}
    for off in ({"Tracker": tracker_off, "RadarManager": manager_off}, {"Tracker": tracker_off},
                {"RadarManager": manager_off}):
        s = run_cell(CROSSING, overrides=off)
        assert s["drops"] >= 1 and s["held_fraction"] < 0.9, off
