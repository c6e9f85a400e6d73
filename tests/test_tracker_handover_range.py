"""Issue 11 (session 16): the hand-over tests the tentative track's range against the range the
manager confirmed (models/tracker/beam_helpers.py ``_start_handover``), and a coast is bounded
to ``max_speed`` before it moves the track, not after (``_limit_speed`` in beams.py).

Traced first: 60 km, −800.77 m/s, 5°, 10 m², seed 2 (below the detection criterion), with the
``tentative_radial_coast`` option on. A weak tentative track coasted on the range rate of its
sparse readings (1 500 m/s, the speed bound) to 206 m from the manager's gate; at the
confirmation the Tracker placed the gate from that prediction, the manager followed it, and the
confirmed track was reported 158 m off the target for 10 ms: a false confirmation
(docs/filters.md "The hand-over tests the track's range").

Session 26: a track more than ``handover_range_tolerance`` (1 bin) but at most
``HYPOTHESIS_JUMP_M`` (2 bins) from the gate centre is moved along its line of sight onto it.
Traced at 60 km, 5°, 10 m², seed 1, −714.29 and −857.14 m/s (below the criterion, default
parameters): tentative tracks 82 and 144 m from the manager's gate centre,
148 and 164 m from the target, went on into confirmed mode; the Tracker placed the confirmed
gate from them, the target sat at the gate's edge, noise readings walked the tracks 180-200 m
off it, and each run counted one false confirmation.
"""

from __future__ import annotations

import numpy as np
import pytest
from designation import SESSION18, run_with_tracker
from test_tracker import _pos, inputs, make_beams
from test_tracker_tentative_coast import DT, GATE, P0, _tentative_track

from axir.models.radar.geometry import cart_to_sph
from axir.models.tracker import Tracker
from axir.models.tracker.beam_helpers import HYPOTHESIS_JUMP_M
from axir.orchestrator.envelope import Cell, run_cell

R0 = float(np.linalg.norm(P0))
TOL = float(Tracker.defaults()["handover_range_tolerance"])  # [m]
NO_SIGNAL = np.zeros((4, 16, 3))


def _tentative() -> tuple[Tracker, float, float, np.ndarray]:
    """A default tracker after 30 tentative readings of a still target at P0 (the manager's
    gate on it), the pedestal angles and the target's beams."""
    _, az, el = cart_to_sph(*P0)
    return _tentative_track(False), az, el, make_beams(tuple(P0), az, el, GATE)


def _move_along_los(trk: Tracker, dr: float) -> None:
    """Move the track's position ``dr`` [m] along its line of sight (a range drift)."""
    p = np.array(_pos(trk))
    for f, v in zip(trk.core.axes, p * (1.0 + dr / float(np.linalg.norm(p))), strict=True):
        f.pos = float(v)


def _range(trk: Tracker) -> float:
    return float(np.linalg.norm(_pos(trk)))


def test_a_track_on_the_confirmed_range_goes_on_into_confirmed_mode() -> None:
    for drift in (0.0, 0.9 * TOL, -0.9 * TOL):
        trk, az, el, _ = _tentative()
        n = trk.core.axes[0].n
        _move_along_los(trk, drift)
        trk.step(DT, inputs(NO_SIGNAL, az, el, 2, GATE))  # the first confirmed step: a coast
        assert trk.core.axes[0].n == n and trk.core._handover  # the same track, to be tested
        assert abs(_range(trk) - (R0 + drift)) < 1.0


def test_a_track_one_to_two_bins_off_is_moved_onto_the_confirmed_range() -> None:
    """Session 26: beyond the tolerance, within 2 bins: the same track (its readings and
    velocity kept), its position moved along the line of sight onto the gate centre."""
    for drift in (1.1 * TOL, -1.1 * TOL, 144.0, -0.99 * HYPOTHESIS_JUMP_M):
        trk, az, el, _ = _tentative()
        n = trk.core.axes[0].n
        vel = [f.vel for f in trk.core.axes]
        _move_along_los(trk, drift)
        p_before = np.array(_pos(trk))
        trk.step(DT, inputs(NO_SIGNAL, az, el, 2, GATE))  # the first confirmed step: a coast
        assert trk.core.axes[0].n == n and trk.core._handover
        assert [f.vel for f in trk.core.axes] == pytest.approx(vel)
        p = np.array(_pos(trk))
        assert abs(_range(trk) - R0) < 1.0  # on the gate centre (the coast moves ≤ 0.15 m)
        u0, u1 = p_before / np.linalg.norm(p_before), p / np.linalg.norm(p)
        assert float(np.dot(u0, u1)) > 1.0 - 1e-9  # along the line of sight


def test_a_track_off_the_confirmed_range_is_reset_and_restarts_on_the_first_reading() -> None:
    for drift in (1.01 * HYPOTHESIS_JUMP_M, -1.01 * HYPOTHESIS_JUMP_M, 206.0, 5_000.0):
        trk, az, el, b = _tentative()
        _move_along_los(trk, drift)
        out = trk.step(DT, inputs(NO_SIGNAL, az, el, 2, GATE))
        assert trk.core.axes[0].n == 0 and not trk.core._handover
        assert out["gate.start"] == GATE  # no track: the manager's gate, not the drifted one
        out = trk.step(DT, inputs(b, az, el, 2, GATE))  # the first confirmed reading
        assert trk.core.axes[0].n == 1
        assert abs(_range(trk) - R0) < 5.0  # on the target (the reading), not 0.2-5 km off


def test_a_coast_moves_the_track_no_faster_than_max_speed() -> None:
    max_speed = Tracker.defaults()["max_speed"]
    for mode in (1, 2):
        trk, az, el, _ = _tentative()
        u = P0 / R0
        for f, v in zip(trk.core.axes, 1.0e5 * u, strict=True):  # 10⁵ m/s along the LOS
            f.vel = float(v)
        p0 = np.array(_pos(trk))
        trk.step(DT, inputs(NO_SIGNAL, az, el, mode, GATE))
        step = float(np.linalg.norm(np.array(_pos(trk)) - p0))
        # before session 16 the coast ran on 10⁵ m/s (10 m) and was bounded after it
        assert step <= max_speed * DT * (1.0 + 1e-9)
        assert step >= 0.99 * max_speed * DT  # the bound, not a stop


def test_the_traced_cell_has_no_false_confirmation() -> None:
    """Traced with ``tentative_radial_coast`` on (an option; the tentative track coasted on
    its range rate): with the range test no false confirmation, without it one. With the
    defaults the cell does not reach that hand-over (none either way)."""
    import axir.models.tracker.beam_helpers as bh

    cell = Cell(range_m=60_000.0, speed=-800.77, el_deg=5.0, rcs=10.0, seed=2, duration=3.0)
    assert run_cell(cell)["false_confirmations"] == 0
    assert run_with_tracker(cell, tentative_radial_coast=True)["false_confirmations"] == 0
    orig = bh.BeamHelpers._start_handover
    bh.BeamHelpers._start_handover = lambda self, gate_true: self.axes[0].n > 0  # before
    try:  # traced with seed 000's velocity gain (the default); the velocity prior (an option,
        # session 17) keeps that track from walking even without the range test
        before = run_with_tracker(cell, tentative_radial_coast=True, **SESSION18)
        prior = run_with_tracker(cell, tentative_radial_coast=True,
                                 **{**SESSION18, "velocity_prior_sigma": 600.0})
    finally:
        bh.BeamHelpers._start_handover = orig
    assert before["false_confirmations"] > 0  # the traced one (as it was)
    assert prior["false_confirmations"] == 0


def test_the_tolerance_is_the_parameter() -> None:
    """The same drift is moved onto the gate centre under the default and kept where it is
    under a wider tolerance."""
    for tol, moved in ((TOL, True), (2.5 * TOL, False)):
        trk, az, el, _ = _tentative()
        trk.core.handover_tol = tol
        _move_along_los(trk, 1.5 * TOL)
        trk.step(DT, inputs(NO_SIGNAL, az, el, 2, GATE))
        assert trk.core.axes[0].n > 0
        assert (abs(_range(trk) - R0) < 1.0) is moved


def test_the_session_26_cells_have_no_false_confirmation() -> None:
    """The two traced cells (module docstring): no false confirmation with the defaults, one
    each as in session 25 (the 2-bin tolerance, the manager's gate not moved to the hits)."""
    for speed in (-714.29, -857.14):
        cell = Cell(range_m=60_000.0, speed=speed, el_deg=5.0, rcs=10.0, seed=1, duration=3.0)
        assert run_cell(cell)["false_confirmations"] == 0
        old = run_with_tracker(cell, {"confirm_range_recentre": False},  # session 25's
                               handover_range_tolerance=2.0 * TOL, velocity_prior_axes=False,
                               beam_background=0.0)  # (session 29's readings off too)
        assert old["false_confirmations"] >= 1


@pytest.mark.parametrize("kinds", [("svd",) * 3, ("vd",) * 3, ("imm",) * 3,
                                   ("alphabeta", "svd", "svd"), ("alphabeta", "alphabeta", "imm")])
def test_a_filter_without_a_cv_position_is_reset_instead(kinds: tuple[str, ...]) -> None:
    """Axes whose state is not a constant-velocity (pos, vel) pair cannot be moved: a track
    1-2 bins off the gate centre is reset (session 16's rule), never left 1.5 bins off, also
    when only one axis is such a filter (review: a mixed set raised AttributeError). The α-β
    track of the same drift is moved (the gate command moved by 1.5 bins here)."""
    for filt, moved in ((kinds, False), (("alphabeta",) * 3, True)):
        trk = _tentative_track(False, filter_x=filt[0], filter_y=filt[1], filter_z=filt[2])
        _, az, el = cart_to_sph(*P0)
        assert trk.core.axes[0].n > 0
        trk.step(DT, inputs(NO_SIGNAL, az, el, 2, GATE + 1.5 * TOL))
        if moved:
            assert trk.core.axes[0].n > 0
            assert abs(_range(trk) - (R0 + 1.5 * TOL)) < 1.0
        else:
            assert trk.core.axes[0].n == 0
