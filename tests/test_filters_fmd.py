"""Fading-memory maneuver detector of the seed-002 filters (seed 002 eqs. 11-15)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.stats import chi2

from axir.models.filters.fmd import FadingMemoryDetector, detection_threshold, end_threshold


# ------------------------------------------------------------------ fading-memory detector
def test_fmd_recursion_and_window() -> None:
    fmd = FadingMemoryDetector(a_f=0.8, i1=100.0, i2=5.0)
    assert fmd.window == 5  # seed 002 eq. (15): M = 1/(1 − a_f)
    ds = [1.0, 4.0, 0.5, 9.0]
    ref = 0.0
    for d in ds:
        fmd.innovation(d)
        ref = 0.8 * ref + d  # eq. (11)
    stat = fmd.L
    assert stat == pytest.approx(ref)
    for e in range(1, 8):
        fmd.acceleration(float(e))
    assert fmd.acc == [3.0, 4.0, 5.0, 6.0, 7.0] and fmd.A == 25.0
    fmd.innovation(float("nan"))  # ignored
    stat = fmd.L
    assert stat == pytest.approx(ref)


def test_fmd_hysteresis() -> None:
    fmd = FadingMemoryDetector(a_f=0.5, i1=10.0, i2=3.0)
    fmd.innovation(20.0)
    assert fmd.decide()  # L > I1
    fmd.L = 0.0
    fmd.acceleration(4.0)
    assert fmd.decide()  # held while A ≥ I2
    fmd.acc, fmd.A = [1.0], 1.0
    assert not fmd.decide()
    fmd.acc, fmd.A = [4.0], 4.0
    assert not fmd.decide()  # A alone does not raise it


def test_fmd_two_thresholds_on_l() -> None:
    """end = "hysteresis": enter when L > I1, hold while L ≥ I2, leave below I2; the
    acceleration window plays no part."""
    fmd = FadingMemoryDetector(a_f=0.5, i1=10.0, i2=4.0, end="hysteresis")
    L, flag = 0.0, False
    for d in (1.0, 20.0, 0.0, 0.0, 4.9, 8.0, 7.0):
        fmd.innovation(d)
        fmd.acceleration(1e6)  # ignored by this rule
        L = 0.5 * L + d  # seed 002 eq. (11)
        flag = L > 10.0 or (flag and L >= 4.0)
        assert pytest.approx(L) == fmd.L
        assert fmd.decide() is flag
    fmd2 = FadingMemoryDetector(a_f=0.5, i1=10.0, i2=4.0, end="hysteresis")
    flags = []
    for d in (20.0, 0.0, 0.0, 0.0):  # L = 20, 10, 5, 2.5
        fmd2.innovation(d)
        flags.append(fmd2.decide())
    assert flags == [True, True, True, False]
    # I2 > I1: no hysteresis, the single threshold L > I1
    fmd3 = FadingMemoryDetector(a_f=0.5, i1=4.0, i2=10.0, end="hysteresis")
    flags = []
    for d in (5.0, 1.0, 0.0):  # L = 5, 3.5, 1.75
        fmd3.innovation(d)
        flags.append(fmd3.decide())
    assert flags == [True, False, False]
    with pytest.raises(ValueError, match="end"):
        FadingMemoryDetector(end="window")


def test_default_thresholds_from_chi2() -> None:
    # I2 = 95 % point of χ² with M = 5 dof = 11.07 (seed 002 Table 3: "like 11.04")
    assert end_threshold(5, 0.05) == pytest.approx(chi2.ppf(0.95, 5))
    assert end_threshold(5, 0.05) == pytest.approx(11.04, abs=0.05)
    assert FadingMemoryDetector(0.8).i2 == pytest.approx(chi2.ppf(0.95, 5))
    assert FadingMemoryDetector(0.8, pfa=1e-3).i1 == pytest.approx(
        chi2.ppf(0.999, 9) / 1.8)


def test_default_thresholds_are_scipy_stats_chi2_bit_for_bit() -> None:
    """The thresholds no longer import scipy.stats (start-up, issue 14): the same floats as
    chi2.ppf over fading factors, P_fa, levels, windows and dimensions."""
    for a_f in (0.0, 0.5, 0.8, 0.95, 0.999):
        for pfa in (0.5, 0.05, 1e-3, 1e-6, 1e-12):
            for n_y in (1, 3):
                want = float(chi2.ppf(1.0 - pfa, n_y * (1.0 + a_f) / (1.0 - a_f))) / (1.0 + a_f)
                assert detection_threshold(a_f, pfa, n_y) == want
    for window in (1, 5, 20, 1000):
        for level in (0.3, 0.05, 1e-4):
            for n_a in (1, 3):
                assert end_threshold(window, level, n_a) == float(
                    chi2.ppf(1.0 - level, window * n_a))


def test_detection_threshold_false_alarm_rate_by_simulation() -> None:
    """Under no maneuver d ~ χ²₁: the rate of L > I1 is close to the requested P_fa."""
    rng = np.random.default_rng(5)
    for pfa in (0.05, 0.01):
        thr = detection_threshold(0.8, pfa)
        d = rng.standard_normal(400_000) ** 2
        L = lfilter([1.0], [1.0, -0.8], d)  # eq. (11) over the sequence, L(0) = 0
        rate = float(np.mean(L[100:] > thr))
        assert rate == pytest.approx(pfa, rel=0.35), (pfa, rate)


def test_fmd_validation() -> None:
    with pytest.raises(ValueError, match="a_f"):
        FadingMemoryDetector(a_f=1.0)
    with pytest.raises(ValueError, match="pfa"):
        FadingMemoryDetector(pfa=0.0)
    with pytest.raises(ValueError, match="thresholds"):
        FadingMemoryDetector(i1=-1.0)
    assert math.isfinite(FadingMemoryDetector(a_f=0.0).i1)
