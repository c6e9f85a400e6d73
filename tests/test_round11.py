"""Issue 14, round 11 (branch spd18): the run loop passes the inputs of the Pedestal, the
TargetGenerator and the Tracker's beams mode positionally (``step(dt, None, *values)``,
``Unit.run_step_args``: no input dict built or read per PRI), each unit reading a mapping into
the same names first. Twins: the positional call against the former step of each unit (the
round-8/9 references, a mapping) on random and poisoned inputs, by the bits of every output,
the exceptions and the state; the loop's choice of the positional call; and the round's
smaller changes (module globals instead of class attributes and numpy's module attributes;
the Tracker's tentative gate cells and mapping defaults moved into ``BeamHelpers``).
"""

from __future__ import annotations

import io
import math
import pickle
from typing import Any

import numpy as np
import pytest
from test_round9 import _FormerPedestal, _FormerTGStep
from test_tracker_round8 import (
    _bits,
    _FormerBeamTracker,
    _inputs,
    _poison,
    _state,
    _tracker,
)

from axir.models.loop import DirectLoop, _positional_keys, _step_args, gs_step, wiring
from axir.models.pedestal import Pedestal
from axir.models.radar.conventions import ACQUISITION, BIN_M, CONFIRMED
from axir.models.radar.tg_outputs import OUTPUTS as TG_OUTPUTS
from axir.models.radar.tg_outputs import output_template
from axir.models.radar.unit import Unit
from axir.models.target_generator import TargetGenerator
from axir.models.tracker import Tracker
from axir.models.tracker.beams import BeamTracker

#: odd input values: numpy and integer types, booleans, non-finite and non-numeric ones
_ODD: list[Any] = [np.float64(0.3), 2, True, np.int64(-1), math.nan, math.inf, -math.inf,
                   "x", None, 1e308, -0.0, np.float32(0.25), [1.0]]


def _call(f: Any, *args: Any) -> Any:
    """The outputs by their bits (keys in order), or the exception's type and message."""
    return _call_out(f, *args)[0]


def _call_out(f: Any, *args: Any) -> tuple[Any, dict[str, Any] | None]:
    """(:func:`_call`'s value, the output mapping or None)."""
    try:
        out = f(*args)
    except Exception as e:  # compared between the twins
        return ("raised", type(e).__name__, str(e)), None
    return [(k, _bits(v)) for k, v in out.items()], out


def _pstate(unit: Unit) -> bytes:
    """The unit's state as pickle bytes without the memo (values, not the identity of shared
    constants: a twin's code compiled in another module holds other 0.0 objects)."""
    st = unit.get_state()
    st.pop("_v", None)
    buf = io.BytesIO()
    p = pickle.Pickler(buf, protocol=4)
    p.fast = True
    p.dump(st)
    return buf.getvalue()


# ------------------------------------------------------------------------------ Pedestal
def test_pedestal_positional_step_equals_the_former_step() -> None:
    """The run loop's positional call and round 9's former Pedestal step (a mapping), twins
    on 4 000 steps: commands and bandwidths random, odd (numpy and integer types, booleans,
    NaN/±inf, strings, None, a list), inputs noted invalid, steps of 0, NaN and −1 s: the
    same outputs (bits), exceptions and state."""
    rng = np.random.default_rng(11)
    new, old = Pedestal(pot_noise=0.002), Pedestal(pot_noise=0.002)
    old.__class__ = _FormerPedestal
    f, keys = new.run_step_args()
    assert keys == ("cmd.az", "cmd.el", "bandwidth") and f == new.step
    odd = 0
    for k in range(4000):
        vals: list[Any] = [float(rng.normal(0.0, 3.0)), float(rng.normal(0.0, 3.0)),
                           float(rng.choice([0.5, 1.0, 5.0, 40.0]))]
        if rng.random() < 0.08:
            vals[int(rng.integers(3))] = _ODD[int(rng.integers(len(_ODD)))]
            odd += 1
        if rng.random() < 0.02:
            new.note_invalid_inputs(["cmd.az"])
            old.note_invalid_inputs(["cmd.az"])
        u = rng.random()
        dt: Any = 1e-4 if u < 0.97 else [0.0, math.nan, -1.0, 3e-4, np.float64(1e-4)][k % 5]
        a = _call(f, dt, None, *vals)
        b = _call(old.step, dt, dict(zip(keys, vals, strict=True)))
        assert a == b, (k, vals, dt)
        assert _pstate(new) == _pstate(old), k
    assert odd > 200


# ----------------------------------------------------------------------- TargetGenerator
@pytest.mark.parametrize("params", [{}, {"mti": 2, "swerling": 1},
                                    {"clutter": False, "noise": False}])
def test_tg_positional_step_equals_the_former_step(params: dict[str, Any]) -> None:
    """The positional call against main's former TargetGenerator step (round 9's reference,
    ``_FormerTGStep``, a mapping): 1 500 steps with the antenna on and off the target (the
    canceller switching), odd inputs (the held-value rule), inputs noted invalid, steps of
    0, 3 PRIs and bad steps, a restored state: the same outputs (bits), exceptions, state."""
    rng = np.random.default_rng(sum(map(ord, repr(params))))
    new, old = TargetGenerator(**params), TargetGenerator(**params)
    old.__class__ = _FormerTGStep
    f, keys = new.run_step_args()
    assert keys == ("antenna.az", "antenna.el", "gate.start", "doppler.centre", "pri")
    o = new.outputs()
    with np.errstate(over="ignore", invalid="ignore"):  # odd Doppler centres (1e308)
        _tg_twins(rng, new, old, f, keys, o)


def _tg_twins(rng: np.random.Generator, new: TargetGenerator, old: TargetGenerator, f: Any,
              keys: tuple[str, ...], o: dict[str, Any]) -> None:
    for k in range(1500):
        pri = 1e-4 if rng.random() < 0.97 else 1.25e-4
        vals: list[Any] = [o["truth.az"] + rng.normal(0.0, 0.01),
                           (o["truth.el"] if k % 500 < 250 else 0.02) + rng.normal(0.0, 0.01),
                           o["truth.range"] - rng.uniform(-1.0, 17.0) * BIN_M,
                           float(rng.uniform(-2e3, 2e3)), pri]
        if rng.random() < 0.05:
            vals[int(rng.integers(5))] = _ODD[int(rng.integers(len(_ODD)))]
        if rng.random() < 0.01:
            new.note_invalid_inputs(["pri"])
            old.note_invalid_inputs(["pri"])
        u = rng.random()
        dt: Any = pri if u < 0.95 else [0.0, 3 * pri, math.nan, -1e-4, np.float64(pri)][k % 5]
        if k % 400 == 399:
            new.set_state(new.get_state())
            old.set_state(old.get_state())
        a, out = _call_out(f, dt, None, *vals)
        b = _call(old.step, dt, dict(zip(keys, vals, strict=True)))
        assert a == b, (k, vals, dt)
        assert _pstate(new) == _pstate(old), k
        if out is not None:
            o = out


def test_tg_output_template_and_numpy_globals() -> None:
    """The step's module-level template is the class's, in OUTPUTS order; np.abs is the
    ufunc the step calls."""
    from axir.models import target_generator as tg

    assert tg._OTEMPLATE is TargetGenerator._otemplate
    assert list(tg._OTEMPLATE) == list(output_template(TG_OUTPUTS))
    assert tg._absolute is np.abs and tg._multiply is np.multiply
    assert "_invalid_noted" in TargetGenerator().__dict__


# ------------------------------------------------------------------------------- Tracker
@pytest.mark.parametrize("params", [{}, {"filter_x": "kalman", "filter_y": "kalman",
                                         "filter_z": "kalman"}, {"ddre_window": 3}])
def test_tracker_positional_step_equals_the_former_step(params: dict[str, Any]) -> None:
    """The beams mode's positional call (``Tracker.run_step_args``) against round 8's former
    step (``_FormerBeamTracker``, a mapping), as test_tracker_round8's random mode sequences
    (drops, tentative phases, hypothesis jumps, poisoned and odd inputs): the same outputs,
    exceptions and state after every step; the tentative gate cells (now a BeamHelpers
    method) were taken."""
    rng = np.random.default_rng(sum(map(ord, repr(params))) + 11)
    new, old = _tracker(**params), _tracker(**params)
    old.core.__class__ = _FormerBeamTracker
    f, keys = new.run_step_args()
    assert f == new.core.step and keys == BeamTracker.STEP_ARGS
    mode, gate, offset, az, el = ACQUISITION, 5000.0, 0.0, 1.0, 0.2
    tentative = raised = 0
    for k in range(2500):
        r = rng.random()
        if r < 0.01 and mode > ACQUISITION:
            mode = ACQUISITION
        elif r < 0.04:
            mode = min(mode + 1, CONFIRMED)
        elif r < 0.045:
            mode = 1
        gate += (rng.choice([-1.0, 1.0]) * rng.uniform(2.5 * BIN_M, 3e3)
                 if rng.random() < 0.01 else rng.normal(0.0, 3.0))
        az = (az + rng.normal(0.0, 1e-3)) % (2 * math.pi)
        el = float(np.clip(el + rng.normal(0.0, 1e-3), -0.2, 1.5707))
        inp = _inputs(rng, k, mode, gate, offset, az, el, strong=rng.random() < 0.85)
        inp.setdefault("alpha", 0.0)
        inp.setdefault("beta", 0.0)
        # session 19's inputs: not resolved (the former step has no Doppler rule)
        inp.setdefault("doppler.range_rate", float(rng.normal(0.0, 300.0)))
        inp.setdefault("doppler.resolved", False)
        _poison(rng, inp)
        if rng.random() < 0.02:
            key = str(rng.choice(["ped.az", "ped.el", "mode", "range.offset", "gate.command",
                                  "alpha", "beta"]))
            inp[key] = _ODD[int(rng.integers(len(_ODD)))]
        T = 1e-4 if rng.random() < 0.97 else float(rng.choice([0.0, math.nan, 2e-4]))
        a = _call(f, T, None, *(inp[key] for key in keys))
        b = _call(old.core.step, T, inp)
        assert a == b, (k, inp)
        assert _state(new.core) == _state(old.core), k
        tentative += mode == 1
        raised += a[0] == "raised"
    assert tentative > 100 and raised > 0


def test_tracker_mapping_defaults_and_a_missing_key() -> None:
    """A mapping that is not a dict, or lacks optional keys, takes the defaults
    (``_mapping_inputs``) as before; ``ped.az`` missing raises KeyError on every path."""
    a, b = _tracker(), _tracker()
    b.core.__class__ = _FormerBeamTracker
    beams = np.random.default_rng(3).exponential(1.0, (4, 16, 3))
    inp = {"beam": beams, "ped.az": 0.3, "ped.el": 0.1, "mode": CONFIRMED}

    class _M(dict):  # another Mapping type: the get path
        pass

    for m in (inp, _M(inp), {**inp, "gate.command": 900.0}):
        assert _call(a.core.step, 1e-4, m) == _call(b.core.step, 1e-4, m)
        assert _state(a.core) == _state(b.core)
    bad = {k: v for k, v in inp.items() if k != "ped.az"}
    assert _call(a.core.step, 1e-4, bad) == _call(b.core.step, 1e-4, bad) == (
        "raised", "KeyError", "'ped.az'")


# ------------------------------------------------------------ run_step_args and the loop
def test_run_step_args_only_for_the_class_s_own_step() -> None:
    """(step, keys) for the Pedestal, the TargetGenerator and the Tracker's beams mode; None
    for a unit without STEP_ARGS, a step replaced on the instance (a wrapper takes the
    mapping), a subclass overriding step, the Tracker's measurement mode or a replaced core
    step."""
    assert Unit().run_step_args() is None
    ped = Pedestal()
    assert ped.run_step_args() == (ped.step, Pedestal.STEP_ARGS)
    ped.step = lambda dt, inputs: {}
    assert ped.run_step_args() is None

    class _SubTG(TargetGenerator):
        def step(self, dt: float, inputs: Any) -> dict[str, Any]:
            return super().step(dt, inputs)

    assert _SubTG().run_step_args() is None
    trk = Tracker()
    assert trk.run_step_args() == (trk.core.step, BeamTracker.STEP_ARGS)
    trk.core.step = lambda T, inputs: {}
    assert trk.run_step_args() is None
    assert Tracker(input_mode="measurement").run_step_args() is None


def test_loop_calls_the_positional_step_when_every_key_is_wired() -> None:
    """``gs_step``'s run loop calls a unit positionally when its wires give exactly its
    STEP_ARGS (each once); otherwise, and for a unit without them, with the mapping."""
    loop = DirectLoop.from_params()
    wires = wiring(loop.units)
    assert _positional_keys(loop.ped, wires["Pedestal"]) == Pedestal.STEP_ARGS
    assert _positional_keys(loop.mgr, wires["RadarManager"]) is None
    assert _positional_keys(loop.ped, wires["Pedestal"][:2]) is None  # bandwidth not wired
    assert _positional_keys(loop.ped, wires["Pedestal"] + wires["Pedestal"][:1]) is None
    assert _step_args(loop.trk, BeamTracker.STEP_ARGS) == loop.trk.core.step
    assert _step_args(loop.trk, BeamTracker.STEP_ARGS[::-1]) is None
    # a loop whose Pedestal misses a wire: the mapping (its default), the same as step
    plan = [(n, u, w if n != "Pedestal" else w[:2]) for n, u, w in loop._plan]
    a, b = DirectLoop.from_params(), DirectLoop.from_params()
    pa = [(n, a.units[n], w) for n, _, w in plan]
    pb = [(n, b.units[n], w) for n, _, w in plan]
    _, run_a = gs_step(pa)
    f_b, _ = gs_step(pb)
    run_a(a, 0.01, a.out, *(u for _, u, _ in pa))
    while b.t < 0.01:
        h = float(b.out["RadarManager"]["pri"])
        f_b(b.out, h, *(u for _, u, _ in pb))
        b.t += h
        b.steps += 1
    assert a.steps == b.steps > 50
    assert ([(u, k, _bits(v)) for u, d in a.out.items() for k, v in d.items()]
            == [(u, k, _bits(v)) for u, d in b.out.items() for k, v in d.items()])


def test_run_loop_positional_equals_the_step_loop_with_options() -> None:
    """``DirectLoop.run`` (positional calls) and ``step`` (mappings) on a loop with the
    3-pulse canceller below 20°, Swerling 1, DDRE and Kalman axes: the same outputs (bits),
    t and steps over three runs, and the same unit states."""
    params = {"TargetGenerator": {"mti": 2, "mti_max_el": 0.35, "swerling": 1, "seed": 5},
              "Tracker": {"ddre_window": 3}, "Pedestal": {"pot_noise": 0.001}}
    a, b = DirectLoop.from_params(params), DirectLoop.from_params(params)
    for end in (0.04, 0.08, 0.12):
        a.run(end)
        while b.t < end:
            b.step()
        assert (a.t, a.steps) == (b.t, b.steps)
        assert ([(u, k, _bits(v)) for u, d in a.out.items() for k, v in d.items()]
                == [(u, k, _bits(v)) for u, d in b.out.items() for k, v in d.items()])
        for ua, ub in ((a.gen, b.gen), (a.ped, b.ped), (a.mgr, b.mgr)):
            assert _pstate(ua) == _pstate(ub)
        assert _state(a.trk.core) == _state(b.trk.core)


def test_positional_call_without_values_raises() -> None:
    """``step(dt, None)`` without the values (their defaults ``...``) raises TypeError on each
    unit and leaves the Pedestal's and the TargetGenerator's state as it was; with every value
    given it steps."""
    ped, gen, trk = Pedestal(), TargetGenerator(), Tracker()
    before = (_pstate(ped), _pstate(gen))
    for f in (ped.step, gen.step, trk.core.step):
        with pytest.raises(TypeError):
            f(1e-4, None)
    assert (_pstate(ped), _pstate(gen)) == before
    with pytest.raises(TypeError):
        ped.step(1e-4, None, 0.1)  # two of three missing
    assert ped.step(1e-4, None, 0.1, -0.2, 1.0)["az.rate"] != 0.0
