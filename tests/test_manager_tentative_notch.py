"""Tentative tracking with one PRI in the MTI notch (issue 11, docs/clutter.md "Tentative in
the notch"): the manager's tentative logic (models/manager/tentative.py) driven dwell by dwell
with scripted Th2 detections and Doppler readings, and the engagement the lead traced (slow).

Target of the unit tests: the lead's 25 km / −900 m/s case. Its Doppler +56 440 Hz
(2·900 m/s / λ) folds to 0.648 cycles at PRI 1, 0.958 at PRI 2 (−0.042·PRF: in the canceller's
notch, −14.6 dB) and 0.297 at PRI 3."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.manager import RadarManager
from axir.models.manager.ambiguity import range_to_bin
from axir.models.manager.doppler_search import blind_mask, consistent_notch_hz, fold_cycles
from axir.models.radar import conventions as radar

R0 = 25_000.0
F_TRUE = 2.0 * 900.0 / radar.DEFAULT_WAVELENGTH  # [Hz], closing at 900 m/s
_C = radar.GATE_BIN - 1
_CF = radar.CENTRE_FILTER - 1


def _manager() -> RadarManager:
    # the scripted readings stand for the final Doppler readings: no peak search (its dwells
    # read the accumulated cells, which the script does not fill)
    return RadarManager(designation_range=R0, doppler_peak_dwells=0)


#: excess over the noise level of a weak detection (a false alarm, the target in the notch: 0.8-1.8
#: traced) and of a strong one (the target clear of the notch: 2.8-13.7)
WEAK, STRONG = 1.0, 5.0


def _script(mgr: RadarManager, readings: dict[int, list[float | None]], max_dwells: int = 200,
            excess: float = WEAK) -> None:
    """Drive tentative dwells: at PRI index i the next entry of ``readings[i]`` is the folded
    Doppler [Hz] read by a detection in the central bin when the window covers the true range
    (None or no entry left: a miss), its excess over the noise level ``excess``. Stops when the
    manager leaves the PRI search."""
    bin_true = range_to_bin(R0)
    state = {"fd": 0.0}

    def track_test(_filters: slice) -> tuple[int, int]:
        i = mgr._pri_idx
        k = mgr._ks[i]
        d = (bin_true - range_to_bin(mgr._gate)) % k
        d = d - k if d > k // 2 else d
        queue = readings.get(i, [])
        if abs(d) > 1 or not queue:
            return -1, -1
        fd = queue.pop(0)
        if fd is None:
            return -1, -1
        state["fd"] = fd
        return _C + d, _CF

    mgr._track_test = track_test
    mgr._measured_doppler = lambda row, noise, f: (state["fd"], 0.0)  # (reading, extra tol)
    mgr._reading_excess = lambda row, noise: excess
    for _ in range(max_dwells):
        if mgr.mode != radar.TENTATIVE or mgr._tent.confirming:
            return
        mgr._end_tentative_dwell(True)


def _enter(mgr: RadarManager, fd: float, pri_idx: int = 0) -> None:
    mgr._pri_idx = pri_idx
    mgr._enter_tentative(range_to_bin(R0) % mgr._ks[pri_idx], fd)


def _fold_hz(f: float, prf: float) -> float:
    return float(np.mod(f, prf))


def test_blind_mask_and_notch_consistency_by_hand():
    """Blind = folding within the fraction of the PRF of 0 Hz, on both sides of every
    multiple of the PRF (values worked by hand)."""
    prf = 10_000.0
    f = np.array([0.0, 900.0, -900.0, 10_950.0, 1_100.0, 5_000.0, 29_050.0])
    assert blind_mask(f, prf, 0.1).tolist() == [True, True, True, True, False, False, True]
    assert consistent_notch_hz(f, prf, 0.1).tolist() == [0.0, 900.0, -900.0, 10_950.0,
                                                         29_050.0]


def test_given_up_pri_keeps_only_the_candidates_blind_there():
    """PRI 1 measured, the next PRI never detects: when it is given up (tent_blind_fraction),
    the hypothesis "blind there" leaves only the Doppler candidates folding into its notch,
    and the true Doppler is one of them (main: the candidates were kept unrestricted and the
    resolution's best candidate, not blind at the given-up PRI, was rejected)."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    f1 = _fold_hz(F_TRUE, prfs[0])
    _enter(mgr, f1)
    t = mgr._tent
    _script(mgr, {0: [f1]})  # PRI 1 found; nothing at the other PRIs
    assert t.skipped >= 0
    prf_s = prfs[t.skipped]
    assert t.dcands.size > 0
    assert np.all(fold_cycles(t.dcands, prf_s) <= mgr.tent_blind_fraction + 1e-12)
    assert np.min(np.abs(t.dcands - F_TRUE)) <= mgr.doppler_tol_fraction * prfs[0]


def test_the_skipped_pri_is_the_blind_one_then_resolution_is_the_true_doppler():
    """The true target: found at PRI 1 and PRI 3 (precise readings), never at PRI 2 (in the
    notch). Resolution on two PRIs → M of N at a PRI other than PRI 2, centred on a Doppler
    within the coherence tolerance of the truth folded there."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    _enter(mgr, _fold_hz(F_TRUE, prfs[0]))
    _script(mgr, {0: [_fold_hz(F_TRUE, prfs[0])], 2: [_fold_hz(F_TRUE, prfs[2])] * 50})
    t = mgr._tent
    assert mgr.mode == radar.TENTATIVE and t.confirming
    assert t.skipped == 1
    assert mgr._pri_idx != 1
    prf_c = 1.0 / mgr.pri
    assert fold_cycles(t.doppler - F_TRUE, prf_c) <= mgr.doppler_tol_fraction


def test_a_detection_in_the_notch_is_not_read_as_a_precise_doppler():
    """At PRI 2 the target is found in the notch but its reading is biased (+0.110·PRF, as
    traced: fold 0.068 for a true 0.958): it only says "in the notch", so the true Doppler stays
    a candidate and the resolution with PRI 3 is right (main: the reading removed the truth,
    PRI 3 was then searched for the wrong Doppler or the wrong alias resolved)."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    biased = _fold_hz(F_TRUE, prfs[1]) + 0.110 * prfs[1]
    _enter(mgr, _fold_hz(F_TRUE, prfs[0]))
    _script(mgr, {0: [_fold_hz(F_TRUE, prfs[0])], 1: [biased] * 50,
                  2: [_fold_hz(F_TRUE, prfs[2])] * 50})
    t = mgr._tent
    assert mgr.mode == radar.TENTATIVE and t.confirming
    assert len(t.meas) == 3  # range coherence at the three PRIs
    assert abs(t.doppler - F_TRUE) <= mgr.doppler_tol_fraction * min(prfs)


def test_a_false_alarm_at_the_blind_pri_is_retro_skipped():
    """At PRI 2 (target blind) a noise detection with a precise-looking reading 0.29·PRF off is
    coherent with the many PRI-1 candidates and narrows them wrongly; at PRI 3 the true target
    is incoherent with it but coherent with PRI 1: PRI 2 is given up after the fact, and the
    resolution is the true Doppler."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    noise = _fold_hz(F_TRUE, prfs[1]) - 0.29 * prfs[1]
    _enter(mgr, _fold_hz(F_TRUE, prfs[0]))
    t = mgr._tent
    t.order = [0, 1, 2]  # PRI 2 second, as in the trace
    _script(mgr, {0: [_fold_hz(F_TRUE, prfs[0])], 1: [noise] * 50,
                  2: [_fold_hz(F_TRUE, prfs[2])] * 50})
    assert mgr.mode == radar.TENTATIVE and t.confirming
    assert t.skipped == 1
    assert abs(t.doppler - F_TRUE) <= mgr.doppler_tol_fraction * min(prfs)


def test_a_blind_speed_uses_the_notch_readings_as_values():
    """+150 m/s folds to 0.059 / 0.007 / 0.950 cycles at PRI 1 / 2 / 3: in the notch at every
    PRI (the lost sweep cells 3° / 25 km / +150 m/s, seeds 1 and 2). PRI 1 weak in the notch
    (an interval), PRI 2 never found: the given-up PRI is the second blind one, so PRI 1's
    reading is taken as a value after all; PRI 3 (weak, in the notch) is a value too, and the
    resolution is the true Doppler (before: the attempt fell back to acquisition)."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    f150 = 2.0 * 150.0 / radar.DEFAULT_WAVELENGTH
    assert [round(float(fold_cycles(f150, p)), 2) for p in prfs] == [0.06, 0.01, 0.05]
    _enter(mgr, _fold_hz(f150, prfs[0]))
    t = mgr._tent
    t.order = [0, 1, 2]
    _script(mgr, {0: [_fold_hz(f150, prfs[0])], 2: [_fold_hz(f150, prfs[2])] * 50})
    assert mgr.mode == radar.TENTATIVE and t.confirming
    assert t.skipped == 1 and t.notch == -1 and len(t.dmeas) == 2
    assert abs(t.doppler - f150) <= mgr.doppler_tol_fraction * min(prfs)


def test_a_strong_detection_in_the_notch_is_a_precise_reading():
    """A strong detection (the target's excess over the noise, here 5) folded into the notch
    is read as a value (MTI off, or a near target: the default scenario, 14 km at ±150 m/s):
    no notch PRI, three Doppler readings, and the resolved Doppler is the truth."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    _enter(mgr, _fold_hz(F_TRUE, prfs[0]))
    t = mgr._tent
    t.order = [0, 1, 2]
    _script(mgr, {i: [_fold_hz(F_TRUE, prfs[i])] * 50 for i in range(3)}, excess=STRONG)
    assert mgr.mode == radar.TENTATIVE and t.confirming
    assert t.notch == -1 and t.skipped == -1 and len(t.dmeas) == 3
    assert abs(t.doppler - F_TRUE) <= mgr.doppler_tol_fraction * min(prfs)


def test_a_strong_second_reading_is_not_retro_skipped():
    """The 3 g turn test's run (MTI off, −88 m/s): PRI 2's strong reading was right, PRI 3's
    first reading 0.022·PRF off, just outside the coherence with both. It must not make PRI 2
    the given-up one (main: PRI 3 measured again; the retro-skip resolved a wrong alias,
    −84 310 Hz for +5 500 Hz): the second measurement is kept."""
    mgr = _manager()
    prfs = [1.0 / p for p in mgr._pris]
    _enter(mgr, _fold_hz(F_TRUE, prfs[0]))
    t = mgr._tent
    t.order = [0, 1, 2]
    off = _fold_hz(F_TRUE, prfs[1]) - 0.29 * prfs[1]
    _script(mgr, {0: [_fold_hz(F_TRUE, prfs[0])], 1: [off], 2: [_fold_hz(F_TRUE, prfs[2])]},
            excess=STRONG)
    assert t.skipped != 1
    assert not t.confirming


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2])
def test_fast_head_on_in_main_beam_clutter_confirmed_on_target_within_1s(seed):
    """The lead's case (issue 11): 25 km, −900 m/s, 1.5°, 10 m², clutter on, MTI on; folded
    Doppler in the canceller's notch at PRI 2. Detectable (filtered SNR 26.9 dB, clutter loss
    5.8, required 12.5). Main: locked at 2.33 s (seed 1) / 2.75 s (seed 2) after 9 attempts."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).parent))
    from engagement import run
    o = run(1.0, r0=R0, rdot=-900.0, el_deg=1.5, rcs=10.0, seed=seed)
    assert o.false_confirmations == 0, o.line()
    assert math.isfinite(o.on_target_time) and o.on_target_time <= 1.0, o.line()
