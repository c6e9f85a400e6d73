"""Doppler coverage and Doppler coherence (models/manager/doppler_search.py, issue 11): the
coverage formula against the TargetGenerator's filters, the step count, the unfolded Doppler
candidates and the manager's tentative Doppler coherence."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from axir.models.manager import RadarManager
from axir.models.manager import doppler_search as ds
from axir.models.manager.ambiguity import pri_seconds
from axir.models.radar import conventions as radar
from axir.models.target_generator import TargetGenerator

LAM = radar.DEFAULT_WAVELENGTH


def _beam_peak(v: float, centre: float, pri: float, n: int = 400) -> float:
    """Largest SUM magnitude over the 3 filters of a noise-free radial target at speed ``v``
    [m/s] after ``n`` pulses with the filter bank centred at ``centre`` [Hz]."""
    traj = json.dumps({"type": "cv", "position": [0.0, 5000.0, 0.0], "velocity": [0.0, v, 0.0]})
    g = TargetGenerator(trajectory=traj, noise=False, clutter=False, seed=1)
    t_end = n * pri
    r_end = 5000.0 + v * t_end
    inp = {"antenna.az": 0.0, "antenna.el": 0.0, "gate.start": r_end - 6 * radar.BIN_M,
           "doppler.centre": centre, "pri": pri}
    beam = g.step(t_end, inp)["beam"]
    return float(beam.sum(axis=0)[6].max())


@pytest.mark.parametrize("v", [123.4, -487.0, 911.0])
@pytest.mark.parametrize("k", [200, 223])
def test_stepped_filter_loss_matches_the_formula_and_the_goal(v, k):
    """The best of the 9 stepped filter positions loses what loss_db says against a target
    at a filter centre (generator simulated, ≤ 0.1 dB), and never more than 4 dB."""
    m = RadarManager()
    pri = pri_seconds(k)
    prf = 1.0 / pri
    n = ds.coverage_steps(m.doppler_spacing_fraction, m.doppler_pole, 4.0)
    fd = -2.0 * v / LAM
    ref = _beam_peak(v, radar.fold_doppler(fd, pri), pri)  # filter-centred
    best = max(_beam_peak(v, radar.fold_doppler(
        ds.step_centre(0.0, j, n, m.doppler_spacing_fraction, prf), pri), pri)
        for j in range(n))
    measured = -20.0 * math.log10(best / ref)
    formula = float(ds.loss_db(np.array([fd]), prf, 0.0, n, m.doppler_spacing_fraction,
                               m.doppler_pole)[0])
    assert measured == pytest.approx(formula, abs=0.1)
    assert measured <= 4.0
    single = float(ds.loss_db(np.array([fd]), prf, 0.0, 1, m.doppler_spacing_fraction,
                              m.doppler_pole)[0])
    assert formula <= single + 1e-9


def test_coverage_steps_for_the_default_filters():
    # one position: 19.6 dB midway between filters (issue 11); 9 steps: ≤ 4 dB (3.46)
    assert ds.worst_loss_db(1, 1 / 3, 0.9) == pytest.approx(19.59, abs=0.01)
    n = ds.coverage_steps(1 / 3, 0.9, 4.0)
    assert n == 9
    assert ds.worst_loss_db(n, 1 / 3, 0.9) <= 4.0 < ds.worst_loss_db(n - 1, 1 / 3, 0.9)
    assert RadarManager()._n_steps == 9


def test_unfolded_candidates_keep_the_true_doppler_and_reject_incoherent_ones():
    prfs = [1.0 / pri_seconds(k) for k in (200, 211, 223)]
    f_true = -2.0 * 612.0 / LAM
    tol = RadarManager().doppler_tol_fraction * prfs[0]
    c = ds.candidates_hz(radar.fold_doppler(f_true, 1 / prfs[0]) + 60.0, prfs[0], 94_000.0, tol)
    assert np.min(np.abs(c - f_true)) <= ds.CAND_STEP_HZ
    for p in prfs[1:]:
        c = ds.consistent_hz(c, radar.fold_doppler(f_true, 1 / p) - 50.0, p, tol)
    assert c.size and np.all(np.abs(c - f_true) < 2 * tol)  # one cluster: the truth
    # a third measurement a quarter PRF off: incoherent, nothing left
    c2 = ds.consistent_hz(c, radar.fold_doppler(f_true + 0.25 * prfs[2], 1 / prfs[2]),
                          prfs[2], tol)
    assert c2.size == 0


def test_steps_for_puts_each_candidate_in_a_filter_of_its_step():
    """Each candidate's step is the one whose 3 filters give it the smallest loss (brute force
    over the 9 single-position losses)."""
    prf = 1.0 / pri_seconds(211)
    cands = np.array([1234.0, -4321.0, 30_000.0])
    steps = ds.steps_for(cands, prf, 0.0, 9, 1 / 3)
    for f in cands:
        losses = [float(ds.loss_db(np.array([f]), prf, ds.step_centre(0.0, j, 9, 1 / 3, prf), 1,
                                   1 / 3, 0.9)[0]) for j in range(9)]
        assert int(np.argmin(losses)) in steps
