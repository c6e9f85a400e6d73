"""The side-filter test of ``doppler_peak_side`` at the acquisition detection (issue 11,
session 28; models/manager/acquisition.py ``_end_acquisition_dwell``, params.py
``acq_peak_side``; docs/clutter.md "The side test at the acquisition detection").

Traced in session 27 (5 km / 3° / −6.5 m/s, 1 m², MTI canceller on): the target was detected
at the 0 Hz Doppler step in the centre filter, 408 Hz off its centre; the side filters (PRF/3
away) held only noise, so the three-filter discriminator read the filter's centre (65.5 Hz at
the acquisition, 1.7 Hz at the first tentative PRI), the tentative stage resolved a wrong
alias at 9.7 kHz and the track was dropped at the first PRI switch. The peak search over the
Doppler steps ran only from the 2nd tentative PRI on. With the test at the acquisition a
detection in the clutter filter (centred on 0 Hz) gets the peak search when its side filters
carry nothing to read.
"""

from __future__ import annotations

import pytest

from axir.models.manager import RadarManager
from axir.models.radar import conventions as radar
from axir.models.radar.conventions import ACQUISITION
from axir.orchestrator.envelope import Cell, run_cell

_C = radar.GATE_BIN - 1  # the gate's centre bin (0-based)
NOISE = 10.0  # accumulated level of every noise cell (the dwell median: the noise level)
TARGET = 200.0  # a strong detection: excess 19, far above doppler_peak_excess (4)


def _acquisition_dwell_end(side_level: float, filt: int = 1,
                           **kw) -> tuple[RadarManager, list[tuple]]:
    """A fresh manager's first acquisition dwell end (its first Doppler step: the centre
    filter is the clutter filter, centred on 0 Hz) with a detection of ``TARGET`` in filter
    ``filt`` (0-based) of the gate's centre bin and ``side_level`` in the filter below it
    (cyclically; every other cell ``NOISE``); returns the manager and the
    ``_enter_tentative`` calls it made."""
    m = RadarManager(**kw)
    assert m.mode == ACQUISITION
    assert m._positions().tolist()[1] == 0  # the centre filter is the clutter filter
    m._dwell.acc[:] = NOISE
    m._dwell.acc[_C, filt] = TARGET
    m._dwell.acc[_C, filt - 1] = side_level
    entered: list[tuple] = []
    m._enter_tentative = lambda *a: entered.append(a)
    m._end_acquisition_dwell(True)
    assert m._detection
    return m, entered


def test_a_strong_detection_with_noise_only_beside_it_gets_the_peak_search():
    m, entered = _acquisition_dwell_end(NOISE)  # side excess 0 < doppler_peak_side (1.5)
    assert m._peak.active and not entered
    # session 27's rule reads it at once: the discriminator has nothing but the centre filter,
    # so the reading is the filter's centre (0 Hz at the first Doppler step)
    m0, entered0 = _acquisition_dwell_end(NOISE, acq_peak_side=False)
    assert not m0._peak.active
    assert len(entered0) == 1 and entered0[0][1] == 0.0


def test_a_strong_detection_read_by_a_side_filter_goes_to_tentative_at_once():
    # side excess 3.8 > doppler_peak_side: the discriminator reads an offset toward that side
    for side in (True, False):
        m, entered = _acquisition_dwell_end(NOISE + 0.2 * (TARGET - NOISE), acq_peak_side=side)
        assert not m._peak.active and len(entered) == 1
        assert entered[0][1] < -100.0  # toward the lower filter [Hz]


def test_a_strong_detection_outside_the_clutter_filter_is_read_at_once():
    # the rule is for the clutter filter only: a filter centred elsewhere reads the offset of a
    # target far from its centre on its side filters' skirts unless the target is weak, and a
    # centred strong target (side filters ≈ −24 dB) would otherwise wait for the peak search
    for filt in (0, 2):
        m, entered = _acquisition_dwell_end(NOISE, filt=filt)
        assert not m._peak.active and len(entered) == 1


def test_no_peak_search_without_doppler_steps():
    m, entered = _acquisition_dwell_end(NOISE, doppler_peak_dwells=0)
    assert not m._peak.active and len(entered) == 1


@pytest.mark.parametrize("speed", [-6.5, -7.5])
def test_slow_targets_at_3_deg_are_held_on_their_true_doppler(speed):
    # the session-27 drops: 5 km / 3° / 1 m², seed 1 (MTI canceller on below 4.5°)
    cell = Cell(range_m=5000.0, speed=speed, el_deg=3.0, rcs=1.0, seed=1, duration=1.0)
    s = run_cell(cell)
    assert s["lock_time"] is not None and s["lock_time"] < 0.2
    assert s["drops"] == 0 and s["false_confirmations"] == 0
    assert s["held_fraction"] == pytest.approx(1.0)
    # without the test: the wrong alias, confirmed later and dropped at the PRI switch
    off = run_cell(cell, overrides={"RadarManager": {"acq_peak_side": False}})
    assert off["drops"] >= 1 and off["held_fraction"] < 0.9
