"""Issue 11 (session 18): the acquisition/tentative Doppler reading's amplitude model
(models/manager/acquisition.py ``_measured_doppler``, RadarManager ``doppler_read``;
docs/clutter.md "The Doppler reading's two amplitude models").

With three filters tiling the PRF one of them always holds the ground clutter, beside the
target's. The reading fits the resonator profile to the filters' target amplitudes:

- 'excess' (the default): mean amplitude less the filter's level. A share of the target
  comparable to the level is under-read, so beside a clutter filter the fit lands off the
  target — by more than the coherence tolerance in the traced case (a 44 dB target at 4.9 km,
  −914 m/s: −3712 Hz read for −2641 Hz, 1.43 s to lock).
- 'rician': each filter's amplitude inverted for the Rice bias of its own level: unbiased in
  expectation, but a side filter holding noise a little above its level reads as a share of
  the target (30 km, 1°, −642.86 m/s: 2028 Hz for 2425 Hz).
- 'both': the midpoint of the two, the tolerance widened by half their difference."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from axir.models.manager import RadarManager
from axir.models.manager.doppler import resonator_gain, rice_mean_ratio
from axir.orchestrator.envelope import Cell


def _expected_row(a: float, delta: float, f: int, sigma: np.ndarray, mgr: RadarManager
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The dwell-mean amplitudes of a target of peak amplitude ``a`` at ``delta`` cycles from
    filter ``f``'s centre, in complex Gaussian noise/clutter of σ ``sigma`` per filter: the
    Rice mean E|s + n| = (σ√π/2)·L(A/σ) (analytic), and each filter's level (Rayleigh mean
    σ√π/2)."""
    s = mgr.doppler_spacing_fraction
    offs = delta - (np.arange(3) - f) * s
    h = resonator_gain(offs, mgr.doppler_pole) / float(resonator_gain(0.0, mgr.doppler_pole))
    level = sigma * math.sqrt(math.pi) / 2.0
    return level * rice_mean_ratio(a * h / sigma), level


def _reading(mgr: RadarManager, acc: np.ndarray, level: np.ndarray, f: int, truth: float
             ) -> tuple[float, float]:
    """(|reading − truth|, the reading's extra tolerance), both in cycles of the PRF; truth in
    cycles from the current centre."""
    prf = 1.0 / mgr.pri
    fd, extra = mgr._measured_doppler(acc, level, f)
    d = (fd - mgr._doppler) / prf - truth
    return abs((d + 0.5) % 1.0 - 0.5), extra / prf


def _error(mgr: RadarManager, delta: float, f: int, a: float, sigma: np.ndarray) -> float:
    acc, level = _expected_row(a, delta, f, sigma, mgr)
    return _reading(mgr, acc, level, f, (f - 1) * mgr.doppler_spacing_fraction + delta)[0]


# (target filter, offset from its centre [cycles], amplitude, σ per filter): the clutter filter
# is filter 2 (index 1) at 4.4× the others' level, as in the traced dwells
CASES = [
    (0, +0.069, 270.0, np.array([15.0, 65.6, 15.0])),  # 4.9 km, −914 m/s (toward the clutter)
    (0, -0.116, 90.0, np.array([14.9, 58.0, 14.4])),   # the default scenario's first dwell
    (2, -0.10, 120.0, np.array([15.0, 65.6, 15.0])),   # filter 3, toward the clutter
    (2, +0.12, 60.0, np.array([15.0, 65.6, 15.0])),    # filter 3, away from it
    (0, +0.15, 400.0, np.array([15.0, 80.0, 15.0])),   # near the clutter filter's edge
]


@pytest.mark.parametrize("f, delta, a, sigma", CASES)
def test_the_rician_reading_beside_a_clutter_filter_is_unbiased(f, delta, a, sigma):
    # the fit's own resolution (the 1/720-PRF grid refined by a parabola), ≪ the coherence
    # tolerance doppler_tol_fraction (0.03)
    assert _error(RadarManager(doppler_read="rician"), delta, f, a, sigma) < 0.004


def test_the_excess_reading_misses_the_traced_target_by_more_than_the_tolerance():
    """The defect: in the traced dwell the excess reading is off by more than the coherence
    tolerance (the target is then looked for at the wrong Doppler)."""
    mgr = RadarManager(doppler_read="excess")
    f, delta, a, sigma = CASES[0]
    assert _error(mgr, delta, f, a, sigma) > mgr.doppler_tol_fraction


def test_without_clutter_the_rician_reading_is_unbiased_too():
    """Equal levels (no clutter filter), a strong target: a neighbour's share of it is still
    within a few σ of the level, so the excess reading is biased there as well (0.0155 cycles,
    ≈ 155 Hz at δ = 0.15); the Rice-inverted reading is not."""
    a, sigma = 500.0, np.array([15.0, 15.0, 15.0])
    e_r, e_x = [], []
    for delta in (-0.12, -0.05, 0.0, 0.07, 0.15):
        e_r.append(_error(RadarManager(doppler_read="rician"), delta, 1, a, sigma))
        e_x.append(_error(RadarManager(doppler_read="excess"), delta, 1, a, sigma))
    assert max(e_r) < 0.004
    assert max(e_x) > 0.01


# a dwell of the 30 km, 1°, −642.86 m/s cell (seed 1; acquisition at PRI 2, centre 2456 Hz,
# MTI on): the target 31 Hz below the centre filter's centre, the side filters' means a little
# above their levels (noise)
_DWELL_30KM = (np.array([47.9, 183.0, 35.3]), np.array([27.5, 31.0, 30.6]), 1,
               (2425.0 - 2456.0) * 105.57e-6)


def _at_pri2(mode: str) -> RadarManager:
    mgr = RadarManager(doppler_read=mode)
    mgr._pri_idx = 1  # PRI 2 (105.57 µs), centre 2456 Hz
    mgr._doppler = 2456.0
    return mgr


def test_the_rician_reading_takes_side_noise_for_the_target():
    acc, level, f, truth = _DWELL_30KM
    mgr = _at_pri2("rician")
    assert mgr.pri == pytest.approx(105.57e-6, rel=1e-3)
    err, _ = _reading(mgr, acc, level, f, truth)
    assert err > mgr.doppler_tol_fraction  # 2028 Hz read for 2425 Hz
    err, _ = _reading(_at_pri2("excess"), acc, level, f, truth)
    assert err < mgr.doppler_tol_fraction


@pytest.mark.parametrize("dwell", ["traced 4.9 km", "30 km"])
def test_both_readings_cover_the_truth_within_their_tolerance(dwell):
    """'both': each model misses one of the two dwells by more than the coherence tolerance;
    the midpoint with its widened tolerance holds the truth in both, and the widening is
    half the models' difference (no more)."""
    if dwell == "30 km":
        acc, level, f, truth = _DWELL_30KM
        mgr = _at_pri2("both")
    else:
        mgr = RadarManager(doppler_read="both")
        f, delta, a, sigma = CASES[0]
        acc, level = _expected_row(a, delta, f, sigma, mgr)
        truth = (f - 1) * mgr.doppler_spacing_fraction + delta
    err, extra = _reading(mgr, acc, level, f, truth)
    assert err <= mgr.doppler_tol_fraction + extra
    prf = 1.0 / mgr.pri
    mode_reads = []
    for mode in ("excess", "rician"):
        mgr.doppler_read = mode
        mode_reads.append(mgr._measured_doppler(acc, level, f))
    (fx, tx), (fr, tr) = mode_reads
    assert tx == 0.0 and tr == 0.0
    assert extra == pytest.approx(0.5 * abs(fx - fr) / prf, rel=1e-9)


# the random engagement traced in session 18 (bench_envelope_random.py --draw-seed 5): strong,
# closing at 914 m/s at 4.9 km and 42.6°; clutter on
_TRACED = Cell(range_m=4926.1, speed=-914.01, el_deg=42.63, rcs=0.9, g=0.0, seed=5,
               duration=0.5, az_deg=299.93, tangential=6.0, maneuver_onset=1.24, clutter=True)


def _run(cell: Cell, mode: str) -> dict:
    from designation import run_with_params

    return run_with_params(cell, "RadarManager", doppler_read=mode)


@pytest.mark.parametrize("speed", [-914.01, 914.01])
def test_the_traced_fast_target_locks_at_once_with_both_readings(speed):
    cell = replace(_TRACED, speed=speed)
    s = _run(cell, "both")
    assert s["lock_time"] is not None and s["lock_time"] < 0.1
    assert s["false_confirmations"] == 0
    assert _run(cell, "excess")["lock_time"] is None  # the default: 1.43 s (seed 5)
