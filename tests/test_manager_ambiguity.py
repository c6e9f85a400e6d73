"""PRI set and range-ambiguity resolver (models/manager/ambiguity.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.manager import ambiguity as amb
from axir.models.radar import conventions as radar

KS = amb.DEFAULT_PRI_BINS
MAX_BIN = 2000  # 150 km, the manager's default max_range


def brute_force(ms, ks, max_bin, tol):
    """Reference: every true bin in [0, max_bin + tol] whose apparent bins all match ±tol."""
    b = np.arange(0, max_bin + tol + 1)
    ok = np.ones(b.shape, bool)
    for m, k in zip(ms, ks, strict=True):
        ok &= amb.circular_residual(b, m % k, k) <= tol
    return b[ok]


def test_pris_are_integer_bins_and_ru_matches_radar_convention():
    for k in KS:
        pri = amb.pri_seconds(k)
        assert pri / radar.BIN_S == pytest.approx(k, abs=1e-9)
        assert radar.unambiguous_range(pri) == pytest.approx(k * radar.BIN_M, rel=1e-12)
        assert amb.unambiguous_range_m(k) == k * radar.BIN_M
        assert 90e-6 < pri < 120e-6  # "around 100 µs"
    assert len(set(KS)) == 3
    assert math.gcd(KS[0], KS[1]) == math.gcd(KS[0], KS[2]) == math.gcd(KS[1], KS[2]) == 1


def test_documented_ghost_free_spans():
    assert amb.ghost_free_span_bins(KS, 1) == 172_600
    assert amb.ghost_free_span_bins(KS[:2], 1) == 3_798
    assert amb.ghost_free_span_bins(KS, 1) > MAX_BIN
    # a badly chosen set (harmonics) is ambiguous early
    assert amb.ghost_free_span_bins((200, 400, 600), 1) == 1198  # lcm 1200 − 2


def test_resolver_recovers_every_range_bin_with_one_bin_errors():
    rng = np.random.default_rng(1)
    truth = np.arange(0, MAX_BIN + 1)  # 0 .. 150 km = 10 × the shortest Ru
    assert 3 * KS[0] < MAX_BIN
    errors = rng.integers(-1, 2, size=(truth.size, 3))
    for b, e in zip(truth, errors, strict=True):
        ms = [int(b + ei) % k for ei, k in zip(e, KS, strict=True)]
        got = amb.resolve_bins(ms, KS, MAX_BIN, tol=1)
        assert got is not None and abs(got - b) <= 1, (b, ms, got)
    # exact measurements give the exact bin
    for b in truth[::7]:
        assert amb.resolve_bins([int(b) % k for k in KS], KS, MAX_BIN, tol=1) == b


def test_resolve_range_with_folded_continuous_ranges():
    rng = np.random.default_rng(2)
    pris = [amb.pri_seconds(k) for k in KS]
    for r in rng.uniform(0.0, 3.5 * amb.unambiguous_range_m(KS[0]), 300):
        app = [radar.apparent_range(r, p) + rng.uniform(-75.0, 75.0) for p in pris]
        got = amb.resolve_range(app, KS, 150e3, tol=1)
        assert got is not None and abs(got - r) <= 2 * radar.BIN_M
    assert amb.resolve_range([float("nan"), 1.0, 2.0], KS, 150e3) is None


def test_resolver_matches_brute_force_and_rejects_inconsistent_sets():
    rng = np.random.default_rng(3)
    n_acc = 0
    n = 3000
    for _ in range(n):
        ms = [int(rng.integers(0, k)) for k in KS]
        ref = brute_force(ms, KS, MAX_BIN, 1)
        got = amb.resolve_bins(ms, KS, MAX_BIN, tol=1)
        if ref.size == 0 or ref[-1] - ref[0] > 2:
            assert got is None
        else:
            n_acc += 1
            assert got in ref
    # documented: random triples pass with probability ≈ 3·(2000/200)·(3/211)·(3/223) ≈ 0.6 %
    assert n_acc / n < 0.02


def test_inconsistent_measurement_returns_none():
    b = 2 * KS[0] + 37
    ms = [b % k for k in KS]
    ms[2] = (ms[2] + 5) % KS[2]  # third PRI disagrees by 5 bins
    assert brute_force(ms, KS, MAX_BIN, 1).size == 0
    assert amb.resolve_bins(ms, KS, MAX_BIN, tol=1) is None
    assert amb.resolve_bins([], [], MAX_BIN) is None
    assert amb.resolve_bins([1, 2], KS, MAX_BIN) is None  # length mismatch


def test_single_pri_is_ambiguous_beyond_its_ru():
    assert amb.resolve_bins([37], [KS[0]], MAX_BIN) is None
    assert amb.resolve_bins([37], [KS[0]], KS[0] - 5) == 37  # unambiguous inside one Ru


def test_candidates_and_consistency_helpers():
    c = amb.candidates(0, KS[0], MAX_BIN, tol=1)
    assert 0 in c and 1 in c and KS[0] - 1 in c and KS[0] in c
    assert c.min() >= 0 and c.max() <= MAX_BIN + 1
    assert np.all(amb.circular_residual(c, 0, KS[0]) <= 1)
    b = 1234
    kept = amb.consistent(c, b % KS[1], KS[1], 1)
    assert np.all(amb.circular_residual(kept, b % KS[1], KS[1]) <= 1)
