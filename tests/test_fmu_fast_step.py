"""The shim's fast step (issue 14, ``fmus/step_plan.py``, shim section "fast step").

A doStep with nothing else to do (initialized, every input in domain) is made by the shim
calling the slave's fast step directly, without pythonfmu's bridge or the slave's
``do_step``; everything else is forwarded as before. Checked here:

- a valid step does not call ``do_step``; an out-of-domain input is forwarded (Warning, the
  replacement) and the next valid step is fast again;
- the FMU's outputs equal the model's own, stepped alone with the same inputs (bit for bit);
- a model exception in the fast step gives the status, log message and later behaviour of
  the same exception raised through the forwarded ``do_step``;
- ``fmi2GetRealStatus(fmi2LastSuccessfulTime)`` is t + h after fast steps;
- :class:`~axir.fmus.step_plan.StepPlan`: gather gives what ``ndarray.item`` gives, scatter
  stores what numpy's item assignment stores, and rejects what it rejects.
"""

from __future__ import annotations

import ctypes
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fmu_standin import StandInSlave
from test_fmu_shim_shared import (  # noqa: F401 (shimmed: the fixture the one below uses)
    DT,
    ERROR,
    OK,
    WARNING,
    _init,
    _slave,
    raw,
    shimmed,
)

from axir.fmus.shared_block import CTL_SCREENED
from axir.fmus.step_plan import FAST_DONE, FAST_FORWARD, StepPlan
from axir.models.pedestal import Pedestal

FATAL = 4
LAST_SUCCESSFUL_TIME = 2  # fmi2StatusKind fmi2LastSuccessfulTime


@pytest.fixture
def pedestal(request: pytest.FixtureRequest) -> Path:
    """The shimmed Pedestal FMU (skips where the shim cannot be built)."""
    return request.getfixturevalue("shimmed") / "Pedestal.fmu"


def _spy_do_step(slave: Any) -> list[float]:
    calls: list[float] = []
    orig = slave.do_step
    slave.do_step = lambda t, h: (calls.append(t), orig(t, h))[1]
    return calls


def test_valid_steps_skip_do_step_invalid_input_is_forwarded(pedestal: Path) -> None:
    with raw(pedestal, "fast") as f:
        _init(f)
        calls = _spy_do_step(_slave("fast"))
        lib, c = f.dll, f.component
        ins = _vrs_of(f, "cmd.az", "cmd.el", "bandwidth")
        lib.fmi2SetReal(c, ins, 3, (ctypes.c_double * 3)(0.5, -0.2, 2.0))
        for k in range(5):
            assert lib.fmi2DoStep(c, k * DT, DT, 1) == OK
        assert calls == []
        assert f.getReal([f.vr["az"]])[0] > 0.0
        lib.fmi2SetReal(c, ins, 3, (ctypes.c_double * 3)(float("nan"), -0.2, 2.0))
        f.logs.clear()
        assert lib.fmi2DoStep(c, 5 * DT, DT, 1) == WARNING
        assert calls == [5 * DT] and "cmd.az" in f.logs[0][1]
        assert f.getBoolean([f.vr["input.invalid"]]) == [True]
        lib.fmi2SetReal(c, ins, 3, (ctypes.c_double * 3)(0.5, -0.2, 2.0))
        assert lib.fmi2DoStep(c, 6 * DT, DT, 1) == OK
        assert calls == [5 * DT]  # fast again


def _vrs_of(f: Any, *names: str) -> Any:
    return (ctypes.c_uint * len(names))(*[f.vr[n] for n in names])


def test_fast_steps_equal_the_model_stepped_alone(pedestal: Path) -> None:
    model = Pedestal()
    with raw(pedestal, "same") as f:
        _init(f)
        calls = _spy_do_step(_slave("same"))
        names = [v for v in f.vr if v in model.outputs()]
        scalars = [n for n in names if isinstance(model.outputs()[n], float)]
        rng = np.random.default_rng(7)
        for k in range(200):
            cmd = {"cmd.az": float(rng.uniform(-2, 2)), "cmd.el": float(rng.uniform(-2, 2)),
                   "bandwidth": 2.0}
            f.setReal([f.vr[n] for n in cmd], list(cmd.values()))
            f.doStep(k * DT, DT)
            out = model.step(DT, cmd)
            assert f.getReal([f.vr[n] for n in scalars]) == [out[n] for n in scalars], k
        assert calls == [] and len(scalars) >= 10


def _fail_at_step(f: Any, name: str, exc: Callable[[], BaseException],
                  forward: bool) -> tuple[list, list]:
    """Three steps, the second raising ``exc()`` in model.step (through the forwarded do_step
    when ``forward``: an out-of-domain input); (statuses, logs without Warnings)."""
    _init(f)
    slave = _slave(name)
    step = slave.model.step
    n = [0]

    def flaky(h: float, inputs: Any) -> Any:
        n[0] += 1
        if n[0] == 2:
            raise exc()
        return step(h, inputs)

    slave.model.step = flaky
    lib, c = f.dll, f.component
    statuses = []
    for k in range(3):
        bad = forward and k == 1
        lib.fmi2SetReal(c, _vrs_of(f, "cmd.az"), 1,
                        (ctypes.c_double * 1)(float("nan") if bad else 0.5))
        statuses.append(lib.fmi2DoStep(c, k * DT, DT, 1))
        if statuses[-1] == FATAL:
            break
    return statuses, [(s, m.replace(name, "<name>")) for s, m in f.logs if s != WARNING]


@pytest.mark.parametrize("exc", [lambda: ValueError("boom 50%"), ZeroDivisionError])
def test_model_exception_in_fast_step_is_the_forwarded_one(
        pedestal: Path, exc: Callable[[], BaseException]) -> None:
    with raw(pedestal, "inst_fast") as f:
        fast = _fail_at_step(f, "inst_fast", exc, forward=False)
    with raw(pedestal, "inst_fwd") as f:
        slow = _fail_at_step(f, "inst_fwd", exc, forward=True)
    assert fast == slow
    assert fast[0] == [OK, ERROR, ERROR]
    assert type(exc()).__name__ in fast[1][0][1] and "t=0.001" in fast[1][0][1]


class _Escape(BaseException):
    """Not an Exception: escapes the slave's do_step (pythonfmu: fmi2Fatal)."""


def test_base_exception_in_fast_step_is_fatal_as_forwarded(pedestal: Path) -> None:
    with raw(pedestal, "inst_bfast") as f:
        fast = _fail_at_step(f, "inst_bfast", lambda: _Escape("out"), forward=False)
    with raw(pedestal, "inst_bfwd") as f:
        slow = _fail_at_step(f, "inst_bfwd", lambda: _Escape("out"), forward=True)
    assert fast[0] == slow[0] == [OK, FATAL]
    assert [s for s, _ in fast[1]] == [s for s, _ in slow[1]]


_AFTER_FATAL = """
import gc, sys
sys.path.insert(0, {tests!r})
from pathlib import Path
import test_fmu_shim_shared as T

class Escape(BaseException):
    pass

def boom(h, inputs):
    raise Escape("out")

with T.raw(Path({fmu!r}), "fatal") as f:
    T._init(f)
    T._slave("fatal").model.step = boom
    print(f.dll.fmi2DoStep(f.component, 0.0, 1e-3, 1))
    print(f.dll.fmi2DoStep(f.component, 1e-3, 1e-3, 1))
for _ in range(3):
    gc.collect()
with T.raw(Path({fmu!r}), "next") as f:
    T._init(f)
    f.doStep(0.0, 1e-3)
gc.collect()
print("survived")
"""


def test_process_survives_fmi2fatal(pedestal: Path) -> None:
    """pythonfmu 0.7.0 releases its Python objects a second time in fmi2FreeInstance after a
    Python exception reached it (fmi2Fatal): the slave class is freed while in use and the
    process crashes at a later garbage collection (main's FMUs: SIGSEGV here). The shim no
    longer calls into that component: the next call answers fmi2Error, the process lives on.
    In a subprocess, so that a crash fails this test only."""
    code = _AFTER_FATAL.format(tests=str(Path(__file__).parent), fmu=str(pedestal))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=300, check=False)
    assert r.returncode == 0, r.stderr[-3000:]
    assert r.stdout.split() == [str(FATAL), str(ERROR), "survived"]


def test_last_successful_time_after_fast_steps(pedestal: Path) -> None:
    with raw(pedestal, "lst") as f:
        _init(f)
        lib, c = f.dll, f.component
        value = ctypes.c_double(-1.0)
        t = 0.25
        for _ in range(3):
            assert lib.fmi2DoStep(c, t, DT, 1) == OK
            t += DT
        assert lib.fmi2GetRealStatus(c, LAST_SUCCESSFUL_TIME, ctypes.byref(value)) == OK
        assert value.value == 0.25 + 2 * DT + DT
        lib.fmi2SetReal(c, _vrs_of(f, "cmd.az"), 1, (ctypes.c_double * 1)(float("inf")))
        assert lib.fmi2DoStep(c, t, DT, 1) == WARNING  # forwarded: pythonfmu's time
        assert lib.fmi2GetRealStatus(c, LAST_SUCCESSFUL_TIME, ctypes.byref(value)) == OK
        assert value.value == t + DT


# ------------------------------------------------------------------ StepPlan alone
def _plan(inputs: list, outputs: list) -> tuple[StepPlan, dict[str, np.ndarray]]:
    block = np.zeros(256, dtype=np.uint8)
    buf = {"Real": block[0:160].view(np.float64), "Integer": block[160:208].view(np.int64),
           "Boolean": block[208:216].view(np.bool_)}
    return StepPlan(block, buf, inputs, outputs), buf


def test_gather_gives_python_scalars_and_fresh_arrays() -> None:
    plan, buf = _plan([("b", "Boolean", 3, 1, ()), ("x", "Real", 7, 1, ()),
                       ("arr", "Real", 0, 6, (2, 3)), ("n", "Integer", 2, 1, ()),
                       ("y", "Real", 9, 1, ())], [])
    buf["Real"][:10] = [0.5, 1, 2, 3, 4, 5, 0, -1e300, 0, np.nextafter(1.0, 2.0)]
    buf["Integer"][2] = -(2 ** 62)
    buf["Boolean"][3] = True
    got = plan.gather()
    assert got.keys() == {"b", "x", "arr", "n", "y"}
    for key, want in (("x", -1e300), ("y", np.nextafter(1.0, 2.0)), ("n", -(2 ** 62)),
                      ("b", True)):
        assert type(got[key]) is type(want if key != "y" else 1.0) and got[key] == want
    assert got["arr"].shape == (2, 3) and got["arr"][1, 2] == 5.0
    got["arr"][0, 0] = 99.0  # a copy: the buffer keeps its value
    assert buf["Real"][0] == 0.5


@pytest.mark.parametrize("contiguous", [True, False])
def test_scatter_stores_what_item_assignment_stores(contiguous: bool) -> None:
    pos = [4, 5, 6, 7] if contiguous else [9, 4, 12, 7]
    outs = [(k, "Real", i, 1, ()) for k, i in zip("abcd", pos, strict=True)]
    outs += [("v", "Real", 14, 4, (2, 2)), ("n", "Integer", 1, 1, ()),
             ("f", "Boolean", 2, 1, ())]
    plan, buf = _plan([], outs)
    values = {"a": np.float32(0.1), "b": 3, "c": True, "d": np.array(2.5),
              "v": np.arange(4.0).reshape(2, 2), "n": np.int64(7), "f": 1}
    plan.scatter(values)
    ref = np.zeros(20)
    for k, i in zip("abcd", pos, strict=True):
        ref[i] = values[k]
    assert buf["Real"][pos].tolist() == ref[pos].tolist()
    assert buf["Real"][14:18].tolist() == [0.0, 1.0, 2.0, 3.0]
    assert buf["Integer"][1] == 7 and bool(buf["Boolean"][2]) is True


@pytest.mark.parametrize("odd", [None, "2.5", "abc", [1.0], object(), 2 ** 1100, 1 + 2j])
def test_scatter_of_odd_values_is_item_assignment(odd: Any) -> None:
    """Whatever numpy's item assignment stores or raises for an odd output value, scatter
    stores or raises too (the fast tuple/struct path falls back to it)."""
    plan, buf = _plan([], [("a", "Real", 0, 1, ()), ("b", "Real", 1, 1, ())])
    ref = np.zeros(2)
    try:
        ref[1] = odd
        want: Any = ref[1]
    except Exception as e:
        want = type(e)
    if isinstance(want, type):
        with pytest.raises(want):
            plan.scatter({"a": 1.0, "b": odd})
    else:
        plan.scatter({"a": 1.0, "b": odd})
        assert buf["Real"][0] == 1.0
        assert buf["Real"][1] == want or (np.isnan(want) and np.isnan(buf["Real"][1]))


_ODD_SCALARS = [None, "2.5", "", [1.0], [], np.float32(0.1), 3, True, -1, 2 ** 63, 2.5,
                float("nan"), np.array(2.5), np.array([1, 2]), np.array([0]), np.int64(7),
                np.True_, np.False_, np.array(True), 1 + 2j, object()]


@pytest.mark.parametrize("kind", ["Integer", "Boolean"])
@pytest.mark.parametrize("odd", _ODD_SCALARS, ids=[repr(v)[:12] for v in _ODD_SCALARS])
def test_packed_integer_and_boolean_outputs_are_item_assignment(kind: str, odd: Any) -> None:
    """Two or more contiguous Integer (or Boolean) outputs are packed with one struct.pack
    (session 7): whatever numpy's item assignment stores or raises for an odd value in the
    middle of them, scatter stores or raises too; the other outputs keep their values."""
    outs = [(k, kind, i, 1, ()) for k, i in (("p", 0), ("q", 1), ("r", 2))]
    plan, buf = _plan([], [("a", "Real", 0, 1, ()), *outs])
    ref = np.zeros(3, dtype=buf[kind].dtype)
    values = {"a": 1.5, "p": 1, "q": odd, "r": 2}
    try:
        for j, k in enumerate("pqr"):
            ref[j] = values[k]
    except Exception as e:
        with pytest.raises(type(e)):
            plan.scatter(values)
        return
    plan.scatter(values)
    assert buf[kind][:3].tobytes() == ref.tobytes() and buf["Real"][0] == 1.5


@pytest.mark.parametrize("value", [np.arange(6.0).reshape(2, 3), np.arange(6.0),
                                   np.arange(6).reshape(2, 3), [[0, 1, 2], [3, 4, 5]],
                                   np.arange(6.0).reshape(3, 2), np.arange(6.0).reshape(2, 3).T])
def test_array_output_of_any_layout_is_stored_flat(value: Any) -> None:
    """An array output of its declared shape is copied into a view of that shape (session 7);
    any other value of the same size (flat, list, other shape, transposed, int) is stored
    through np.ravel as before: the same flat values either way."""
    plan, buf = _plan([], [("v", "Real", 2, 6, (2, 3)), ("a", "Real", 0, 1, ())])
    plan.scatter({"v": value, "a": 0.5})
    assert buf["Real"][2:8].tolist() == np.ravel(value).astype(float).tolist()
    with pytest.raises(ValueError):  # a wrong size raises as before
        plan.scatter({"v": np.arange(5.0), "a": 0.5})


def test_scatter_equals_item_assignment_on_random_outputs() -> None:
    """Random outputs of every kind (Reals, several Integers and Booleans, arrays) stored by
    scatter equal numpy's item-by-item assignment into a second, identical block."""
    outs = [("x", "Real", 3, 1, ()), ("y", "Real", 4, 1, ()), ("m", "Real", 6, 6, (3, 2)),
            ("i", "Integer", 0, 1, ()), ("j", "Integer", 1, 1, ()), ("k", "Integer", 3, 1, ()),
            ("b", "Boolean", 0, 1, ()), ("c", "Boolean", 1, 1, ()), ("d", "Boolean", 2, 1, ())]
    rng = np.random.default_rng(14)
    for _ in range(50):
        plan, buf = _plan([], outs)
        values: dict[str, Any] = {"x": rng.normal(), "y": float(rng.integers(-9, 9)),
                                  "m": rng.normal(size=(3, 2))}
        values.update({k: int(rng.integers(-2 ** 62, 2 ** 62)) for k in "ijk"})
        values.update({k: bool(rng.integers(2)) for k in "bcd"})
        plan.scatter(values)
        _, ref = _plan([], [])
        for key, kind, i, size, shape in outs:
            if shape:
                ref[kind][i:i + size] = np.ravel(values[key])
            else:
                ref[kind][i] = values[key]
        for kind in ("Real", "Integer", "Boolean"):
            assert buf[kind].tobytes() == ref[kind].tobytes(), kind


def test_scatter_missing_output_is_a_key_error() -> None:
    plan, _ = _plan([], [("a", "Real", 0, 1, ()), ("b", "Real", 1, 1, ())])
    with pytest.raises(KeyError):
        plan.scatter({"a": 1.0})


# ------------------------------------------------------------------ the slave in process
def _standin(seed: int) -> Any:
    s = StandInSlave(instance_name="x", resources=".")
    s.exit_initialization_mode()
    return s, np.random.default_rng(seed).rayleigh(size=192)


def test_fast_step_and_do_step_give_the_same_outputs() -> None:
    """The stand-in (arrays, Integer, Boolean outputs) stepped through ``do_step`` and through
    the fast step (as the shim calls it: t, h in the block, inputs screened) ends with the
    same value arrays and time, step after step."""
    (a, beams), (b, _) = _standin(1), _standin(1)
    beam_vrs = [i for i, r in enumerate(a._rows) if r.name.startswith("beam.")]
    ped = [i for i, r in enumerate(a._rows) if r.name == "ped.az"]
    t, h = 0.0, 1e-4
    for k in range(20):
        for s in (a, b):
            s.set_real(beam_vrs, (beams * (1 + k)).tolist())
            s.set_real(ped, [0.01 * k])
        assert a.do_step(t, h) is True
        b._shared.step[:] = (t, h)
        b._ctl[CTL_SCREENED] = 1  # what the shim's domain check sets
        assert b._fast_step() == FAST_DONE
        t += h
        for kind in ("Real", "Integer", "Boolean"):
            assert a._buf[kind].tolist() == b._buf[kind].tolist(), (k, kind)
        assert a._time == b._time == t
    count = next(i for i, r in enumerate(a._rows) if r.name == "count")
    assert a._get_one(count) == b._get_one(count) == 5  # min(steps, n_max = 5): it stepped


def test_fast_step_exception_is_raised_by_the_next_do_step() -> None:
    s, _ = _standin(2)

    def boom(h: float, inputs: Any) -> Any:
        raise ArithmeticError("no")

    s.model.step = boom
    s._shared.step[:] = (0.5, 1e-4)
    assert s._fast_step() == FAST_FORWARD
    assert isinstance(s._pending, ArithmeticError) and s._failed is None  # nothing logged yet
    assert s._fast_step() == FAST_FORWARD  # a pending exception: forward, nothing done
    assert s.do_step(0.5, 1e-4) is False  # the forwarded call raises it where step would
    assert s._pending is None and "ArithmeticError: no" in s._failed
    assert "t=0.5" in s._failed
    assert s._fast_step() == FAST_FORWARD  # failed: always forwarded


def test_reset_returns_last_successful_time_to_that_of_a_fresh_instance(pedestal: Path) -> None:
    """fmi2Reset: back to the state right after fmi2Instantiate, also for
    fmi2GetRealStatus(fmi2LastSuccessfulTime) (the shim's own answer after fast steps must
    not outlive the reset)."""
    with raw(pedestal, "lst-reset") as f:
        lib, c = f.dll, f.component
        fresh, value = ctypes.c_double(-1.0), ctypes.c_double(-1.0)
        fresh_status = lib.fmi2GetRealStatus(c, LAST_SUCCESSFUL_TIME, ctypes.byref(fresh))
        _init(f)
        for k in range(3):
            assert lib.fmi2DoStep(c, 0.5 + k * DT, DT, 1) == OK
        assert lib.fmi2GetRealStatus(c, LAST_SUCCESSFUL_TIME, ctypes.byref(value)) == OK
        assert value.value == 0.5 + 3 * DT
        assert lib.fmi2Reset(c) == OK
        value.value = -1.0
        assert lib.fmi2GetRealStatus(c, LAST_SUCCESSFUL_TIME, ctypes.byref(value)) == \
            fresh_status
        assert str(value.value) == str(fresh.value)  # (nan == nan is False)
        _init(f)  # and the reset instance steps fast again, with its own time
        assert lib.fmi2DoStep(c, 0.0, DT, 1) == OK
        assert lib.fmi2GetRealStatus(c, LAST_SUCCESSFUL_TIME, ctypes.byref(value)) == OK
        assert value.value == DT
