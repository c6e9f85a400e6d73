"""Confirmed-tracking PRIs outside the acquisition PRIs' common blind bands (issue 11, session
11, branch env15; ``RadarManager.track_pri_bins``, models/manager/pri_choice.py
"Confirmed-tracking PRIs"; docs/envelope.md "Session 11").

The predicted-loss coverage is computed here with the two-pulse canceller's own formula,
|H(ν)|² = 2·sin²(πν) (unit noise gain), not with the code under test."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.manager import RadarManager
from axir.models.radar import conventions as radar
from axir.orchestrator.envelope import Cell

_D = RadarManager.defaults()
ACQ = (_D["pri1_bins"], _D["pri2_bins"], _D["pri3_bins"])
TRACK = tuple(int(x) for x in str(_D["track_pri_bins"]).replace(",", " ").split())
F_MAX = 2.0 * _D["max_speed"] / _D["wavelength"]  # [Hz] ±1500 m/s (max_speed)
F = np.arange(-F_MAX, F_MAX, 5.0)
CLUTTER_EDGE = 1.6e3  # [Hz] just above PRF_min/6 = 1.49 kHz: the band blind at every PRI


def _min_loss_db(ks: tuple[int, ...]) -> np.ndarray:
    """Smallest two-pulse canceller loss [dB] over the PRIs ``ks`` [bins] at each of F."""
    best = np.full(F.shape, np.inf)
    for k in ks:
        nu = F * k * radar.BIN_S
        g = np.maximum(2.0 * np.sin(np.pi * nu) ** 2, 1e-12)
        best = np.minimum(best, -10.0 * np.log10(g))
    return best


def _blind_width_hz(ks: tuple[int, ...], lo: float = CLUTTER_EDGE) -> float:
    """Widest run [Hz] of Dopplers with |f| ≥ ``lo`` where every PRI of ``ks`` predicts more
    than 3 dB of loss."""
    blind = (_min_loss_db(ks) > 3.0) & (np.abs(F) >= lo)
    widest = run = 0
    for b in blind:
        run = run + 1 if b else 0
        widest = max(widest, run)
    return widest * 5.0


def test_the_default_tracking_pris_leave_no_common_blind_band():
    assert TRACK, "the feature is on by default"
    assert set(TRACK).isdisjoint(ACQ)
    # the three acquisition PRIs: 8.3-10.5 kHz blind at all three (2.1 kHz wide)
    assert _blind_width_hz(ACQ) > 2000.0
    assert _min_loss_db(ACQ)[np.argmin(np.abs(F - 9400.0))] > 3.0
    # with the tracking PRIs: no band blind at every PRI outside the clutter band
    assert _blind_width_hz(ACQ + TRACK) == 0.0
    # each tracking PRI alone (the other eclipsed) still covers every band 2.2 kHz off 0
    for k in TRACK:
        assert _blind_width_hz((*ACQ, k), lo=2.2e3) == 0.0
    # and the step rate: no tracking PRI below 60 % of the shortest acquisition PRI
    assert min(TRACK) >= 0.6 * min(ACQ)


def test_track_pri_bins_is_validated_and_empty_turns_it_off():
    for bad in ("abc", "10", "200", "157,157", "157,128,140,150,160", "157;128", "30000"):
        with pytest.raises(ValueError, match="track_pri_bins"):
            RadarManager(track_pri_bins=bad)
    off = RadarManager(track_pri_bins="")
    assert off._all_ks == off._ks == ACQ
    on = RadarManager(track_pri_bins=" 157, 128 ")
    assert on._all_ks == (*ACQ, 157, 128)
    assert on._all_pris[3] == pytest.approx(157 * radar.BIN_S)


def _confirmed(m: RadarManager, rng_m: float, unf: float) -> None:
    """Put ``m`` in confirmed tracking at true range ``rng_m`` [m] on acquisition PRI 1 with
    the tracked unfolded Doppler ``unf`` [Hz] and a range rate that agrees with it."""
    m.mode = radar.CONFIRMED
    m._pri_idx = 0
    m._track.last_range = rng_m
    m._track.good_range = m._track.anchor_range = rng_m
    m._track.last_rate = -unf * m.wavelength / 2.0
    m._offset = (round(rng_m / radar.BIN_M) // ACQ[0]) * ACQ[0] * radar.BIN_M
    m._gate = rng_m - m._offset
    m._start_doppler_track(radar.fold_doppler(unf, m.pri), unf)
    m._track.conf_time = m.confirm_switch_delay  # confirmed long enough to switch (session 19)


def _loss_db(f: float, k: int) -> float:
    return -10.0 * math.log10(max(2.0 * math.sin(math.pi * f * k * radar.BIN_S) ** 2, 1e-12))


def test_the_switch_leaves_a_common_blind_band_for_a_tracking_pri():
    f = 9400.0  # blind (> 3 dB) at every acquisition PRI
    b = next(b for b in range(250, 4000)
             if all(min(b % k, k - b % k) >= 8 + 3 for k in ACQ + TRACK))
    rng_m = b * radar.BIN_M + 10.0
    off = RadarManager(track_pri_bins="")
    _confirmed(off, rng_m, f)
    off._switch_confirmed_pri()
    assert off._pri_idx < 3
    assert _loss_db(f, off._all_ks[off._pri_idx]) > 3.0  # nothing of the three helps
    m = RadarManager()
    _confirmed(m, rng_m, f)
    m._switch_confirmed_pri()
    j = m._pri_idx
    assert j >= 3 and m._track.pri_switches == 1
    k = m._all_ks[j]
    assert k in TRACK
    assert _loss_db(f, k) <= 3.0
    assert m.outputs()["pri"] == pytest.approx(k * radar.BIN_S)
    ru = k * radar.BIN_M
    assert m._offset % ru == 0.0 and m._offset + m._gate == pytest.approx(rng_m)
    assert m._doppler == pytest.approx(radar.fold_doppler(f + m.doppler_dither_fraction / m.pri,
                                                          m.pri))
    # eclipse margin: a range whose apparent range at one tracking PRI is within 8 bins of
    # 0 / Ru goes to the other one, or stays when both are eclipsed
    k1, k2 = TRACK[0], TRACK[1]
    b1 = next(b for b in range(250, 20000) if b % k1 < 4 and min(b % k2, k2 - b % k2) > 12)
    m1 = RadarManager()
    _confirmed(m1, b1 * radar.BIN_M, f)
    m1._switch_confirmed_pri()
    assert m1._all_ks[m1._pri_idx] != k1
    both = next(b for b in range(250, 200000) if b % k1 < 4 and b % k2 < 4)
    m2 = RadarManager()
    _confirmed(m2, both * radar.BIN_M, f)
    m2._switch_confirmed_pri()
    assert m2._pri_idx < 3


def test_a_track_on_a_tracking_pri_returns_to_a_clear_acquisition_pri():
    b = next(b for b in range(250, 4000)
             if all(min(b % k, k - b % k) >= 8 + 3 for k in ACQ + TRACK))
    rng_m = b * radar.BIN_M + 10.0
    m = RadarManager()
    _confirmed(m, rng_m, 9400.0)
    m._switch_confirmed_pri()
    assert m._pri_idx >= 3
    # the Doppler leaves the common band: a clear acquisition PRI (≤ 0 dB by the canceller's
    # formula) takes the track back (fewer steps per second); not while none is that clear
    f_clear = next(f for f in np.arange(11_000.0, 17_000.0, 10.0)
                   if min(_loss_db(f, k) for k in ACQ) <= -0.5)
    f_edge = next(f for f in np.arange(10_500.0, 12_000.0, 10.0)
                  if 0.5 < min(_loss_db(f, k) for k in ACQ) < 2.5
                  and _loss_db(f, m._all_ks[m._pri_idx]) <= 3.0)
    for f, back in ((f_edge, False), (f_clear, True)):
        m._track.doppler_unf = f
        m._track.last_rate = -f * m.wavelength / 2.0
        m._switch_confirmed_pri()
        assert (m._pri_idx < 3) == back
    assert min(_loss_db(f_clear, k) for k in ACQ) == pytest.approx(
        _loss_db(f_clear, m._all_ks[m._pri_idx]))
    # off: the track stays on the tracking PRI
    stay = RadarManager(track_pri_return=False)
    _confirmed(stay, rng_m, 9400.0)
    stay._switch_confirmed_pri()
    stay._track.doppler_unf = f_clear
    stay._track.last_rate = -f_clear * stay.wavelength / 2.0
    stay._switch_confirmed_pri()
    assert stay._pri_idx >= 3


def _noise_sum(gen: np.random.Generator, scale: float) -> np.ndarray:
    z = gen.normal(size=(16, 3)) + 1j * gen.normal(size=(16, 3))
    return 4.0 * scale * np.abs(z)


def test_a_tracking_pri_never_reaches_acquisition_or_tentative_and_survives_state():
    m = RadarManager()
    _confirmed(m, 20_000.0, 9400.0)
    m._switch_confirmed_pri()
    assert m._pri_idx >= 3
    # state round trip on a tracking PRI: the copy steps exactly as the original
    twin = RadarManager()
    twin.set_state(m.get_state())
    assert twin._pri_idx == m._pri_idx and twin.pri == m.pri
    gen1, gen2 = np.random.default_rng(5), np.random.default_rng(5)
    scale = math.sqrt(m.noise_power)
    inputs = {"track.range": 20_000.0, "track.range_rate": m._track.last_rate,
              "maneuver": 0.0}
    acq_pris = {k * radar.BIN_S for k in ACQ}
    modes = []
    for _ in range(6_000):
        o1 = m.step(m.pri, {**inputs, "sum": _noise_sum(gen1, scale)})
        o2 = twin.step(twin.pri, {**inputs, "sum": _noise_sum(gen2, scale)})
        assert o1["pri"] == o2["pri"] and o1["mode"] == o2["mode"]
        modes.append(o1["mode"])
        if o1["mode"] != radar.CONFIRMED:
            # no target: the track is dropped; acquisition (and any tentative a noise
            # detection opens) runs on the three acquisition PRIs only
            assert m._pri_idx < 3
            assert any(o1["pri"] == pytest.approx(p) for p in acq_pris)
            st = m.get_state()
            assert st["_pri_idx"] < 3
    assert modes[0] == radar.CONFIRMED and radar.ACQUISITION in modes
    # every acquisition PRI was visited after the drop (the passes cycle over the three)
    seen: set[int] = set()
    m2 = RadarManager()
    _confirmed(m2, 20_000.0, 9400.0)
    m2._switch_confirmed_pri()
    m2._drop_track()
    assert m2.mode == radar.ACQUISITION and m2._pri_idx < 3
    for passes in range(12):  # every later pass of the search (they cycle over the PRIs)
        m2._search.passes = passes
        m2._start_pass()
        assert m2._pri_idx < 3 and all(w[2] < 3 for w in m2._search.windows)
    m2._enter_tentative(5, 1000.0)  # a detection opens tentative: its PRI order
    assert sorted(m2._tent.order) == [0, 1, 2]
    m2._drop_track()
    for _ in range(5_000):
        o = m2.step(m2.pri, {**inputs, "sum": _noise_sum(gen1, scale)})
        if o["mode"] != radar.CONFIRMED:
            seen.add(round(o["pri"] / radar.BIN_S))
    assert seen == set(ACQ)


#: random draw 1's 6.2 g cell (benchmarks/bench_envelope_random.py draw_cells(90, 1)): its
#: Doppler ramps down through 8.3-10.5 kHz, blind at all three acquisition PRIs
CELL_11KM = Cell(range_m=11068.1, speed=-228.68, el_deg=2.08, rcs=0.146, g=6.19, seed=6,
                 az_deg=77.92, tangential=124.4, maneuver_onset=0.97)


def _run(cell: Cell, **rm: object) -> tuple[dict, list[tuple[int, float]]]:
    """The cell in the direct loop (as orchestrator.envelope.run_cell) with RadarManager
    overrides ``rm``; its summary and the (mode, pri) the manager output at every PRI."""
    from axir.models.loop import DirectLoop
    from axir.orchestrator import envelope

    orig = envelope.cell_parameters
    trace: list[tuple[int, float]] = []
    step = DirectLoop.step

    def traced(self: DirectLoop) -> None:
        step(self)
        o = self.out["RadarManager"]
        trace.append((int(o["mode"]), float(o["pri"])))

    try:
        envelope.cell_parameters = lambda c: {
            **orig(c), "RadarManager": {**orig(c)["RadarManager"], **rm}}
        DirectLoop.step = traced
        out = envelope.run_cell(cell)
    finally:
        envelope.cell_parameters = orig
        DirectLoop.step = step
    return out, trace


@pytest.mark.slow
def test_the_turning_target_in_the_common_blind_band_is_held():
    from engagement import assert_meets_goals

    out, trace = _run(CELL_11KM)
    assert_meets_goals(out)
    assert out["rms_range_error_m"] < 5.0
    acq = {round(k * radar.BIN_S, 12) for k in ACQ}
    track = {round(k * radar.BIN_S, 12) for k in TRACK}
    used = {round(p, 12) for mode, p in trace if mode == radar.CONFIRMED}
    assert used & track, "the track moved to a confirmed-tracking PRI"
    assert all(round(p, 12) in acq for mode, p in trace if mode != radar.CONFIRMED)
    # the feature off is main's radar: the same cell is dropped in the band
    off, trace_off = _run(CELL_11KM, track_pri_bins="")
    assert off["drops"] >= 1 and off["held_fraction"] < 0.95
    assert all(round(p, 12) in acq for _, p in trace_off)
