"""Threshold statistics (models/manager/thresholds.py): Rayleigh and dwell-sum factors
against scipy, and the false-alarm rate of the manager on noise only (tests/manager_scene.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from manager_scene import LAM, Scene, make, run  # noqa: F401
from scipy import stats

from axir.models.manager import RadarManager
from axir.models.manager.thresholds import (
    dwell_sum_looks,
    envelope_correlation,
    rayleigh_sum_factors,
)
from axir.models.radar import conventions as radar


# ------------------------------------------------------------------------------- noise only
def noise_only_run(adaptive: bool, seed: int) -> tuple[int, int, list[dict]]:
    pfa = 1e-3
    mgr = make(pfa_acq=pfa, dwell_acq=8, latency_pris=1, noise_avg_dwells=32.0,
               adaptive_looks=adaptive)
    scene = Scene(37_000.0, seed=seed)
    scene.present = False
    outs = run(mgr, scene, 24_000)
    prev_mode = [radar.ACQUISITION] + [o["mode"] for o in outs[:-1]]
    acq_dwells = [o for o, pm in zip(outs, prev_mode, strict=True)
                  if pm == radar.ACQUISITION and o["dwell.done"]]
    return sum(o["detection"] for o in acq_dwells), len(acq_dwells), outs


def test_noise_only_false_alarm_rate_adaptive_looks_within_bounds():
    """With the effective looks estimated from the data (default), the false-alarm rate stays
    within a factor of the design (measured ≈ 0.5× here: the spread estimate is biased high)."""
    fa, n, outs = noise_only_run(True, 22)
    p_dwell = 1.0 - (1.0 - 1e-3) ** 48
    assert 0.2 * n * p_dwell <= fa <= 2.0 * n * p_dwell, (fa, n * p_dwell)
    assert not any(o["mode"] == radar.CONFIRMED for o in outs)


def test_noise_only_false_alarm_rate_matches_design_pfa():
    """Threshold design: with the exact noise model (adaptive_looks off) the acquisition
    false-alarm rate matches the design Pfa (binomial 99.9 % interval)."""
    pfa = 1e-3
    fa, n, outs = noise_only_run(False, 21)
    p_dwell = 1.0 - (1.0 - pfa) ** 48  # 48 independent cells tested per dwell
    lo, hi = stats.binom.interval(0.999, n, p_dwell)
    assert n > 1500
    assert lo <= fa <= hi, (fa, n, n * p_dwell)
    modes = np.array([o["mode"] for o in outs])
    assert not np.any(modes == radar.CONFIRMED)
    # each false alarm costs a short tentative episode (≈ 2 × (settle + dwell) PRIs) that ends
    # back in acquisition: ≈ 85 % of the time is spent searching at this (high) Pfa
    assert np.mean(modes == radar.ACQUISITION) > 0.75


def test_threshold_factors_match_rayleigh_statistics():
    # one look: Rayleigh quantile √(−2 ln Pfa), median √(2 ln 2), mean √(π/2)
    q = math.sqrt(-2.0 * math.log(1e-4))
    c_med, c_mean = rayleigh_sum_factors(1, 1e-4)
    assert c_med == pytest.approx(q / math.sqrt(2.0 * math.log(2.0)), rel=1e-3)
    assert c_mean == pytest.approx(q / math.sqrt(math.pi / 2.0), rel=1e-3)
    # 16 looks: Monte Carlo tail at the computed threshold
    rng = np.random.default_rng(7)
    x = rng.rayleigh(size=(400_000, 16)).sum(axis=1)
    c_med, c_mean = rayleigh_sum_factors(16, 1e-3)
    for th in (c_med * np.median(x), c_mean * 16 * math.sqrt(math.pi / 2)):
        p = np.mean(x > th)
        lo, hi = stats.binom.interval(0.999, x.size, 1e-3)
        assert lo / x.size <= p <= hi / x.size


def test_dwell_sum_looks_and_settling():
    # exact moments: an uncorrelated dwell (pole 0) keeps all looks_per_pri·K looks; one PRI
    # keeps the beams; a faster filter (smaller pole) decorrelates the PRIs more
    assert dwell_sum_looks(4, 16, 0.0) == 64
    assert dwell_sum_looks(4, 1, 0.9) == 4
    assert dwell_sum_looks(4, 16, 0.5) > dwell_sum_looks(4, 16, 0.9) > 4
    assert envelope_correlation(0.0) == pytest.approx(0.0, abs=1e-12)
    assert envelope_correlation(1.0) == pytest.approx(1.0)
    m = RadarManager(doppler_pole=0.9, latency_pris=3, settle_db=40.0)
    assert m.get_state()["_settle_pris"] == 3 + 44  # 0.9**44 < 10**(-40/20) < 0.9**43
    assert RadarManager(doppler_pole=0.0, latency_pris=3).get_state()["_settle_pris"] == 3




# ------------------------------------------------------- partly cluttered filters (issue 11)
@pytest.mark.parametrize("a,b", [(1.0, 0.0), (1.0, 0.7), (1.0, 2.0), (0.0, 1.0)])
@pytest.mark.parametrize("which", [0, 1])
def test_clutter_noise_factor_gives_the_design_pfa_for_its_law(a, b, which):
    """X = √(A² + B²·R²), R Rayleigh: the factor fitted to the sample IQR/median puts
    P(X > factor × median (or mean)) on Pfa = 1e-3 (2·10⁶ seeded draws, ±4σ binomial)."""
    from axir.models.manager.thresholds import clutter_noise_factor

    rng = np.random.default_rng(7)
    n = 2_000_000
    x = np.sqrt(a * a + (b * np.sqrt(-2.0 * np.log(rng.random(n)))) ** 2)
    q25, med, q75 = np.percentile(x, (25, 50, 75))
    scale = med if which == 0 else x.mean()
    k = clutter_noise_factor((q75 - q25) / med, 1e-3, which)
    hits = int(np.sum(x > k * scale))
    if b == 0.0:  # constant: nothing exceeds
        assert hits == 0
        return
    assert abs(hits - 1e-3 * n) < 4 * math.sqrt(1e-3 * n), (hits, k)


@pytest.mark.parametrize("m", [5, 9, 13, 16])
def test_quartiles_equal_numpy_percentile_bit_for_bit(m):
    """The dwell-end quartiles (sort fast path when q·(m − 1) is whole) are numpy's linear
    percentiles exactly, ties, NaN and inf included (issue 14: results.csv unchanged)."""
    from axir.models.manager.thresholds import _quartiles

    rng = np.random.default_rng(m)
    for k in range(300):
        cells = rng.rayleigh(size=(m, 3)) * 10.0 ** rng.uniform(-3, 3)
        if k % 3 == 0:
            cells[rng.integers(m), 1] = cells[0, 1]  # a tie
        if k == 7:
            cells[2, 0] = np.nan
        if k == 8:
            cells[3, 2] = np.inf
        with np.errstate(invalid="ignore"):  # numpy's own inf − inf in the inf case
            expect = np.percentile(cells, (25.0, 50.0, 75.0), axis=0)
            got = _quartiles(cells)
        np.testing.assert_array_equal(got, expect)
        assert got.tobytes() == expect.tobytes()


def test_common_mode_residue_factor_is_the_one_look_dwell_law():
    """A filter flagged ``common`` (MTI clutter residue: white, the same in the 4 beams) gets
    the exact dwell-sum ratio of ONE look per PRI, higher than the 4-independent-beam one;
    unflagged filters keep the thermal ratio."""
    from axir.models.manager.thresholds import (
        common_mode_factor,
        dwell_sum_factors,
        threshold_factors,
    )

    one = dwell_sum_factors(1, 16, 0.9, 1e-5)[0]
    four = dwell_sum_factors(4, 16, 0.9, 1e-5)[0]
    assert common_mode_factor(16, 0.9, 1e-5, 0) == one
    assert one > 1.5 * four  # 3.23 vs 1.92: the common-mode residue has a far heavier tail
    out = threshold_factors(4, 16, 0.9, 1e-5, 0, None, None,
                            np.array([True, False, False]))
    np.testing.assert_allclose(out, [one, four, four])


class _SteppedNoise(Scene):
    """Noise only, its amplitude ×``gain`` from ``t_jump`` [s] on (the front end changed: the
    MTI canceller switched off, the beam moved into clutter)."""

    def __init__(self, gain: float, t_jump: float, seed: int):
        super().__init__(37_000.0, seed=seed)
        self.present = False
        self.gain, self.t_jump = gain, t_jump

    def sum_array(self, gate_start, pri, dc):
        s = super().sum_array(gate_start, pri, dc)
        return s * self.gain if self.t >= self.t_jump else s


@pytest.mark.parametrize("seed", [1, 2])
def test_noise_level_restarts_when_the_front_end_changes(seed):
    """A 2× noise step (6 dB) after 0.2 s: averaging alone (noise_attack_ratio 0) lets the
    stale level through (seeds 1 and 2: 5 false alarms in the 218 acquisition dwells after
    the step, in the first ones, until the average catches up); the fast attack restarts the
    level from the first dwell above 1.25× it (0 in 228; the design 4.8e-4 per dwell expects
    0.1)."""
    def after_step(attack: float) -> int:
        mgr = make(noise_attack_ratio=attack, noise_avg_dwells=8.0)
        outs = run(mgr, _SteppedNoise(2.0, 0.2, seed), 6000)
        t = np.cumsum([o["pri"] for o in outs])
        prev = [radar.ACQUISITION] + [o["mode"] for o in outs[:-1]]
        return sum(1 for o, pm, ti in zip(outs, prev, t, strict=True)
                   if ti > 0.2 and pm == radar.ACQUISITION and o["dwell.done"]
                   and o["detection"])

    assert after_step(0.0) >= 3
    assert after_step(1.25) <= 1
