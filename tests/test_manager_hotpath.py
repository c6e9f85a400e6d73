"""The radar manager's speed helpers (issue 14, session 8: models/manager/hotpath.py and the
scalar paths of models/manager/thresholds.py) give exactly what the array code gives."""

from __future__ import annotations

import math

import numpy as np
import pytest
from manager_scene import Scene, make

from axir.models.loop import DirectLoop
from axir.models.manager import thresholds as th
from axir.models.manager.hotpath import (
    clutter_flags,
    clutter_flags_array,
    ema_at,
    filter_positions,
    filter_positions_array,
)
from axir.models.radar import conventions as radar
from axir.orchestrator.scenario import load_scenario


def _same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and repr(a) == repr(b)  # NaN-safe, types and bits


def test_step_outputs_equal_the_full_outputs_at_every_step_of_the_closed_loop() -> None:
    sc = load_scenario("closed-loop")
    loop = DirectLoop.from_params({n: dict(u.get("parameters", {})) for n, u in sc.units.items()})
    mgr = loop.mgr
    step = mgr.step
    modes, fast = set(), 0

    def checked(dt, inputs):
        nonlocal fast
        had = mgr._out_tmpl is not None
        o = step(dt, inputs)
        assert _same(o, mgr.outputs()), loop.steps
        modes.add(o["mode"])
        fast += had and not o["dwell.done"]
        return o

    mgr.step = checked
    loop._plan = [(n, mgr if u is mgr else u, w) for n, u, w in loop._plan]
    loop.run(0.3)
    assert radar.CONFIRMED in modes and len(modes) >= 2
    assert fast > 1000  # the template path was taken


@pytest.mark.parametrize("seed", [3, 4])
def test_step_outputs_equal_the_full_outputs_through_drops_and_reacquisition(seed) -> None:
    mgr = make()
    scene = Scene(37_000.0, seed=seed)
    modes = []
    for k in range(3 * 1200):
        scene.present = k % 1200 < 900  # the target fades: missed dwells, drop, acquisition
        inp = scene.inputs()
        pri = scene.prev["pri"] if scene.prev else 1e-4
        o = mgr.step(pri, inp)
        assert _same(o, mgr.outputs()), k
        modes.append(o["mode"])
        scene.prev = o
        scene.t += pri
    assert set(modes) == {radar.ACQUISITION, radar.TENTATIVE, radar.CONFIRMED}
    assert modes.count(radar.CONFIRMED) > 500


def test_filter_positions_equal_the_array_code_ties_included() -> None:
    rng = np.random.default_rng(5)
    for _ in range(3000):
        n = int(rng.integers(1, 12))
        pri = float(rng.uniform(5e-5, 4e-4))
        sp = float(rng.choice([1.0 / 3.0, 0.3, 0.25]))
        grid = sp / pri / n
        if rng.random() < 0.4:  # exactly halfway between two grid positions (rint ties)
            d = (int(rng.integers(-60, 60)) + 0.5) * grid
        else:
            d = float(rng.uniform(-3.0, 3.0)) / pri
        got = filter_positions(d, pri, n, sp)
        ref = filter_positions_array(d, pri, n, sp)
        assert got.dtype == np.int64 and np.array_equal(got, ref), (d, pri, n, sp)


def _spread_reference(cells: np.ndarray, n: int) -> np.ndarray:
    """The former array code of thresholds.spread_estimate (np.percentile quartiles)."""
    q25, q50, q75 = np.percentile(cells, (25.0, 50.0, 75.0), axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        est = (q75 - q25) / q50 * math.sqrt(n)
    lo = math.sqrt(th.IQR2)
    return np.clip(np.nan_to_num(est, nan=lo, posinf=lo, neginf=lo), lo, lo * math.sqrt(n))


@pytest.mark.parametrize("m", [5, 9, 13])
def test_spread_estimate_equals_the_percentile_code(m) -> None:
    rng = np.random.default_rng(m)
    for i in range(2000):
        cells = rng.rayleigh(size=(m, 3)) * float(rng.choice([1e-3, 1.0, 50.0]))
        if i % 7 == 0:
            cells[:, 1] = 0.0  # q50 = 0: 0/0
        if i % 11 == 0:
            cells[: m // 2 + 1, 2] = 0.0  # q50 = 0 < q75: x/0
        if i % 5 == 0:
            cells = np.round(cells, 1)  # ties
        n = int(rng.choice([16, 64, 1000]))
        got = th.spread_estimate(cells, n)
        assert got.tobytes() == _spread_reference(cells, n).tobytes()
    bad = rng.rayleigh(size=(m, 3))
    bad[0, 0] = np.nan  # the numpy path
    assert th.spread_estimate(bad, 64).tobytes() == _spread_reference(bad, 64).tobytes()


def _factors_reference(looks, k, pole, pfa, which, spread, excess, common) -> np.ndarray:
    """The former (3,)-array code of thresholds.threshold_factors."""
    out = np.full(3, th.dwell_sum_factors(looks, k, pole, pfa)[which])
    if common is not None and common.any():
        out = np.where(common, np.maximum(out, th.common_mode_factor(k, pole, pfa, which)), out)
    if spread is None:
        return out
    floor = out.copy()
    n = looks * k
    l_thermal = th.dwell_sum_looks(looks, k, pole)
    phi = th.IQR2 / spread**2
    for f, p in enumerate(phi):
        lf = min(float(n), max(1.0, p * n))
        if lf < th.CLUTTER_LOOKS_FRACTION * l_thermal:
            out[f] = max(floor[f], th.rayleigh_sum_factors(th.grid_looks_floor(lf), pfa)[which])
        if excess is not None and excess[f]:
            out[f] = max(out[f], th.clutter_noise_factor(float(spread[f]) / math.sqrt(n), pfa,
                                                         which))
    return out


def test_threshold_factors_equal_the_array_code() -> None:
    rng = np.random.default_rng(9)
    lo = math.sqrt(th.IQR2)
    for i in range(400):
        which = i % 2
        pfa = float(rng.choice([1e-3, 1e-5]))
        spread = lo * np.sqrt(64.0) ** rng.uniform(0.0, 1.0, 3)
        excess = rng.random(3) < 0.4 if i % 3 else None
        common = rng.random(3) < 0.3 if i % 4 else None
        sp = None if i % 9 == 0 else spread
        got = th.threshold_factors(4, 16, 0.9, pfa, which, sp, excess, common)
        ref = _factors_reference(4, 16, 0.9, pfa, which, sp, excess, common)
        assert got.dtype == np.float64 and got.tobytes() == ref.tobytes()


def test_clutter_flags_equal_the_array_code() -> None:
    rng = np.random.default_rng(11)
    for i in range(3000):
        lv = rng.uniform(0.5, 3.0, 14) * 100.0
        lv[rng.random(14) < 0.5] = np.nan  # classes not measured yet
        if i % 10 == 0:
            lv[:] = np.nan
        if i % 13 == 0:
            lv[int(rng.integers(14))] = 0.0  # a zero floor: x/0
        pos = [int(p) for p in rng.integers(0, 14, 3)]
        thermal = 0.0 if i % 17 == 0 else float(rng.uniform(50.0, 150.0))
        got = clutter_flags(lv, pos, thermal, 3.0)
        ref = clutter_flags_array(lv, np.array(pos), thermal, 3.0)
        assert got == (ref[0].tolist(), ref[1].tolist())


def test_ema_at_equals_update_spread_on_the_classes_repeats_included() -> None:
    rng = np.random.default_rng(12)
    for _ in range(2000):
        values = rng.uniform(0.5, 3.0, 14)
        pos = [int(p) for p in rng.integers(0, 4, 3)]  # often a repeated class
        est = rng.uniform(0.5, 3.0, 3)
        avg = float(rng.choice([1.0, 8.0, 20.0]))
        ref = values.copy()
        ema = ref[pos]
        th.update_spread(ema, np.zeros((9, 3)), 64, avg, est)
        ref[pos] = ema
        ema_at(values, pos, est, avg)
        assert values.tobytes() == ref.tobytes()


def test_clutter_noise_factor_equals_the_bisection_through_its_iqr_function() -> None:
    ln2, ln15 = math.log(2.0), math.log(1.5)

    def iqr(u: float) -> float:
        return math.sqrt(1.0 + 2.0 * u * ln2) - math.sqrt(max(1.0 - 2.0 * u * ln15, 0.0))

    def reference(r: float, pfa: float) -> float:  # the former loop, q/median
        lo, hi = 0.0, 0.5 / ln2
        if r >= iqr(hi):
            lo = hi
        else:
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                if iqr(mid) < r:
                    lo = mid
                else:
                    hi = mid
        u = 0.5 * (lo + hi)
        return math.sqrt(1.0 + 2.0 * u * (math.log(1.0 / pfa) - ln2))

    for r in np.linspace(0.0, 1.0, 2001).tolist():
        for pfa in (1e-3, 1e-5):
            assert th.clutter_noise_factor(r, pfa, 0) == reference(r, pfa)
