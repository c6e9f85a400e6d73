"""Issue 14, round 9 (branch spd16): the per-PRI paths written out further, each bit for bit
the code it replaces (kept as the reference: main's step of the unit, verbatim, here or in the
round-8 tests), on random and edge states.

- Tracker: ``innovation_factor(α, β, False)`` (= 1 + ``prediction_vrr``) written out in
  ``BeamTracker.step`` (the NIS test of the mixed and steady phases).
"""

from __future__ import annotations

import math
import struct
from typing import Any

import numpy as np
from test_tracker_round8 import _bits, _FormerBeamTracker, _inputs, _state

from axir.models.filters.gains import innovation_factor
from axir.models.radar.conventions import CONFIRMED
from axir.models.tracker import Tracker

_EDGE = [0.0, -0.0, 5e-324, 1e-300, 1e-3, 0.1, 0.5, 0.99, 1.0, 1.5, 1.99, 2.0, 2.5, 4.0, -1.0,
         1e300, math.inf, -math.inf, math.nan]


def _vrr_factor(a: float, bb: float) -> float:
    """The lines of ``BeamTracker.step`` that replace ``innovation_factor(a, bb, False)``."""
    den = a * (4.0 - 2.0 * a - bb)
    if a <= 0.0 or bb <= 0.0 or den <= 0.0:
        return math.inf
    return 1.0 + (2.0 * a * a + 2.0 * bb + a * bb) / den


def test_vrr_factor_written_out_equals_innovation_factor() -> None:
    """The written-out factor is innovation_factor's (non-evolutive) on every pair of edge
    values and 200 000 random pairs in and around the stability triangle, by its bits."""
    pairs = [(a, b) for a in _EDGE for b in _EDGE]
    rng = np.random.default_rng(9)
    pairs += list(zip(rng.uniform(-0.5, 2.5, 200_000).tolist(),
                      rng.uniform(-0.5, 4.5, 200_000).tolist(), strict=True))
    for a, b in pairs:
        assert struct.pack("<d", _vrr_factor(a, b)) == struct.pack(
            "<d", innovation_factor(a, b, False)), (a, b)


def test_tracker_step_nis_factor_mixed_phase_equals_the_former_step() -> None:
    """Twin trackers (round 8's reference step, which calls innovation_factor), fed steady
    gains from the manager that are stable, unstable (the infinite factor), zero, negative or
    NaN, switching mid-track: every output and the state equal after every step; the
    non-evolutive NIS path was taken (its factor is finite there: the step uses the steady
    gains only inside the stability triangle; the infinite branch is the test above)."""
    rng = np.random.default_rng(90)
    gains = [(0.3, 0.05), (0.05, 0.001), (0.9, 0.6), (1.9, 0.5), (0.5, 0.0), (0.0, 0.2),
             (-0.1, 0.1), (math.nan, 0.1), (0.2, math.nan), (1e-3, 1e-6)]
    new, old = Tracker(track_init_n=2), Tracker(track_init_n=2)
    old.core.__class__ = _FormerBeamTracker
    taken = 0
    a_ss, b_ss = gains[0]
    for k in range(4000):
        if rng.random() < 0.01:
            a_ss, b_ss = gains[rng.integers(len(gains))]
        mode = 1 if k % 1000 < 30 else CONFIRMED
        inp: dict[str, Any] = _inputs(rng, k, mode, 7000.0 + 0.02 * k, 0.0, 0.4, 0.15,
                                      strong=rng.random() < 0.95)
        inp["alpha"], inp["beta"] = a_ss, b_ss
        o_old, o_new = old.core.step(1e-4, inp), new.core.step(1e-4, inp)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _state(new.core) == _state(old.core), k
        fx = new.core.axes[0]
        if fx.n >= 3 and not fx.evolutive and not o_new["coasting"]:
            taken += 1
    assert taken > 500, taken
