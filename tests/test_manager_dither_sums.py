"""The confirmed Doppler loop on weak targets (issue 11, session 25; models/manager/
doppler_track.py ``_dither_update``, ``doppler_disc_pairs``, ``doppler_search_from_centre``;
params.py ``miss_limit``).

Unit level: synthetic dither dwells whose central bins hold a target of a known offset δ from
the undisplaced centre (amplitudes |H(δ ∓ Δ)| of the one-pole resonator,
``doppler.resonator_gain``) over a flat noise level. End to end: random draw 8's turning cell,
dropped with session 24's settings, held with the defaults."""

from __future__ import annotations

import math

import numpy as np
import pytest
from designation import MANAGER_S24

from axir.models.manager import RadarManager
from axir.models.manager.doppler import resonator_gain
from axir.models.manager.doppler_track import dither_offset, half_width
from axir.models.radar.conventions import CENTRE_FILTER, GATE_BIN, N_BINS, N_DOPPLER, fold_doppler

CF = CENTRE_FILTER - 1
CENTRAL = (GATE_BIN - 2, GATE_BIN - 1, GATE_BIN)  # 0-based bins 6, 7, 8
WEIGHTS = (0.5, 1.0, 0.5)
NOISE = 4.0  # the side bins' mean SUM over the dwell (any unit)


def _dwell(excess: float) -> np.ndarray:
    """A dwell accumulator: NOISE in every cell, plus ``excess`` × WEIGHTS (sum 2 × excess)
    in the centre filter's central bins."""
    acc = np.full((N_BINS, N_DOPPLER), NOISE)
    for b, w in zip(CENTRAL, WEIGHTS, strict=True):
        acc[b, CF] += excess * w
    return acc


def _manager(**kw) -> RadarManager:
    m = RadarManager(doppler_disc_rician=False, **kw)
    m._track.dither_sign = 1
    return m


def _pair(m: RadarManager, delta: float, amp: float, ok: bool = True) -> tuple[float, float]:
    """A +Δ dwell then a −Δ dwell of a target ``delta`` cycles off the undisplaced centre
    whose filter-centred excess is ``amp`` (central bins' sum 2 × amp × |H|/|H(0)|)."""
    dither, pole = m.doppler_dither_fraction, m.doppler_pole
    h0 = resonator_gain(np.array([0.0]), pole)[0]
    out = []
    for sign in (1, -1):
        assert m._track.dither_sign == sign
        g = resonator_gain(np.array([delta - sign * dither]), pole)[0] / h0
        m._dwell.acc = _dwell(amp * g)
        out.append(m._dither_update(ok))
    return out[0], out[1]


@pytest.mark.parametrize("delta", [-0.012, -0.004, 0.0, 0.003, 0.011])
def test_a_strong_pair_reads_its_offset_at_once(delta):
    """a/n ≫ doppler_disc_snr on both dwells: the pair alone measures δ (the ratio of the
    resonator's gains inverted by dither_offset), and the sums restart."""
    m = _manager()
    d_plus, d = _pair(m, delta, 20.0 * NOISE)
    assert math.isnan(d_plus)
    assert d * m.pri == pytest.approx(delta, abs=2e-4)
    assert m._track.disc_pairs == 0 and not m._track.disc_sum.any()


def test_weak_pairs_are_summed_until_the_threshold_and_read_the_same_offset():
    """The pair's mean excess 1.8 × the level per dwell: below doppler_disc_snr (3) for one
    pair and for 2 (3/√2 = 2.12), above for 3 (3/√3 = 1.73); the summed pairs read the
    offset of one clean pair (the ratio of sums)."""
    m = _manager()
    delta = 0.005
    h0 = resonator_gain(np.array([0.0]), 0.9)[0]
    g_mean = sum(resonator_gain(np.array([delta - s * 0.006]), 0.9)[0] for s in (1, -1)) / 2
    amp = 0.9 * NOISE * h0 / g_mean  # mean excess per dwell: 2 × amp × g_mean/h0 = 1.8 NOISE
    for k in (1, 2):
        _, d = _pair(m, delta, amp)
        assert math.isnan(d) and m._track.disc_pairs == k
    _, d = _pair(m, delta, amp)
    assert d * m.pri == pytest.approx(delta, abs=2e-4)
    assert m._track.disc_pairs == 0


def test_one_pair_at_a_time_never_reads_a_weak_target():
    """doppler_disc_pairs = 1 (session 24's rule): the same weak pairs are never measured."""
    m = _manager(doppler_disc_pairs=1)
    h_lo = resonator_gain(np.array([0.011]), 0.9)[0] / resonator_gain(np.array([0.0]), 0.9)[0]
    for _ in range(20):
        _, d = _pair(m, 0.005, 0.9 * NOISE / h_lo)
        assert math.isnan(d)
        assert m._track.disc_pairs == 0


@pytest.mark.parametrize("sign", [1, -1])
def test_a_pair_with_one_sign_at_the_noise_reads_toward_the_other(sign):
    """The target so far off that the far dwell holds noise only (excess 0): the pair's sum
    passes, the ratio lies beyond the table and reads its end, on the target's side (session
    24's rule wanted each sign clear, and the centre never moved: random draw 8, 120 Hz)."""
    m = _manager()
    m._dwell.acc = _dwell(10.0 * NOISE if sign > 0 else 0.0)
    assert math.isnan(m._dither_update(True))
    m._dwell.acc = _dwell(0.0 if sign > 0 else 10.0 * NOISE)
    d = m._dither_update(True)
    end = dither_offset(1e300, m.doppler_dither_fraction, m.doppler_pole)
    assert d * m.pri == pytest.approx(sign * end)
    assert end > half_width(m.doppler_pole)  # beyond the 3 dB half-width
    each = _manager(doppler_disc_together=False, doppler_disc_pairs=1)  # session 24's rule
    each._dwell.acc = _dwell(10.0 * NOISE if sign > 0 else 0.0)
    each._dither_update(True)
    each._dwell.acc = _dwell(0.0 if sign > 0 else 10.0 * NOISE)
    assert math.isnan(each._dither_update(True))


def test_noise_alone_restarts_the_sums_after_doppler_disc_pairs():
    m = _manager(doppler_disc_pairs=5)
    for k in range(1, 5):
        _, d = _pair(m, 0.0, 0.0)
        assert math.isnan(d) and m._track.disc_pairs == k
    _, d = _pair(m, 0.0, 0.0)
    assert math.isnan(d)
    assert m._track.disc_pairs == 0 and not m._track.disc_sum.any()


def test_a_bad_dwell_restarts_and_its_pair_is_not_measured():
    """A dwell that is not ok (a non-finite sample, a stall) empties the sums; the −Δ dwell
    after a bad +Δ dwell has no pair and is not added (a ratio of one −Δ dwell to nothing)."""
    m = _manager()
    h_lo = resonator_gain(np.array([0.011]), 0.9)[0] / resonator_gain(np.array([0.0]), 0.9)[0]
    _pair(m, 0.005, 0.9 * NOISE / h_lo)
    assert m._track.disc_pairs == 1
    m._dwell.acc = _dwell(50.0)
    assert math.isnan(m._dither_update(False))  # the +Δ dwell is bad
    assert m._track.disc_pairs == 0 and not m._track.disc_sum.any()
    m._dwell.acc = _dwell(50.0)
    assert math.isnan(m._dither_update(True))
    assert m._track.disc_pairs == 0 and not m._track.disc_sum.any()
    _, d = _pair(m, -0.004, 20.0 * NOISE)  # the next clean pair reads at once
    assert d * m.pri == pytest.approx(-0.004, abs=2e-4)


@pytest.mark.parametrize("from_centre, steps", [(True, [0, -1, 1, -2, 2, 0]),
                                                 (False, [-1, 1, -2, 2, -1, 1])])
def test_the_doppler_search_after_misses(from_centre, steps):
    """After doppler_bias_reset_misses missed dwells the centre is searched around the last
    detecting dwell's undisplaced centre G: G itself first (default), then ±s, ±2s."""
    m = RadarManager(doppler_search_from_centre=from_centre, miss_limit=100)
    tr = m._track
    pri = m.pri
    g = 1234.5
    s = m.doppler_search_halfwidths * half_width(m.doppler_pole) / pri
    for i, k in enumerate(steps):
        tr.misses = m.doppler_bias_reset_misses + i
        tr.good_doppler = g
        m._follow_doppler(False)
        assert m._doppler == pytest.approx(fold_doppler(g + k * s, pri), abs=1e-9)
        assert tr.doppler_bias == 0.0 and tr.dither_sign == 1


# ------------------------------------------------------------------------- end to end
#: random draw 8 (benchmarks/bench_envelope_random.py --draw-seed 8): 17.4 km, −21.47 m/s,
#: 72.27°, 0.443 m² (19.7 dB filtered), a 2.3 g turn from 1.14 s, seed 3
DRAW8 = dict(range_m=17368.2, speed=-21.47, el_deg=72.27, rcs=0.443, g=2.3, seed=3,
             az_deg=227.72, tangential=174.6, maneuver_onset=1.14)


@pytest.mark.parametrize("manager, dropped", [({}, False), (MANAGER_S24, True)])
def test_a_weak_turning_target_is_held(manager, dropped):
    """The turn moves the target's Doppler by ≈ 550 Hz/s; with session 24's rules the pairs
    never passed (one sign 120 Hz off at the noise), two noise misses started the search off
    the centre and five misses dropped the track at 2.82 s with its range right; with the
    defaults it is held to the end, on the target."""
    from axir.orchestrator.envelope import Cell, run_cell

    r = run_cell(Cell(**DRAW8), overrides={"RadarManager": manager})
    assert r["false_confirmations"] == 0
    assert r["lock_time"] < 0.2
    if dropped:
        assert r["drops"] >= 1 and r["held_fraction"] < 0.95
    else:
        assert r["drops"] == 0 and r["held_fraction"] == 1.0
        assert r["rms_range_error_m"] < 10.0
