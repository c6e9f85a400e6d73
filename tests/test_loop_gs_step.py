"""The direct loop's written-out Gauss-Seidel pass (``models/loop.py`` ``gs_step``, issue 14)
does what the plain per-wire loop does: the same input mappings (keys in wire order, the same
value objects), the same order of calls, the outputs stored per unit; also when a unit reads
a unit that steps later (last step's outputs), itself, or a unit that stepped before it."""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np

from axir.models.loop import DirectLoop, gs_step


class _Stub:
    """A unit that records its calls and returns fresh outputs (floats and an array)."""

    def __init__(self, name: str, log: list, seed: int) -> None:
        self.name, self.log = name, log
        self.rng = np.random.default_rng(seed)

    def step(self, h: float, inputs: dict[str, Any]) -> dict[str, Any]:
        self.log.append((self.name, h, list(inputs.items())))
        return {"a": float(self.rng.random()), "b": float(self.rng.random()),
                "arr": self.rng.random(3)}


def _plain(plan: list, out: dict, h: float) -> None:
    """The loop as it was before issue 14's written-out pass."""
    for name, unit, wires in plan:
        inputs = {}
        for key, src, skey in wires:
            inputs[key] = out[src][skey]
        out[name] = unit.step(h, inputs)


def _plan(log: list, seed: int) -> list:
    names = ["P", "G", "T", "M"]
    units = {n: _Stub(n, log, seed + k) for k, n in enumerate(names)}
    rng = np.random.default_rng(seed)
    plan = []
    for n in names:  # random wiring: any source (later, earlier, itself), any key order
        wires = [(f"in{j}", names[int(rng.integers(4))], ("a", "b", "arr")[int(rng.integers(3))])
                 for j in range(int(rng.integers(0, 6)))]
        plan.append((n, units[n], wires))
    return plan


def test_gs_step_equals_the_plain_loop_on_random_wirings() -> None:
    for seed in range(40):
        log_a: list = []
        log_b: list = []
        plan_a, plan_b = _plan(log_a, seed), _plan(log_b, seed)
        init = {n: {"a": 0.5, "b": 0.25, "arr": np.zeros(3)} for n in "PGTM"}
        out_a = {k: dict(v) for k, v in init.items()}
        out_b = {k: dict(v) for k, v in init.items()}
        f, run = gs_step(plan_b, step_source=("M", "a"))
        for h in (1e-4, 2e-4, 1e-4):
            _plain(plan_a, out_a, h)
            f(out_b, h, *[u for _, u, _ in plan_b])
        # the written-out run loop: h read from M's output "a" before each pass
        loop_b = type("L", (), {"t": 0.0, "steps": 0})()
        t = 0.0
        while t < 2.0:
            h = float(out_a["M"]["a"])
            _plain(plan_a, out_a, h)
            t += h
        run(loop_b, 2.0, out_b, *[u for _, u, _ in plan_b])
        assert loop_b.t == t and len(log_a) == len(log_b) == 12 + 4 * loop_b.steps
        for (na, ha, ia), (nb, hb, ib) in zip(log_a, log_b, strict=True):
            assert (na, ha) == (nb, hb)
            assert [k for k, _ in ia] == [k for k, _ in ib]
            for (_, va), (_, vb) in zip(ia, ib, strict=True):
                assert np.array_equal(va, vb)
        for n in "PGTM":
            for k in ("a", "b", "arr"):
                assert np.array_equal(out_a[n][k], out_b[n][k])


def test_direct_loop_steps_as_the_plain_loop() -> None:
    """Two DirectLoops, one stepped through ``step`` (the written-out pass), one through the
    plain loop: every output identical for 300 PRIs; a replaced plan is picked up."""
    a, b = DirectLoop.from_params(), DirectLoop.from_params()
    for k in itertools.count():
        if k == 300:
            break
        a.step()
        o = b.out
        h = float(o["RadarManager"]["pri"])
        _plain(b._plan, o, h)
        b.t += h
        for name, d in a.out.items():
            for key, v in d.items():
                w = b.out[name][key]
                assert np.asarray(v).tobytes() == np.asarray(w).tobytes(), (k, name, key)
    calls = []
    unit = a._plan[0][1]
    orig = unit.step
    a._plan = [(n, u, w) for n, u, w in a._plan]  # a replaced plan: its pass is rewritten
    unit.step = lambda h, inputs: calls.append(sorted(inputs)) or orig(h, inputs)
    a.step()
    assert calls == [["bandwidth", "cmd.az", "cmd.el"]]


def test_direct_loop_pickles_and_continues() -> None:
    """The written-out pass is not pickled (a function made by exec): a pickled loop rewrites
    it and continues as the original."""
    import pickle

    a = DirectLoop.from_params()
    for _ in range(50):
        a.step()
    b = pickle.loads(pickle.dumps(a))
    for _ in range(50):
        a.step()
        b.step()
    assert a.t == b.t
    assert a.out["Tracker"]["sum"].tobytes() == b.out["Tracker"]["sum"].tobytes()


def test_run_equals_steps() -> None:
    """``run`` (the written-out loop) and ``step`` repeated: the same t, step count and
    outputs, also after a first part stepped by hand and with a unit's ``step`` wrapped."""
    a, b = DirectLoop.from_params(), DirectLoop.from_params()
    for _ in range(20):
        a.step()
    seen = []
    orig = a.gen.step
    a.gen.step = lambda h, inputs: seen.append(h) or orig(h, inputs)
    a.run(0.03)
    while b.t < 0.03:
        b.step()
    assert (a.t, a.steps) == (b.t, b.steps) and len(seen) == a.steps - 20
    for name, d in a.out.items():
        for key, v in d.items():
            assert np.asarray(v).tobytes() == np.asarray(b.out[name][key]).tobytes(), (name, key)
    rec: list = []
    a.run(0.035, every=10, record=rec)  # the recording path: step by step
    assert rec and a.t >= 0.035
