"""Out-of-domain inputs (issue 10 point 5): every input of every FMU is fuzzed with NaN, ±inf,
±1e308 (Reals) or out-of-range integers for ONE step, then sane inputs return. The step answers
without error, a Warning names the variable and the value, and afterwards the outputs equal —
bit for bit — those of a run that never saw the bad value and got the replacement instead (the
last valid value; the start value 0 V for the Pedestal's rate commands). Before the fix a
TargetGenerator ``doppler.centre`` of 1e308 left every beam NaN for ever and ``pri`` = 1e308
failed every later step.

Runs on the real FMUs through fmpy (tests/conftest.py builds them from the working tree).
"""

from __future__ import annotations

import ctypes
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_fmu_all import ELEMENT, FEEDS, FMUS, Driver, free_state, get_state, opened

from axir.fmus.build import DECLARATIONS

REAL_BAD = (math.nan, math.inf, -math.inf, 1e308, -1e308)
INT_BAD = (-5, 99, 2**31 - 1, -(2**31))
WARM = {"TargetGenerator": 12, "Tracker": 12, "Pedestal": 12, "RadarManager": 40}
AFTER = {"TargetGenerator": 8, "Tracker": 8, "Pedestal": 8, "RadarManager": 24}


def _model(name: str) -> Any:
    import importlib

    return importlib.import_module(f"axir.fmus.{DECLARATIONS[name]}").SPEC.model


def _cases(name: str) -> list[tuple[Any, str]]:
    """(port, scalar name) per input port: the scalar itself, or one element of an array
    (a middle bin, the centre filter)."""
    out = []
    for port in _model(name).INPUTS:
        if port.kind is bool:
            continue  # an FMI Boolean is always true or false by the time the unit sees it
        names = port.scalar_names()
        out.append((port, names[len(names) // 2 - 1] if port.shape else names[0]))
    return out


def _override(name: str, k: int, scalar: str, value: float) -> dict[str, Any]:
    feed = FEEDS[name](k)
    m = ELEMENT.match(scalar)
    if m is None:
        return {scalar: value}
    base = m["base"]
    arr = np.array(feed[base], dtype=float)
    arr[tuple(int(i) - 1 for i in m["idx"].split(","))] = value
    return {base: arr}


def _held(name: str, port: Any, scalar: str, k: int) -> float:
    """What the unit must get instead of a bad value at step k (by the ports' declaration)."""
    if port.invalid == "start":
        return port.initial
    prev = FEEDS[name](k - 1)
    m = ELEMENT.match(scalar)
    if m is None:
        return prev[scalar]
    return float(np.asarray(prev[m["base"]])[tuple(int(i) - 1 for i in m["idx"].split(","))])


def _values(drv: Driver) -> tuple[bytes, dict[str, float]]:
    """Outputs as bytes (all but the input.invalid flag/counter) and the flag/counter."""
    out = drv.output_values()
    flags = {k: v for k, v in out.items() if k.startswith("input.invalid")}
    rest = np.array([float(v) for k, v in sorted(out.items()) if k not in flags])
    return rest.tobytes(), flags


@pytest.mark.parametrize("name", FMUS)
def test_bad_input_for_one_step_then_sane(fmu_dir: Path, name: str) -> None:
    n0, m = WARM[name], AFTER[name]
    with opened(fmu_dir, name, "fuzz") as inst:
        drv = Driver(inst, name)
        drv.run(0, n0)
        s0 = get_state(inst)
        try:
            for port, scalar in _cases(name):
                # reference: the replacement value fed directly, never a bad one
                inst.call("fmi2SetFMUstate", s0)
                drv.step(n0, _override(name, n0, scalar, _held(name, port, scalar, n0)))
                ref, ref_flags = [], []
                for k in range(n0 + 1, n0 + 1 + m):
                    drv.step(k)
                    v, f = _values(drv)
                    ref.append(v)
                    ref_flags.append(f)
                bads = INT_BAD if port.kind is int else REAL_BAD
                for bad in bads:
                    what = f"{name}.{scalar} = {bad!r}"
                    inst.call("fmi2SetFMUstate", s0)
                    inst.log.clear()
                    drv.step(n0, _override(name, n0, scalar, bad))  # no exception: not Error
                    text = "\n".join(inst.log)
                    assert "out of domain" in text and scalar in text, (what, inst.log)
                    assert repr(float(bad) if port.kind is float else bad) in text, what
                    got, got_flags = [], []
                    for k in range(n0 + 1, n0 + 1 + m):
                        drv.step(k)
                        v, f = _values(drv)
                        got.append(v)
                        got_flags.append(f)
                    assert got == ref, f"{what}: outputs differ from the held-value run"
                    last = np.frombuffer(got[-1])
                    assert np.isfinite(last).sum() == np.isfinite(np.frombuffer(ref[-1])).sum()
                    if ref_flags[-1]:  # the unit counts the replaced step as invalid
                        assert (got_flags[-1]["input.invalid.count"]
                                == ref_flags[-1]["input.invalid.count"] + 1), what
        finally:
            free_state(inst, s0)


def test_domains_are_in_the_model_description(fmu_dir: Path) -> None:
    """Declared input domains reach the importer as FMI min/max."""
    from fmpy import read_model_description

    md = read_model_description(str(fmu_dir / "Tracker.fmu"))
    v = {x.name: x for x in md.modelVariables}
    assert (v["mode"].min, v["mode"].max) == ("0", "2")
    assert float(v["beam.up[1,1]"].min) == 0.0 and float(v["alpha"].max) == 2.0
    md = read_model_description(str(fmu_dir / "TargetGenerator.fmu"))
    v = {x.name: x for x in md.modelVariables}
    assert float(v["pri"].max) == 1.0 and float(v["doppler.centre"].max) == 1e7
    assert ctypes  # (module used by the shared helpers)
