"""Pedestal.fmu through fmpy's low-level API: outputs equal the model's, state, errors, NaN."""

from __future__ import annotations

import math
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

from axir.fmus.build import build_fmu
from axir.models.pedestal import Pedestal

DT = 1e-3
INPUTS = ("cmd.az", "cmd.el", "bandwidth")


# ------------------------------------------------------------------ fmpy low-level helpers
@dataclass
class Loaded:
    """An instantiated FMU with its variable map and captured log."""

    fmu: FMU2Slave
    md: Any
    vr: dict[str, int]
    logs: list[tuple[int, str]] = field(default_factory=list)
    callbacks: Any = None

    def log_text(self, min_status: int = 0) -> str:
        return "\n".join(m for s, m in self.logs if s >= min_status)

    def names(self, kind: str, causality: str) -> list[str]:
        return [v.name for v in self.md.modelVariables
                if v.type == kind and v.causality == causality]

    def get(self, names: list[str], kind: str = "Real") -> list[Any]:
        getter = {"Real": self.fmu.getReal, "Integer": self.fmu.getInteger,
                  "Boolean": self.fmu.getBoolean}[kind]
        return getter([self.vr[n] for n in names])

    def outputs(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for kind in ("Real", "Integer", "Boolean"):
            names = self.names(kind, "output")
            if names:
                out.update(zip(names, self.get(names, kind), strict=True))
        return out


@contextmanager
def loaded(fmu_path: Path, unzip_dir: str | None = None, instance: str = "inst",
           params: dict[str, float] | None = None, init: bool = True) -> Iterator[Loaded]:
    """Instantiate (loggingOn), optionally initialise; always freeInstance (+ freeLibrary).

    fmpy 0.3.32's ``FMU2Slave.freeInstance()`` calls ``fmi2FreeInstance`` and then
    ``freeLibrary()`` itself; calling ``freeLibrary()`` a second time would dlclose twice.
    """
    md = read_model_description(str(fmu_path))
    d = unzip_dir or extract(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    logs: list[tuple[int, str]] = []

    def logger(component: Any, name: Any, status: int, category: Any, message: bytes) -> None:
        logs.append((status, message.decode() if isinstance(message, bytes) else str(message)))

    fmu = FMU2Slave(guid=md.guid, unzipDirectory=d,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance)
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(logger)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    fmu.instantiate(loggingOn=True, callbacks=cb)
    inst = Loaded(fmu, md, vr, logs, cb)
    try:
        if init:
            fmu.setupExperiment(startTime=0.0)
            fmu.enterInitializationMode()
            for k, v in (params or {}).items():
                t = next(x.type for x in md.modelVariables if x.name == k)
                {"Real": fmu.setReal, "Integer": fmu.setInteger,
                 "Boolean": fmu.setBoolean}[t]([vr[k]], [v])
            fmu.exitInitializationMode()
        yield inst
    finally:
        fmu.freeInstance()


# ------------------------------------------------------------------ tests


@pytest.fixture(scope="module")
def fmu_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_fmu("Pedestal", tmp_path_factory.mktemp("fmu"))


def _cmd(k: int) -> list[float]:
    """A deterministic input sequence exercising rate/acceleration limits."""
    return [3.0 * math.sin(0.01 * k), -2.0 + 0.002 * k, 1.0 + 0.5 * math.cos(0.003 * k)]


def _run(inst, n: int, k0: int = 0, t0: float = 0.0) -> list[dict]:
    ins = [inst.vr[n_] for n_ in INPUTS]
    res = []
    for k in range(k0, k0 + n):
        inst.fmu.setReal(ins, _cmd(k))
        inst.fmu.doStep(t0 + (k - k0) * DT, DT)
        res.append(inst.outputs())
    return res


def test_outputs_equal_model(fmu_path: Path) -> None:
    params = {"seed": 7, "az0": 6.2, "pot_noise": 0.01, "bandwidth0": 3.0}
    model = Pedestal(seed=7, az0=6.2, pot_noise=0.01, bandwidth=3.0)
    with loaded(fmu_path, params=params) as inst:
        init = inst.outputs()
        ref0 = model.outputs()
        assert all(init[k] == ref0[k] for k in init), "initial (calculated) outputs"
        got = _run(inst, 300)
    for k, out in enumerate(got):
        ref = model.step(DT, dict(zip(INPUTS, _cmd(k), strict=True)))
        for name, value in out.items():
            assert value == ref[name], (k, name, value, ref[name])  # bit-identical


def test_two_instances_one_process(fmu_path: Path, tmp_path: Path) -> None:
    d = extract(str(fmu_path), unzipdir=str(tmp_path / "x"))
    with loaded(fmu_path, d, "a", {"seed": 1}) as a, loaded(fmu_path, d, "b", {"seed": 2}) as b:
        ra, rb = _run(a, 50), _run(b, 50)
        assert ra[-1]["pot.az.a"] != rb[-1]["pot.az.a"] or ra[-1]["pot.el.a"] != rb[-1][
            "pot.el.a"], "instances must have separate noise generators"
        # a third instance from another extraction of the same FMU also coexists
        with loaded(fmu_path, None, "c", {"seed": 1}) as c:
            assert _run(c, 50) == ra


def _shimmed(fmu_path: Path) -> bool:
    """The FMU carries the C shim that returns fmi2Error (default build, needs gcc)."""
    with zipfile.ZipFile(fmu_path) as z:
        return "binaries/linux64/Pedestal_pythonfmu.so" in z.namelist()


def test_invalid_parameter_is_not_fatal(fmu_path: Path) -> None:
    """The adapter logs an Error naming the parameter at exitInitializationMode, which the C
    shim answers with fmi2Error (pythonfmu 0.7.0 alone: OK there, then fmi2Discard at every
    doStep); never fmi2Fatal."""
    shim = _shimmed(fmu_path)
    for name, value in (("rate_per_volt", -1.0), ("pot_noise", 50.0)):  # range, cross-check
        with loaded(fmu_path, init=False) as inst:
            inst.fmu.setupExperiment(startTime=0.0)
            inst.fmu.enterInitializationMode()
            inst.fmu.setReal([inst.vr[name]], [value])
            if shim:
                with pytest.raises(FMICallException) as e:
                    inst.fmu.exitInitializationMode()
                assert e.value.status == 3  # fmi2Error
            else:
                inst.fmu.exitInitializationMode()
            assert any(s == 3 and name in m for s, m in inst.logs), inst.logs
            with pytest.raises(FMICallException) as e:
                inst.fmu.doStep(0.0, DT)
            assert e.value.status == (3 if shim else 2)  # not fatal: usable/freeable
            assert not any(s == 4 for s, _ in inst.logs)


def test_nan_input_warns_and_continues(fmu_path: Path) -> None:
    with loaded(fmu_path) as inst:
        inst.fmu.setReal([inst.vr["cmd.az"]], [float("nan")])
        inst.fmu.doStep(0.0, DT)
        assert any(s == 1 and "cmd.az" in m for s, m in inst.logs), inst.logs
        out = inst.outputs()
        assert out["input.invalid"] and out["input.invalid.count"] == 1
        assert math.isfinite(out["az"])
        inst.fmu.setReal([inst.vr["cmd.az"]], [0.5])
        inst.fmu.doStep(DT, DT)
        assert not inst.outputs()["input.invalid"]


def test_fixed_parameter_after_init_ignored(fmu_path: Path) -> None:
    with loaded(fmu_path) as inst:
        try:
            inst.fmu.setReal([inst.vr["rate_per_volt"]], [5.0])
            assert not _shimmed(fmu_path), "the shim answers fmi2Error"
        except FMICallException as e:
            assert e.status == 3 and _shimmed(fmu_path)
        assert "rate_per_volt" in inst.log_text(3)
        assert inst.fmu.getReal([inst.vr["rate_per_volt"]]) == [0.1]
        inst.fmu.doStep(0.0, DT)


def test_state_save_restore_bit_identical(fmu_path: Path) -> None:
    with loaded(fmu_path, params={"seed": 3}) as inst:
        _run(inst, 20)
        s = inst.fmu.getFMUState()
        first = _run(inst, 30, k0=20)
        inst.fmu.setFMUState(s)
        again = _run(inst, 30, k0=20)
        inst.fmu.setFMUState(s)  # a state can be restored twice
        third = _run(inst, 30, k0=20)
        inst.fmu.freeFMUState(s)
    assert first == again == third


def test_state_serialize_into_other_instance(fmu_path: Path) -> None:
    with loaded(fmu_path, None, "a", {"seed": 5, "az0": 1.0}) as a:
        _run(a, 25)
        s = a.fmu.getFMUState()
        data = a.fmu.serializeFMUState(s)
        a.fmu.freeFMUState(s)
        ref = _run(a, 40, k0=25)
    assert isinstance(data, bytes) and len(data) > 100
    with loaded(fmu_path, None, "b") as b:  # other instance, default parameters
        s2 = b.fmu.deserializeFMUState(data)
        b.fmu.setFMUState(s2)
        b.fmu.freeFMUState(s2)
        assert b.fmu.getReal([b.vr["az0"]]) == [1.0]  # parameters are part of the state
        assert _run(b, 40, k0=25) == ref


def test_garbage_state_bytes_rejected(fmu_path: Path) -> None:
    with loaded(fmu_path) as inst:
        s = inst.fmu.deserializeFMUState(b"not a state")
        try:
            inst.fmu.setFMUState(s)
            assert not _shimmed(fmu_path), "the shim answers fmi2Error"
        except FMICallException as e:
            assert e.status == 3 and _shimmed(fmu_path)
        inst.fmu.freeFMUState(s)
        assert "unusable state" in inst.log_text(3)
        inst.fmu.doStep(0.0, DT)  # instance still fine
