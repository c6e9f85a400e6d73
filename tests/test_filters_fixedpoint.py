"""Fixed-point emulation of the reduced SVD filter with the seed-002 Table 3 word lengths."""

from __future__ import annotations

import math
import pickle
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from axir.models.filters.base import FilterConfig
from axir.models.filters.fixedpoint import TABLE3, Format, TableQuantiser
from axir.models.filters.svd import SVDReducedFilter
from axir.models.tracker import Tracker

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "reports"))
from fixed_point import radial_truth


def test_quantiser_rounding_sign_saturation() -> None:
    f = Format(8, 1.0, 0.002)
    lsb = 1 / 256
    assert f.lsb == lsb and f.largest == 255 * lsb
    assert f.quantise(0.1) == (round(0.1 / lsb) * lsb, False)
    assert f.quantise(2.5 * lsb) == (2 * lsb, False)  # ties to even
    assert f.quantise(3.5 * lsb) == (4 * lsb, False)
    assert f.quantise(-0.1) == (-round(0.1 / lsb) * lsb, False)  # sign-magnitude
    assert f.quantise(7.0) == (255 * lsb, True) and f.quantise(-7.0) == (-255 * lsb, True)
    assert math.isnan(f.quantise(math.nan)[0])


@pytest.mark.parametrize("name,rel", [("X1", 0.01), ("P", 0.01), ("K", 0.03), ("Ku", 0.03),
                                      ("Pu", 0.05), ("u", 0.2), ("N", 0.06), ("s_r", 1e-12),
                                      ("s_m", 1e-12), ("I1", 1e-12), ("I2", 1e-12)])
def test_lsb_half_reproduces_the_seed_error_column(name: str, rel: float) -> None:
    """Table 3's "maximum error" is LSB/2 of the stated range and width (the seed rounds:
    38 for 38.15, 0.1 for 0.117, 0.014 for 0.0134, 9 for N's 8.5)."""
    fmt = TABLE3[name]
    assert fmt.lsb / 2 == pytest.approx(fmt.paper_error, rel=rel)


def test_one_implementation_identity_hook_is_float() -> None:
    """The hook sits on the registers only: an identity hook gives the float filter exactly;
    the Table 3 hook touches every Table 3 variable."""
    truth, _ = radial_truth([(30.0, 50.0, 20.0)], 80)
    z = truth + np.random.default_rng(4).normal(0.0, 100.0, 80)
    names: set[str] = set()

    def spy(name: str, value: float) -> float:
        names.add(name)
        return value

    a = SVDReducedFilter(FilterConfig())
    b = SVDReducedFilter(FilterConfig(quant=spy))
    c = SVDReducedFilter(FilterConfig(quant=TableQuantiser()))
    for zk in z:
        assert a.update(float(zk), 1.0) == b.update(float(zk), 1.0)
        assert a.x == b.x and a.P == b.P
        c.update(float(zk), 1.0)
    assert names == set(TABLE3)
    assert c.x != a.x
    lsb = TABLE3["X1"].lsb
    assert c.X1 / lsb == pytest.approx(round(c.X1 / lsb), abs=1e-9)  # on the 16-bit grid


def test_propagated_error_within_first_order_bound() -> None:
    """No maneuver, steady state: the fixed-point X1, X2 stay within the bound of the error
    dynamics e(k+1) = (I − KH)Φ e(k) + δ driven by the per-step rounding δ (LSB/2 of the X1
    register and of m1 = X1 + T·X2, K·LSB_R/2, and the gain rounding LSB_K/2 times the largest
    innovation): |e| ≤ Σ_j |A^j| δ."""
    cfg = FilterConfig(sigma_m=5.0, sigma_meas=100.0)
    truth, _ = radial_truth([], 300)
    rng = np.random.default_rng(2)
    e1 = e2 = r_max = 0.0
    for _ in range(10):
        z = truth + rng.normal(0.0, 100.0, truth.size)
        ref, fix = SVDReducedFilter(cfg), SVDReducedFilter(replace(cfg, quant=TableQuantiser()))
        for k, zk in enumerate(z):
            ref.update(float(zk), 1.0)
            fix.update(float(zk), 1.0)
            if k > 20:
                e1 = max(e1, abs(ref.X1 - fix.X1))
                e2 = max(e2, abs(ref.X2 - fix.X2))
                r_max = max(r_max, abs(ref.nu))
    k1, k2 = ref.K1, ref.K2
    A = np.array([[1 - k1, 1 - k1], [-k2, 1 - k2]])  # (I − K H) Φ, T = 1
    lx, lv, lr, lk = (TABLE3[n].lsb for n in ("X1", "X2", "R", "K"))
    delta = np.array([lx + k1 * lr / 2 + lk / 2 * r_max, lv / 2 + k2 * lr / 2 + lk / 2 * r_max])
    gain, M = np.zeros((2, 2)), np.eye(2)
    for _ in range(3000):
        gain += np.abs(M)
        M = A @ M
    b1, b2 = gain @ delta
    assert e1 <= b1 and e2 <= b2, (e1, b1, e2, b2)
    assert e1 > TABLE3["X1"].lsb / 2  # propagation: more than one register's rounding


def test_tracker_fixed_point_parameter() -> None:
    with pytest.raises(ValueError, match="fixed_point"):
        Tracker(fixed_point=True)
    with pytest.raises(ValueError, match="svd_reduced"):
        Tracker(fixed_point=True, input_mode="measurement", filter_range="svd")
    truth, _ = radial_truth([(30.0, 50.0, 20.0)], 60)
    z = truth + np.random.default_rng(7).normal(0.0, 100.0, truth.size)
    common = {"input_mode": "measurement", "filter_range": "svd_reduced", "sigma_range": 100.0}
    fixed, flt = Tracker(fixed_point=True, **common), Tracker(**common)
    inputs = [{"meas.range": float(v), "meas.az": 1.0, "meas.el": 0.0, "meas.valid": 1.0,
               "meas.new": 1.0} for v in z]
    lsb = TABLE3["X1"].lsb
    for k, inp in enumerate(inputs[:30]):
        a, b = fixed.step(1.0, inp), flt.step(1.0, inp)
        if k >= 2 and not a["maneuver"]:
            assert a["track.range"] / lsb == pytest.approx(round(a["track.range"] / lsb),
                                                           abs=1e-9)
            assert abs(a["track.range"] - b["track.range"]) < 400.0
    state = pickle.loads(pickle.dumps(fixed.get_state()))
    first = [fixed.step(1.0, inp) for inp in inputs[30:]]
    other = Tracker()
    other.set_state(state)
    again = [other.step(1.0, inp) for inp in inputs[30:]]
    for a, b in zip(first, again, strict=True):
        assert a.keys() == b.keys()
        assert all(np.array_equal(a[key], b[key]) for key in a)
