"""Range walk of the tentative hypotheses (issue 11, models/manager/range_walk.py,
docs/clutter.md "Late locks at 30-42 km"): the walk of a Doppler candidate and the coupled
range / Doppler coherence, worked by hand."""

from __future__ import annotations

import numpy as np

from axir.models.manager.range_walk import WALK_QUANTUM, coupled, step_walks, walk_bins
from axir.models.radar import conventions as radar

LAM = radar.DEFAULT_WAVELENGTH


def _doppler(rdot: float) -> float:
    return -2.0 * rdot / LAM  # [Hz], f = −2ṙ/λ


def test_walk_of_a_closing_target_by_hand():
    # 800 m/s closing for 0.25 s: 200 m = 2.67 bins of 75 m, nearer → −3 bins
    f = np.array([_doppler(-800.0), _doppler(0.0), _doppler(300.0)])
    assert walk_bins(f, LAM, 0.25).tolist() == [-3, 0, 1]  # 300 m/s: 75 m = +1 bin
    assert walk_bins(f, LAM, 0.0).tolist() == [0, 0, 0]


def test_short_attempts_keep_one_window_per_step():
    # every walk within ±1 bin (a short attempt): one window, walk 0 (as without the walk)
    walks = np.array([-1, 0, 1, 1, 0])
    steps = np.array([2, 2, 2, 5, 5])
    assert step_walks(walks, steps, 2) == [0]
    assert step_walks(walks, steps, 7) == [0]  # a step without candidates
    # walks of 2-4 bins need a window 3 bins away (multiples of WALK_QUANTUM)
    assert WALK_QUANTUM == 3
    assert step_walks(np.array([0, -3, 4]), np.array([1, 1, 1]), 1) == [0, -3, 3]


def test_coupled_coherence_keeps_the_alias_whose_walk_explains_the_range():
    k = 211
    b0 = 560  # true bin at the attempt's start
    cands = np.array([b0 - 1, b0, b0 + 1])
    dt = 0.25
    fast, slow = _doppler(-800.0), _doppler(-100.0)  # two aliases of one reading
    dc = np.array([fast, slow])
    m_now = (b0 - 3) % k  # the target walked −2.67 bins: seen 3 bins nearer
    m0, rc, dcc = coupled(cands, dc, m_now, k, 1, LAM, dt, walk=-3)
    assert m0 == b0 % k
    assert rc.tolist() == [b0 - 1, b0, b0 + 1]
    assert dcc.tolist() == [fast]  # the slow alias walks 0.3 bin: not this window's walk
    # in the window of walk 0 the fast alias is dropped, and the range is then incoherent
    m0, rc, dcc = coupled(cands, dc, m_now, k, 1, LAM, dt, walk=0)
    assert dcc.size == 0 or rc.size == 0
