"""The confirmed gate centred on the M-of-N hits (issue 11, session 26; models/manager/
machine.py ``_enter_confirmed``, params.py ``confirm_range_recentre``), and the Tracker's
hand-over test against it (``handover_range_tolerance``, tests/test_tracker_handover_range.py).

Unit level: a manager in M-of-N confirmation fed synthetic dwells whose target sits in one of
the central bins 6, 7, 8; the confirmed gate's true range moves by one bin toward the side bin
that held more hits than the centre bin and than the other side bin, and not otherwise.

End to end (traced first): a strong target at 10 km, +1 000 m/s, 5°, 10 m², seed 2, was
confirmed with the manager's gate 82 m (1.1 bins) off the target in bin 6, while the
tentative track was 3.6 m off it. With the 1-bin hand-over tolerance alone the Tracker took
the gate's range for that good track (a first version, which reset such a track, dropped
it); with the gate centred on the hits the track goes on where it was.
"""

from __future__ import annotations

import numpy as np
import pytest

from axir.models.manager import RadarManager
from axir.models.radar.conventions import (
    BIN_M,
    CENTRE_FILTER,
    CONFIRMED,
    GATE_BIN,
    N_BINS,
    N_DOPPLER,
)
from axir.orchestrator.envelope import Cell, run_cell

CF = CENTRE_FILTER - 1
C = GATE_BIN - 1  # 0-based bin 7
NOISE = 4.0
GATE_BIN_CMD = 40  # the confirming gate's apparent bin


def _dwell(bin0: int) -> np.ndarray:
    """A dwell accumulator: NOISE everywhere, a strong target in the centre filter of the
    0-based bin ``bin0``."""
    acc = np.full((N_BINS, N_DOPPLER), NOISE)
    acc[bin0, CF] += 50.0 * NOISE
    return acc


def _confirm(bins: list[int], **kw) -> RadarManager:
    """A manager in M-of-N confirmation at GATE_BIN_CMD (PRI 0, no offset) fed one dwell per
    entry of ``bins`` (0-based bin of the target; −1: a dwell of noise only)."""
    m = RadarManager(**kw)
    t = m._tent
    t.doppler = 1000.0
    t.confirming = True
    t.hits = t.nmiss = 0
    t.bin_hits = [0, 0, 0]
    m._command(GATE_BIN_CMD, 0, 0)
    m._resolved_bin = GATE_BIN_CMD  # as _resolve sets it (the gate's true bin)
    for b in bins:
        m._dwell.acc = _dwell(b) if b >= 0 else np.full((N_BINS, N_DOPPLER), NOISE)
        m._end_tentative_dwell(True)
    return m


def _true_gate(m: RadarManager) -> float:
    return m._gate + m._offset


@pytest.mark.parametrize(("bins", "shift"), [
    ([C, C, C], 0),
    ([C - 1, C - 1, C - 1], -1),
    ([C + 1, C + 1, C + 1], 1),
    ([C - 1, C, C - 1], -1),  # 2 of 3 in bin 6
    ([C + 1, C, C], 0),  # the centre bin holds more
    ([C - 1, -1, C - 1, C + 1], -1),  # 3 of 4 dwells (bins 6, –, 6, 8): bin 6 holds most
    ([C - 1, C + 1, C], 0),  # one hit per bin: no side holds more than the centre
])
def test_the_confirmed_gate_moves_to_the_side_bin_of_the_hits(bins, shift):
    m = _confirm(bins)
    assert m.mode == CONFIRMED
    assert _true_gate(m) == pytest.approx(GATE_BIN_CMD * BIN_M + shift * BIN_M)
    assert m._track.anchor_range == _true_gate(m)  # the plausibility anchor is the new centre
    assert m._resolved_bin * BIN_M == _true_gate(m)  # range.resolved: the moved bin


def test_a_gate_at_range_zero_is_not_moved_below_it():
    """Hits in bin 6 of a gate whose true start is bin 0: no move to a negative range."""
    m = RadarManager()
    t = m._tent
    t.doppler, t.confirming, t.hits, t.nmiss, t.bin_hits = 1000.0, True, 0, 0, [0, 0, 0]
    m._command(0, 0, 0)
    for _ in range(3):
        m._dwell.acc = _dwell(C - 1)
        m._end_tentative_dwell(True)
    assert m.mode == CONFIRMED and m._gate == 0.0 and m._offset == 0.0


def test_the_option_off_keeps_the_resolved_gate():
    m = _confirm([C - 1] * 3, confirm_range_recentre=False)
    assert m.mode == CONFIRMED and _true_gate(m) == GATE_BIN_CMD * BIN_M


def test_a_gate_at_the_first_apparent_bin_moves_across_the_fold():
    """A true range one bin below an unambiguous interval's start is the previous interval's
    last apparent bin (the offset a whole interval less)."""
    m = RadarManager()
    t = m._tent
    t.doppler, t.confirming, t.hits, t.nmiss, t.bin_hits = 1000.0, True, 0, 0, [0, 0, 0]
    k = m._ks[0]
    m._command(0, 0, k)  # apparent bin 0 of the second interval
    for _ in range(3):
        m._dwell.acc = _dwell(C - 1)
        m._end_tentative_dwell(True)
    assert m.mode == CONFIRMED
    assert m._gate == (k - 1) * BIN_M and m._offset == 0.0


def _handover_distance(cell: Cell, **manager) -> float:
    """|tentative track range − confirmed gate centre| [m] at the run's first hand-over
    (measured by wrapping the Tracker's ``_start_handover``)."""
    import math

    import axir.models.tracker.beam_helpers as bh
    from axir.models.tracker.outputs import GATE_CENTRE_M

    seen: list[float] = []
    orig = bh.BeamHelpers._start_handover

    def spy(self, gate_true: float) -> bool:
        if self.axes[0].n > 0:
            r = math.sqrt(sum(f.x[0] ** 2 for f in self.axes))
            seen.append(abs(r - (gate_true + GATE_CENTRE_M)))
        return orig(self, gate_true)

    bh.BeamHelpers._start_handover = spy
    try:
        run_cell(cell, overrides={"RadarManager": manager})
    finally:
        bh.BeamHelpers._start_handover = orig
    return seen[0]


def test_the_traced_strong_target_keeps_its_track_at_the_hand_over():
    """The module docstring's run: the tentative track is 3.6 m off the target and the
    resolved gate 82 m off it (the hits in bin 6). With the gate moved to the hits the track
    is within a few metres of the gate centre and goes on untouched; without, 79 m (beyond
    the Tracker's 1-bin hand-over tolerance: moved onto the resolved gate). Held either way."""
    cell = Cell(range_m=10_000.0, speed=1_000.0, el_deg=5.0, rcs=10.0, seed=2, duration=3.0)
    assert _handover_distance(cell) < 10.0
    assert _handover_distance(cell, confirm_range_recentre=False) > 60.0
    now = run_cell(cell)
    assert now["drops"] == 0 and now["false_confirmations"] == 0
    assert now["held_fraction"] == pytest.approx(1.0)
