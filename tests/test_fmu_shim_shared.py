"""The C shim's status rules of issue 10 and its shared value block (issue 14).

- a call during which the FMU logged only a Warning returns ``fmi2Warning`` (pythonfmu alone:
  fmi2OK);
- ``fmi2SetBoolean`` with a value other than fmi2True (1) / fmi2False (0) returns
  ``fmi2Error`` with a log naming the variable, and sets nothing (pythonfmu alone: any
  non-zero int becomes true);
- ``fmi2Get/Set{Real,Integer,Boolean}`` are served from the block the Python slave shares with
  the shim (``fmus/shared_block.py``): valid calls never reach the slave's Python get/set,
  invalid ones still do (and log as before); FMU state save/restore, serialisation and
  ``fmi2Reset`` stay correct with the shared arrays.

All through fmpy's low-level API on the shimmed FMUs (raw ctypes calls where the status
itself is checked: fmpy's wrappers do not raise on fmi2Warning).
"""

from __future__ import annotations

import ctypes
import gc
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

from axir.fmus.build import INNER_SUFFIX, ShimUnavailableError, compile_shim

OK, WARNING, ERROR = 0, 1, 3
DT = 1e-3  # Pedestal step [s]


@pytest.fixture(scope="module")
def shimmed(fmu_dir: Path) -> Path:
    try:
        compile_shim()
    except ShimUnavailableError as e:
        pytest.skip(f"the C shim cannot be built here: {e}")
    import zipfile

    with zipfile.ZipFile(fmu_dir / "Pedestal.fmu") as z:
        if f"binaries/linux64/Pedestal{INNER_SUFFIX}" not in z.namelist():
            pytest.skip("the session's FMUs were built without the shim")
    return fmu_dir


@contextmanager
def raw(fmu: Path, name: str = "raw") -> Iterator[Any]:
    """fmpy's FMU2Slave with a collecting logger (logging on), always freed."""
    md = read_model_description(str(fmu))
    f = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu)),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    f.logs = []
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(
        lambda env, n, status, cat, msg: f.logs.append((status, msg.decode())))
    f.instantiate(loggingOn=True, callbacks=cb)
    f.vr = {v.name: v.valueReference for v in md.modelVariables}
    f.cb = cb
    try:
        yield f
    finally:
        f.freeInstance()


def _vrs(*vrs: int) -> Any:
    return (ctypes.c_uint * len(vrs))(*vrs)


def _slave(instance_name: str) -> Any:
    """The Python slave object pythonfmu built for ``instance_name`` (same interpreter)."""
    gc.collect()  # a slave replaced by fmi2Reset lives on in a reference cycle until then
    found = [o for o in gc.get_objects()
             if any(c.__name__ == "AxirSlave" for c in type(o).__mro__[1:])
             and getattr(o, "instance_name", None) == instance_name]
    assert len(found) == 1, found
    return found[0]


def _init(f: Any) -> None:
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()


# ------------------------------------------------------------------ issue 10 leftovers
def test_warning_only_call_returns_fmi2warning(shimmed: Path) -> None:
    with raw(shimmed / "Pedestal.fmu") as f:
        _init(f)
        lib, c = f.dll, f.component
        nan = (ctypes.c_double * 1)(float("nan"))
        assert lib.fmi2SetReal(c, _vrs(f.vr["cmd.az"]), 1, nan) == OK  # screened at doStep
        f.logs.clear()
        assert lib.fmi2DoStep(c, 0.0, DT, 1) == WARNING
        assert [s for s, _ in f.logs] == [WARNING] and "cmd.az" in f.logs[0][1]
        sane = (ctypes.c_double * 1)(0.5)
        assert lib.fmi2SetReal(c, _vrs(f.vr["cmd.az"]), 1, sane) == OK
        assert lib.fmi2DoStep(c, DT, DT, 1) == OK  # the flag is per call


@pytest.mark.parametrize("bad", [2, -1, 255])
def test_set_boolean_other_than_0_or_1_is_an_error(shimmed: Path, bad: int) -> None:
    with raw(shimmed / "TargetGenerator.fmu") as f:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        vr = _vrs(f.vr["clutter"], f.vr["noise"])
        lib, c = f.dll, f.component
        values = (ctypes.c_int * 2)(0, bad)
        assert lib.fmi2SetBoolean(c, vr, 2, values) == ERROR
        errors = [m for s, m in f.logs if s == ERROR]
        assert len(errors) == 1 and "noise" in errors[0] and str(bad) in errors[0], f.logs
        assert f.getBoolean([f.vr["clutter"], f.vr["noise"]]) == [True, True]  # nothing set
        assert lib.fmi2SetBoolean(c, vr, 2, (ctypes.c_int * 2)(0, 1)) == OK
        assert f.getBoolean([f.vr["clutter"], f.vr["noise"]]) == [False, True]


# ------------------------------------------------------------------ shared value block
def test_valid_get_set_do_not_enter_python(shimmed: Path) -> None:
    """Valid get/set calls are answered by the shim from the shared block (the slave's get/set
    methods are not called) with the values the slave holds; a wrong-type value reference and
    a fixed parameter after initialization still reach the slave and answer fmi2Error."""
    with raw(shimmed / "Pedestal.fmu", "shared") as f:
        _init(f)
        slave = _slave("shared")
        calls: list[str] = []
        for m in ("get_real", "set_real", "get_integer", "set_integer", "get_boolean",
                  "set_boolean"):
            orig = getattr(slave, m)
            setattr(slave, m, lambda *a, _m=m, _o=orig: (calls.append(_m), _o(*a))[1])
        ins = [f.vr[k] for k in ("cmd.az", "cmd.el", "bandwidth")]
        f.setReal(ins, [0.25, -0.125, 2.0])
        buf = slave._buf["Real"]
        assert [buf[slave._index["Real"][v]] for v in ins] == [0.25, -0.125, 2.0]
        for k in range(10):
            f.doStep(k * DT, DT)
        outs = [v for k, v in f.vr.items() if k in ("az", "el", "az.rate")]
        got = f.getReal(outs)
        assert got == [float(buf[slave._index["Real"][v]]) for v in outs]
        assert got[0] > 0.0 and got[2] > 0.0  # the pedestal moves towards the command
        assert f.getInteger([f.vr["input.invalid.count"]]) == [0]
        assert f.getBoolean([f.vr["input.invalid"]]) == [False]
        assert calls == []
        with pytest.raises(FMICallException) as e:
            f.getReal([f.vr["input.invalid.count"]])  # an Integer
        assert e.value.status == ERROR
        with pytest.raises(FMICallException) as e:
            f.setReal([f.vr["rate_per_volt"]], [5.0])  # fixed after initialization
        assert e.value.status == ERROR
        assert calls == ["get_real", "set_real"]
        assert f.getReal([f.vr["rate_per_volt"]]) == [0.1]  # unchanged


def _pedestal_steps(f: Any, k0: int, n: int) -> list[list[float]]:
    ins = [f.vr[k] for k in ("cmd.az", "cmd.el", "bandwidth")]
    outs = [v for k, v in f.vr.items() if k in ("az", "el", "pot.az.a", "az.rate")]
    res = []
    for k in range(k0, k0 + n):
        f.setReal(ins, [0.5 + 0.001 * k, -0.2, 2.0])
        f.doStep(k * DT, DT)
        res.append(f.getReal(outs) + f.getReal(ins))
    return res


def test_fmu_state_restore_with_shared_values(shimmed: Path) -> None:
    """fmi2SetFMUstate (and a serialised round trip) restores the values the shim serves —
    inputs and outputs — and the continuation is bit-identical."""
    with raw(shimmed / "Pedestal.fmu") as f:
        _init(f)
        _pedestal_steps(f, 0, 20)
        saved_values = f.getReal([f.vr["az"], f.vr["cmd.az"]])
        state = f.getFMUstate()
        blob = f.serializeFMUstate(state)
        first = _pedestal_steps(f, 20, 30)
        f.setFMUstate(state)
        assert f.getReal([f.vr["az"], f.vr["cmd.az"]]) == saved_values
        assert _pedestal_steps(f, 20, 30) == first
        f.setFMUstate(f.deSerializeFMUstate(blob))
        assert f.getReal([f.vr["az"], f.vr["cmd.az"]]) == saved_values
        assert _pedestal_steps(f, 20, 30) == first
        f.freeFMUstate(state)


def test_reset_hands_over_a_new_block(shimmed: Path) -> None:
    """After fmi2Reset (pythonfmu builds a new slave object) the shim serves the new slave's
    values: the parameter is back at its start value, and set/step/get work as on a fresh
    instance."""
    with raw(shimmed / "Pedestal.fmu", "reset") as f:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.setReal([f.vr["rate_per_volt"]], [0.2])
        f.exitInitializationMode()
        fresh_run = _pedestal_steps(f, 0, 5)
        f.reset()
        assert f.getReal([f.vr["rate_per_volt"]]) == [0.1]
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.setReal([f.vr["rate_per_volt"]], [0.2])
        f.exitInitializationMode()
        slave = _slave("reset")
        assert slave._buf["Real"][slave._index["Real"][f.vr["rate_per_volt"]]] == 0.2
        assert _pedestal_steps(f, 0, 5) == fresh_run
        assert np.isfinite(f.getReal([f.vr["az"]])[0])


# ------------------------------------------------------------------ input screening in C
def _step_status(f: Any, k: int) -> int:
    return f.dll.fmi2DoStep(f.component, k * DT, DT, 1)


@pytest.mark.parametrize(("name", "value", "status"), [
    ("bandwidth", 0.0, OK), ("bandwidth", 1e6, OK),  # the closed domain's ends
    ("bandwidth", -1e-300, WARNING), ("bandwidth", np.nextafter(1e6, 2e6), WARNING),
    ("bandwidth", float("nan"), WARNING), ("cmd.az", float("inf"), WARNING),
    ("cmd.az", -1e6, OK), ("cmd.az", -1.0000000001e6, WARNING)])
def test_screening_agrees_with_the_domains(shimmed: Path, name: str, value: float,
                                           status: int) -> None:
    """The shim's pre-doStep screen and the slave's check accept exactly the closed domain
    [min, max] of the modelDescription; outside (NaN, inf included) the step warns naming the
    variable."""
    with raw(shimmed / "Pedestal.fmu") as f:
        _init(f)
        f.logs.clear()
        f.setReal([f.vr[name]], [value])
        assert _step_status(f, 0) == status
        warned = [m for s, m in f.logs if s == WARNING]
        assert (len(warned) == 1 and name in warned[0]) if status else not warned, f.logs


def test_integer_input_screened(shimmed: Path) -> None:
    """Tracker ``mode`` (Integer, domain 0..2): 2 passes, 3 and -5 warn, 1 passes again."""
    with raw(shimmed / "Tracker.fmu") as f:
        _init(f)
        for k, (mode, status) in enumerate([(2, OK), (3, WARNING), (-5, WARNING), (1, OK)]):
            f.logs.clear()
            f.setInteger([f.vr["mode"]], [mode])
            assert _step_status(f, k) == status, (mode, f.logs)
            assert any("mode" in m for s, m in f.logs if s == WARNING) == bool(status)


def test_shim_screen_is_the_one_used(shimmed: Path) -> None:
    """With the shared block, in-domain steps do not run the slave's own comparisons: with
    the slave's Python-side bounds made impossible, in-domain inputs still step without a
    warning (the shim checked them on the block's bounds), and the held values follow the
    inputs; an out-of-domain value still gets the slave's full treatment (Warning)."""
    with raw(shimmed / "Pedestal.fmu", "screen") as f:
        _init(f)
        slave = _slave("screen")
        slave._domains = [(d[0], d[1], d[3] + np.inf, d[2] - np.inf, *d[4:])
                          for d in slave._domains]
        f.logs.clear()
        f.setReal([f.vr["cmd.az"], f.vr["bandwidth"]], [0.3, 2.5])
        assert _step_status(f, 0) == OK and f.logs == []
        held = slave._domains[0][6]
        assert 0.3 in held.tolist() and 2.5 in held.tolist()
        f.setReal([f.vr["bandwidth"]], [-1.0])
        assert _step_status(f, 1) == WARNING


def test_bound_calls_check_status_like_call(shimmed: Path) -> None:
    """The master's pre-bound calls (``FmuInstance.bind`` / ``bind_do_step``: the C function
    with arguments converted once) raise the same FmiError as ``call``, and move values."""
    import ctypes as ct

    from axir.orchestrator.errors import FmiError
    from axir.orchestrator.fmi import FmuInstance

    with FmuInstance(shimmed / "Pedestal.fmu", "bound", logging_on=True) as inst:
        step = inst.bind_do_step()
        with pytest.raises(FmiError) as e:  # before initialization: the slave refuses
            step(0.0, DT)
        assert e.value.function == "fmi2DoStep" and e.value.status == ERROR
    with FmuInstance(shimmed / "Pedestal.fmu", "bound2", logging_on=True) as inst:
        inst.setup(0.0)
        inst.enter_init()
        inst.exit_init()
        vr = (ct.c_uint * 1)(inst.variable("rate_per_volt").valueReference)
        buf = (ct.c_double * 1)(5.0)
        set_fixed = inst.bind("fmi2SetReal", vr, 1, buf)
        with pytest.raises(FmiError) as e:
            set_fixed()
        assert e.value.function == "fmi2SetReal" and e.value.status == ERROR
        port = inst.port(["cmd.az"])
        out = inst.port(["az"])
        set_az = inst.bind("fmi2SetReal", port.vr, 1, port.buf)
        get_az = inst.bind("fmi2GetReal", out.vr, 1, out.buf)
        step = inst.bind_do_step()
        port.buf[0] = 0.5
        epoch = inst.epoch
        for k in range(10):
            assert set_az() == OK
            step(k * DT, DT)
        assert inst.epoch == epoch + 20  # sets and doSteps count, gets do not
        get_az()
        assert 0.0 < out.buf[0] < 0.5
        inst.close()
        with pytest.raises(FmiError, match="freed"):
            step(1.0, DT)


TAMPERED_FIRST_SET = """
import sys
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
d = sys.argv[1]
logs = []
md = read_model_description(d)
cb = fmi2CallbackFunctions()
cb.logger = fmi2CallbackLoggerTYPE(lambda c, n, s, cat, m: logs.append(m.decode()))
f = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier="Pedestal")
f.instantiate(loggingOn=True, callbacks=cb)
vr = {v.name: v.valueReference for v in md.modelVariables}
try:
    f.setReal([vr["cmd.az"]], [0.5])
    print("set OK")
except Exception as e:
    print("set refused", e.status)
print(" | ".join(logs))
f.freeInstance()
"""


def test_failed_bundle_check_is_reported_by_the_first_call(shimmed: Path, tmp_path: Path) -> None:
    """A slave whose bundle check failed offers no shared block: the first call, even a set
    the shim could have served, goes through pythonfmu, delivers the Fatal-status message and
    answers fmi2Error (as before the shared values)."""
    import subprocess
    import sys
    import zipfile

    d = tmp_path / "x"
    with zipfile.ZipFile(shimmed / "Pedestal.fmu") as z:
        z.extractall(d)
    slave = next(d.glob("resources/_axir_*/fmus/slave.py"))
    slave.write_text(slave.read_text() + "\n# tampered\n")
    r = subprocess.run([sys.executable, "-c", TAMPERED_FIRST_SET, str(d)], capture_output=True,
                       text=True, timeout=120)
    assert "set refused 3" in r.stdout and "bundled code mismatch" in r.stdout, (r.stdout,
                                                                                  r.stderr)
