"""The beam-common clutter residue's thresholds (models/manager/residue.py, issue 11 session
21): the canceller-shaped thermal gains against their closed form, the canceller inference,
the effective looks at the ends of the share, and the threshold factor against a Monte-Carlo
simulation of four beams sharing a common white residue through the one-pole Doppler filter."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from axir.models.manager.residue import (
    SHARE_MARGIN,
    class_shares,
    class_thermal_gains,
    mti_inferred,
    residue_floors,
    share_factor,
    share_looks,
)
from axir.models.manager.thresholds import dwell_sum_factors


@pytest.mark.parametrize("pole", [0.5, 0.9])
def test_class_thermal_gains_match_the_closed_form(pole):
    """The one-pole filter's normalised power response is the Poisson kernel (k-th Fourier
    coefficient ρ^|k|), so behind the canceller |H|² = 1 − cos 2πν (order 1) the filtered
    thermal power is 1 − ρ·cos 2πν_c, and behind (2/3)(1 − cos 2πν)² (order 2)
    1 − (4/3)ρ cos 2πν_c + (1/3)ρ² cos 4πν_c."""
    step = 1.0 / 27.0
    nu = np.arange(14) * step
    g1 = class_thermal_gains(14, step, pole, 1)
    g2 = class_thermal_gains(14, step, pole, 2)
    np.testing.assert_allclose(g1, 1.0 - pole * np.cos(2 * math.pi * nu), atol=1e-6)
    np.testing.assert_allclose(
        g2, 1.0 - 4.0 / 3.0 * pole * np.cos(2 * math.pi * nu)
        + pole**2 / 3.0 * np.cos(4 * math.pi * nu), atol=1e-6)
    assert class_thermal_gains(14, step, pole, 0) == [1.0] * 14


def test_canceller_is_inferred_from_the_levels():
    """On: level² = G (thermal only) or G + a white residue 3× the thermal power; off: flat
    level² (thermal), even with slow clutter raising the classes near 0 Hz; unmeasured
    classes (NaN) are skipped, fewer than 3 classes with G ≥ 1 say off."""
    g = class_thermal_gains(14, 1.0 / 27.0, 0.9, 1)
    assert mti_inferred(list(g), g)
    assert mti_inferred([x + 3.0 for x in g], g)
    assert not mti_inferred([1.0] * 14, g)
    slow = [1.0 + 20.0 * math.exp(-c) for c in range(14)]
    assert not mti_inferred(slow, g)
    nan = [math.nan] * 14
    assert not mti_inferred(nan, g)
    few = [x if x < 1.0 or i == 13 else math.nan for i, x in enumerate(g)]
    assert not mti_inferred(few, g)
    assert not mti_inferred([1.0] * 14, [1.0] * 14)


def test_share_looks_and_factor_span_independent_to_one_common_signal():
    """Share 0: the 4 independent beams' looks and exact ratio; share 1: one look per PRI
    (the former common-mode law); monotone in between."""
    assert share_looks(0.0, 4) == pytest.approx(4.0)
    assert share_looks(1.0, 4) == pytest.approx(1.0)
    for which in (0, 1):
        assert share_factor(0.0, 4, 16, 0.9, 1e-5, which) == pytest.approx(
            dwell_sum_factors(4, 16, 0.9, 1e-5)[which])
        assert share_factor(1.0, 4, 16, 0.9, 1e-5, which) == pytest.approx(
            dwell_sum_factors(1, 16, 0.9, 1e-5)[which])
    shares = np.linspace(0.0, 1.0, 41)
    looks = [share_looks(s, 4) for s in shares]
    facs = [share_factor(s, 4, 16, 0.9, 1e-5, 0) for s in shares]
    assert all(a >= b for a, b in itertools.pairwise(looks))
    assert all(a <= b for a, b in itertools.pairwise(facs))


def _dwell_sums(share: float, n: int, k: int, pole: float, rng: np.random.Generator
                ) -> np.ndarray:
    """n dwell sums Σ_b Σ_k |y_b| of 4 beams, each the one-pole filter (stationary start) of
    white complex noise of unit power holding the common share ``share``."""
    def cn(*shape):
        return (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)) / math.sqrt(2)

    a, b = math.sqrt(share), math.sqrt(1.0 - share)
    y = cn(n, 4)  # stationary output, unit power (common share: the same law at start)
    y = a * cn(n, 1) + b * y
    s = np.zeros(n)
    g = math.sqrt(1.0 - pole * pole)
    for _ in range(k):
        x = a * cn(n, 1) + b * cn(n, 4)
        y = pole * y + g * x
        s += np.abs(y).sum(axis=1)
    return s


@pytest.mark.parametrize("share", [0.0, 0.3, 0.6, 0.85, 1.0])
def test_share_factor_against_monte_carlo(share):
    """The q/median ratio at Pfa 1e-3 of simulated dwell sums (K = 16, ρ = 0.9, 2·10⁵
    dwells): the tail-matched looks' factor is not below it (beyond the Monte Carlo's ≈ 1 %
    noise) and at most 10 % above it (the price of matching the tail's scale, not the
    variance: variance-matched looks fell 5.5 % below it at share 0.3)."""
    rng = np.random.default_rng(7)
    s = _dwell_sums(share, 200_000, 16, 0.9, rng)
    mc = np.quantile(s, 1.0 - 1e-3) / np.median(s)
    got = share_factor(share, 4, 16, 0.9, 1e-3, 0)
    assert got >= mc * 0.985, (got, mc)
    assert got <= mc * 1.10, (got, mc)


def test_class_shares_and_floors_per_filter():
    """A class at or below (1 + SHARE_MARGIN) × its thermal power has no share and no floor;
    above it, the share is 1 − 1.1·T/level² with T the canceller-shaped thermal power when
    the levels say the canceller is on, else 1, and the floor its share factor; an unmeasured
    class has none."""
    g = class_thermal_gains(14, 1.0 / 27.0, 0.9, 1)
    th = 2.0  # the calibrated thermal level [SUM units]
    on = [th * math.sqrt(x + 2.0) for x in g]  # canceller on, residue 2× thermal
    sh = class_shares(on, th, g)
    assert SHARE_MARGIN == 0.1
    np.testing.assert_allclose(sh, [1.0 - 1.1 * x / (x + 2.0) for x in g], rtol=1e-12)
    out = residue_floors(sh, [0, 4, 13], 4, 16, 0.9, 1e-5, 0)
    for f, p in zip(out, [0, 4, 13], strict=True):
        share = 1.0 - 1.1 * g[p] / (g[p] + 2.0)
        assert f == pytest.approx(share_factor(share, 4, 16, 0.9, 1e-5, 0))
    off = [th * 1.0] * 14
    off[0] = th * 2.0  # slow clutter in the 0 Hz class
    off[1] = th * 1.04  # within the margin: level² 1.08 ≤ 1.1
    off[5] = math.nan
    sh = class_shares(off, th, g)
    assert sh[0] == pytest.approx(1.0 - 1.1 / 4.0) and sh[1:] == [0.0] * 13
    out = residue_floors(sh, [0, 5, 9], 4, 16, 0.9, 1e-5, 0)
    assert out[0] == pytest.approx(share_factor(1.0 - 1.1 / 4.0, 4, 16, 0.9, 1e-5, 0))
    assert out[1:] == [0.0, 0.0]
