"""The master's fast stepping paths on the four real FMUs: the C step (issue 14, session 9:
:class:`~axir.orchestrator.stepper.CStepPlan`, ``Master._advance_c``) and the inlined Python
calls (session 7: :meth:`Master._advance_raw` through :meth:`Master._raw_plan`) make the same
FMI calls as the generic :meth:`Master._advance` (bit-identical values, both algorithms), raise
the same :class:`FmiError` for a failed call, refuse a freed instance before calling anything,
and are not used when a call is wrapped (the benchmark's timers) — then the generic path
steps."""

from __future__ import annotations

import ctypes
import shutil
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

from axir.orchestrator import master as master_module
from axir.orchestrator import stepper
from axir.orchestrator.errors import FmiError
from axir.orchestrator.master import Master
from axir.orchestrator.scenario import load_scenario

STEPS = 300


def _master(fmu_dir: Path, algorithm: str) -> Master:
    sc = replace(load_scenario("closed-loop"), duration=1.0)
    return Master(sc.system(fmu_dir), algorithm=algorithm, order=sc.order, step=sc.step,
                  step_from=sc.step_from, initial_step=sc.initial_step)


def _outputs(m: Master) -> list[Any]:
    """Every connected output the master read last, as bytes (bit-exact)."""
    return [bytes(src.fresh()) for w in (x for ws in m._writes_into.values() for x in ws)
            for src, _, _ in w.segments]


def _use(m: Master, path: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Make ``m`` step through ``path``: "c", "raw" (inlined Python) or "generic"."""
    assert m._raw_plan() is not None  # real FMUs: every call inlinable
    if path == "c":
        assert stepper.available(), "the C step extension is not built"
    else:
        monkeypatch.setattr(master_module, "cstep_available", lambda: False)
    if path == "generic":
        m._raw_plan = lambda: None  # type: ignore[method-assign]
    expected = {"c": "_advance_c", "raw": "_advance_raw", "generic": "_advance"}[path]
    assert m._stepping()[1].__name__ == expected


@pytest.mark.parametrize("algorithm", ["gauss-seidel", "jacobi"])
def test_c_and_inlined_steps_equal_the_generic_steps(fmu_dir: Path, algorithm: str,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    runs = []
    for path in ("c", "raw", "generic"):
        with monkeypatch.context() as mp, _master(fmu_dir, algorithm) as m:
            m.initialize(0.0, 1.0)
            _use(m, path, mp)
            trace = []
            for _ in range(STEPS):
                m.step(m.next_step_ns())
                trace.append((m.t_ns, _outputs(m)))
            m.run(m.t_ns / 1e9 + 0.01)  # run() takes the same path
            trace.append((m.t_ns, _outputs(m)))
            runs.append(trace)
    assert runs[0] == runs[1] == runs[2]
    assert runs[0][-1][0] > runs[0][0][0]  # time advanced


@pytest.mark.skipif(shutil.which("gcc") is None and shutil.which("cc") is None,
                    reason="no C compiler: the optional extension is not built")
def test_the_c_step_is_built_where_a_compiler_is() -> None:
    assert stepper._stepper is not None  # pip install built orchestrator/_stepper.c


def test_a_wrapped_call_falls_back_to_the_generic_path(fmu_dir: Path) -> None:
    with _master(fmu_dir, "gauss-seidel") as m:
        m.initialize(0.0, 1.0)
        calls = []
        w = m._writes_into["Tracker"][0]
        inner = w.write
        w.write = lambda: calls.append(1) or inner()
        assert m._raw_plan() is None
        m.run(0.001)
        assert len(calls) == m.steps > 0  # the wrapper ran once per step


_FAIL_TRANSFER = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p,
                                   ctypes.c_size_t, ctypes.c_void_p)(lambda *args: 3)
_FAIL_STEP = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double, ctypes.c_double,
                               ctypes.c_int)(lambda *args: 4)


@pytest.mark.parametrize("path", ["c", "raw"])
def test_a_failed_status_raises_the_calls_fmi_error(fmu_dir: Path, path: str,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    with _master(fmu_dir, "gauss-seidel") as m:
        m.initialize(0.0, 1.0)
        m.run(0.001)
        w = m._writes_into["Tracker"][0]
        w.write.raw = w.write.raw._replace(fn=_FAIL_TRANSFER)  # a C function answering fmi2Error
        _use(m, path, monkeypatch)
        with pytest.raises(FmiError) as e:
            m.run(0.002)
        assert e.value.function == f"fmi2Set{w.kind}" and e.value.status == 3
        assert e.value.instance == "Tracker"


def test_a_failed_do_step_in_the_c_step_stops_the_step(fmu_dir: Path) -> None:
    """fmi2Fatal from the second unit's doStep: FmiError naming it, and the units after it
    are not stepped (their inputs are not written either)."""
    with _master(fmu_dir, "gauss-seidel") as m:
        m.initialize(0.0, 1.0)
        m.run(0.001)
        second, stepped = m.order[1], []
        count = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double,
                                  ctypes.c_double, ctypes.c_int)(
            lambda *args: stepped.append(args) or 0)
        for i, (_, do_step) in enumerate(m._steps):
            do_step.raw = do_step.raw._replace(fn=_FAIL_STEP if i == 1 else count)
        plan, advance = m._stepping()
        assert advance.__name__ == "_advance_c"
        with pytest.raises(FmiError) as e:
            advance(plan, 100_000)
        assert (e.value.instance, e.value.function, e.value.status) == \
            (second, "fmi2DoStep", 4)
        assert len(stepped) == 1  # the first unit only
        t = m.t_ns / 1e9  # not advanced: the step failed
        assert stepped[0][1:3] == (t, (m.t_ns + 100_000) / 1e9 - t)


@pytest.mark.parametrize("path", ["c", "raw"])
def test_a_freed_instance_is_refused_before_any_call(fmu_dir: Path, path: str,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    with _master(fmu_dir, "gauss-seidel") as m:
        m.initialize(0.0, 1.0)
        _use(m, path, monkeypatch)
        m.run(0.001)
        epochs = {n: i.epoch for n, i in m.instances.items()}
        steps, t_ns = m.steps, m.t_ns
        m.instances["RadarManager"].close()  # the last unit of the order
        with pytest.raises(FmiError, match="freed"):
            m.step(100_000)
        assert {n: i.epoch for n, i in m.instances.items()} == epochs  # nothing was called
        assert (m.steps, m.t_ns) == (steps, t_ns)
