"""A confirmed track's coast through the clutter notch (issue 11, session 30;
models/tracker/notch.py, RadarManager ``notch_coast_time``): a target whose radial speed passes
through 0 at low elevation is held, its readings in the notch (the clutter's) not used."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from axir.models.manager import RadarManager
from axir.models.radar import conventions as radar
from axir.models.tracker import Tracker, notch
from axir.models.tracker.notch import LineFit, NotchCoast
from axir.orchestrator.envelope import Cell, run_cell

LAMBDA = RadarManager.defaults()["wavelength"]
V_N, MAX_EL, T_CROSS = 5.0, math.radians(4.5), 6.0
R, EL, DT = 10_000.0, math.radians(2.0), 1e-4


class _Track:
    """x, y, z filters of a target at 10 km, az 0, el 2° at t = 0, flying straight at radial
    speed ``v_r`` and ``v_t`` across (east); the filters' velocity is the truth plus ``err``
    (x, y, z) [m/s], their positions the truth's plus ``dp`` (x, y, z) [m]."""

    def __init__(self, v_t: float, v_r: float, n: int = notch.MIN_N,
                 err: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        u = (0.0, math.cos(EL), math.sin(EL))
        self.p = [R * c for c in u]
        self.v = [v_t + v_r * u[0], v_r * u[1], v_r * u[2]]
        self.err = err
        self.dp = (0.0, 0.0, 0.0)
        self.axes = [SimpleNamespace(pos=0.0, vel=0.0, n=n) for _ in range(3)]
        self._show()

    def _show(self) -> None:
        for f, p, v, e, d in zip(self.axes, self.p, self.v, self.err, self.dp, strict=True):
            f.pos, f.vel = p + d, v + e

    def step(self, nc: NotchCoast, rate: float, el: float = EL, dt: float = DT) -> bool:
        """The decision at this position, then the target flies on ``dt``."""
        on = nc(self.axes, rate, el, dt)
        for f in self.axes:
            f.n += 1
        self.p = [p + v * dt for p, v in zip(self.p, self.v, strict=True)]
        velocities = [f.vel for f in self.axes]
        self._show()
        if on:  # a coasting filter keeps the velocity the coast gave it
            for f, v in zip(self.axes, velocities, strict=True):
                f.vel = v
        return on

    def run(self, nc: NotchCoast, rate: float, steps: int = 4000, el: float = EL) -> bool:
        on = False
        for _ in range(steps):
            on = self.step(nc, rate, el)
        return on


def _radial(axes: list[SimpleNamespace]) -> float:
    p = [f.pos for f in axes]
    return sum(a * f.vel for a, f in zip(p, axes, strict=True)) / math.hypot(*p)


def test_the_line_fit_is_the_weighted_least_squares_line():
    # reference: numpy's weighted polyfit over the same samples, weights e^(−age/τ), with a
    # PRI schedule that changes (100, 111.6, 64 µs) and noisy positions
    rng = np.random.default_rng(5)
    dts = np.concatenate([np.full(300, 100e-6), np.full(200, 111.6e-6), np.full(250, 64e-6)])
    t = np.cumsum(dts) - dts[0]
    truth = np.array([20_000.0, -3_000.0, 900.0]) + np.outer(t, [-120.0, 250.0, 3.0])
    pos = truth + rng.normal(0.0, 15.0, truth.shape)
    fit = LineFit(0.02)
    assert fit.velocity() is None
    for k in range(len(t)):
        fit.add(*pos[k], dts[k])
    w = np.exp(-(t[-1] - t) / 0.02)
    for axis in range(3):
        slope = np.polyfit(t, pos[:, axis], 1, w=np.sqrt(w))[0]
        assert fit.velocity()[axis] == pytest.approx(slope, rel=1e-9, abs=1e-9)
    assert fit.span() == pytest.approx(w.sum() * dts[-1], rel=1e-12)
    fit.reset()
    assert fit.velocity() is None and fit.span() == 0.0
    # a NaN, infinite or negative step leaves its sample out (a NaN PRI from a host would
    # otherwise turn the sums into NaN for the rest of the track)
    for k in range(3):
        fit.add(float(k), 2.0 * k, 0.0, 1e-3)
    before = list(fit.s)
    for bad in (math.nan, math.inf, -1e-3):
        fit.add(50.0, 50.0, 50.0, bad)
        assert fit.s == before, bad
    assert fit.velocity() == pytest.approx((1000.0, 2000.0, 0.0))  # 1 m, 2 m per ms


def test_a_crossing_track_coasts_on_its_fitted_velocity_and_the_managers_range_rate():
    # 250 m/s across at 10 km: a_r = 6.25 m/s², −4 → +5 m/s in 1.4 s < 6 s. The filter's
    # velocity is 100 m/s off upward and 9 m/s off along the line of sight (a track pulled by
    # clutter); the coast takes the positions' line fit across it, the manager's Doppler along
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    trk = _Track(250.0, -4.0, err=(30.0, -9.0 * math.cos(EL), 100.0))
    steps = 1
    while not trk.step(nc, -4.0):
        steps += 1
    assert steps == 2877  # once the fit holds MIN_FIT_SPAN (0.25 s)
    assert _radial(trk.axes) == pytest.approx(-4.0, abs=1e-3)  # the manager's (2.5 cm on)
    u = [f.pos / math.hypot(*trk.p) for f in trk.axes]
    e = [f.vel - v for f, v in zip(trk.axes, trk.v, strict=True)]
    e_los = sum(a * b for a, b in zip(e, u, strict=True))
    # across the line of sight: the truth, to 1 cm/s (the filter's ≈ 100 m/s off)
    assert math.dist(e, [e_los * c for c in u]) < 0.01
    # the coast goes on through 0 and up to 1.5 × the speed (hysteresis), then ends
    assert trk.step(nc, 0.0) and trk.step(nc, 7.4)
    assert not trk.step(nc, 7.6) and not nc.on
    assert trk.step(nc, -4.0)  # a new entry is possible again


@pytest.mark.parametrize(("v_t", "rate", "el", "n", "why"), [
    (250.0, 3.0, EL, notch.MIN_N, "a receding target in the band is leaving it"),
    (250.0, -6.0, EL, notch.MIN_N, "outside the band"),
    (60.0, -4.0, EL, notch.MIN_N, "a_r = 0.36 m/s²: 25 s to cross, > 6 s"),
    (250.0, -4.0, math.radians(6.0), notch.MIN_N, "above the clutter regime"),
    (250.0, math.nan, EL, notch.MIN_N, "no Doppler from the manager"),
])
def test_no_coast(v_t, rate, el, n, why):
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    trk = _Track(v_t, -4.0, n)
    assert trk.run(nc, rate, el=el) is False, why
    assert [f.vel for f in trk.axes] == trk.v  # nothing moved


def test_a_young_track_does_not_coast():
    # its fit is long enough (from MIN_N/2 readings on), the track not yet MIN_N readings old
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    trk = _Track(250.0, -4.0)
    for _ in range(4000):
        for f in trk.axes:
            f.n = notch.MIN_N - 1
        assert trk.step(nc, -4.0) is False
    assert nc.fit.span() >= notch.MIN_FIT_SPAN
    assert trk.step(nc, -4.0) is True  # (MIN_N readings)


def test_a_coast_that_outlasts_a_crossing_ends_and_waits_for_the_band_to_be_left():
    # the manager keeps reading ≈ 0 m/s (a target that turned to fly across the line of sight)
    nc = NotchCoast(V_N, MAX_EL, 0.5)  # notch_cross_time 0.5 s: at most 1 s of coast
    trk = _Track(400.0, -4.0)  # a_r = 16 m/s²: −4 → +5 m/s in 0.56 s > 0.5 s: no entry
    assert trk.run(nc, 6.0, steps=3000) is False  # (fitting beside the band)
    assert trk.run(nc, -4.0, steps=10) is False
    assert trk.run(nc, -1.0, steps=10) is True  # 6 m/s in 0.375 s: coasts
    assert trk.run(nc, 0.0, steps=9990) is True  # 1.0 s in all: still
    assert trk.run(nc, 0.0, steps=20) is False  # past MAX_COASTS × 0.5 s: ended ...
    assert trk.step(nc, -1.0) is False  # ... and not again while the band holds it
    assert trk.step(nc, 8.0) is False  # the band is left
    assert trk.step(nc, -1.0) is True  # a new crossing


def test_the_crossing_time_is_the_straight_flight_kinematics():
    # a_r·t ≥ v_n − ṙ: at −4 m/s the 9 m/s to +5 take 9/a_r; a_r = v_t²/r
    v_t = 200.0  # a_r = 4 m/s²: 2.25 s
    assert _Track(v_t, -4.0).run(NotchCoast(V_N, MAX_EL, 2.3), -4.0) is True
    assert _Track(v_t, -4.0).run(NotchCoast(V_N, MAX_EL, 2.2), -4.0) is False


def test_angle_noise_does_not_make_a_crossing():
    # a slow radial target (4 m/s closing): its filtered positions carry angle noise × range
    # across the line of sight (σ 10 m ≈ 1 mrad at 10 km, correlated over 10 ms: AR(1); with
    # MIN_FIT_SPAN 0.06 s this coasted, and σ 15 m still does: notch.py), and
    # its filter velocity swings ±600 m/s every 5 ms. Straight flight at the filter's velocity
    # would cross the notch within notch_cross_time (a_r = 36 m/s²); the positions' line fit
    # sees a few tens of m/s — no coast
    rng = np.random.default_rng(7)
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    trk = _Track(0.0, -4.0, notch.MIN_N // 2)
    rho = math.exp(-DT / 0.01)
    noise = np.zeros(2)
    coasts, filter_would = 0, 0
    for k in range(6000):  # fitted from MIN_N/2 readings on, tested from MIN_N on
        noise = rho * noise + math.sqrt(1.0 - rho * rho) * rng.normal(0.0, 10.0, 2)
        trk.err = (600.0 if (k // 50) % 2 else -600.0, 0.0, 0.0)
        trk.dp = (noise[0], 0.0, noise[1])  # across: east, and up
        trk._show()
        v2 = sum(f.vel * f.vel for f in trk.axes)
        filter_would += (v2 - _radial(trk.axes) ** 2) * T_CROSS >= (V_N + 4.0) * R
        coasts += trk.step(nc, -4.0)
    assert coasts == 0
    assert filter_would == 6000  # the filter's velocity would have coasted at every step
    v = nc.fit.velocity()
    assert v is not None and 1.0 < math.hypot(v[0], v[2]) < 60.0  # the fit saw the noise


def test_a_restarted_fit_and_a_missing_doppler():
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    trk = _Track(250.0, -4.0)
    assert trk.step(nc, -4.0, el=math.radians(6.0)) is False  # above max_el: nothing fitted
    # below it again: no decision before the fit holds MIN_FIT_SPAN,
    # Σ dᵏ·dt = dt·(1 − dᵏ)/(1 − d) ≥ 0.25 s, d = e^(−dt/TAU_FIT): k ≥ 2877 steps of 0.1 ms
    d = math.exp(-DT / notch.TAU_FIT)
    k_min = math.ceil(math.log(1.0 - notch.MIN_FIT_SPAN * (1.0 - d) / DT) / math.log(d))
    assert k_min == 2877
    assert trk.run(nc, -4.0, steps=k_min - 1) is False
    assert trk.run(nc, -4.0, steps=1) is True
    # a step without the manager's Doppler ends the coast, keeps a time-out's latch
    nc.t_on = 99.0
    assert trk.step(nc, math.nan) is False and nc.t_on == 99.0
    assert trk.step(nc, -4.0) is False  # still latched
    # a non-finite position is left out of the fit
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    trk.run(nc, 9.0, steps=100)
    trk.axes[2].pos = math.nan
    nc(trk.axes, 9.0, EL, DT)
    assert all(math.isfinite(v) for v in nc.fit.s)


def test_off_and_reset():
    assert _Track(250.0, -4.0).run(NotchCoast(0.0, MAX_EL, T_CROSS), -4.0) is False
    nc = NotchCoast(V_N, MAX_EL, T_CROSS)
    assert _Track(250.0, -4.0).run(nc, -4.0)
    nc.reset()
    assert nc.on is False and nc.fit.s == [0.0] * 9
    # above notch_coast_max_el: no coast, and the fit starts again below it
    young = _Track(250.0, -4.0, notch.MIN_N - 20)  # fitted, not yet old enough to coast
    assert young.run(nc, -4.0, steps=10) is False
    assert nc.fit.s[0] > 0.0
    assert young.step(nc, -4.0, el=math.radians(6.0)) is False
    assert nc.fit.s == [0.0] * 9


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
        core._notch.on = True
        core._notch.fit.add(1.0, 2.0, 3.0, 1e-4)
        restart()
        assert core._notch.on is False and core._notch.fit.s == [0.0] * 9
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
