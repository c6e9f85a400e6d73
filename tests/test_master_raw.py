"""The master's inlined stepping path (issue 14, session 7) on the four real FMUs:
:meth:`Master._advance_raw` through :meth:`Master._raw_plan` makes the same FMI calls as the
generic :meth:`Master._advance` (bit-identical values, both algorithms), raises the same
:class:`FmiError` for a failed call, refuses a freed instance before calling anything, and is
not used when a call is wrapped (the benchmark's timers) — then the generic path steps."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

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


@pytest.mark.parametrize("algorithm", ["gauss-seidel", "jacobi"])
def test_inlined_steps_equal_the_generic_steps(fmu_dir: Path, algorithm: str) -> None:
    runs = []
    for inlined in (True, False):
        with _master(fmu_dir, algorithm) as m:
            m.initialize(0.0, 1.0)
            assert (m._raw_plan() is not None) is True  # real FMUs: every call inlinable
            if not inlined:
                m._raw_plan = lambda: None  # type: ignore[method-assign]
            trace = []
            for _ in range(STEPS):
                m.step(m.next_step_ns())
                trace.append((m.t_ns, _outputs(m)))
            runs.append(trace)
    assert runs[0] == runs[1]
    assert runs[0][-1][0] > runs[0][0][0]  # time advanced


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


def test_a_failed_status_raises_the_calls_fmi_error(fmu_dir: Path) -> None:
    with _master(fmu_dir, "gauss-seidel") as m:
        m.initialize(0.0, 1.0)
        m.run(0.001)
        w = m._writes_into["Tracker"][0]
        w.write.raw = w.write.raw._replace(fn=lambda *args: 3)  # fmi2Error
        with pytest.raises(FmiError) as e:
            m.run(0.002)
        assert e.value.function == f"fmi2Set{w.kind}" and e.value.status == 3
        assert e.value.instance == "Tracker"


def test_a_freed_instance_is_refused_before_any_call(fmu_dir: Path) -> None:
    with _master(fmu_dir, "gauss-seidel") as m:
        m.initialize(0.0, 1.0)
        m.run(0.001)
        epochs = {n: i.epoch for n, i in m.instances.items()}
        steps, t_ns = m.steps, m.t_ns
        m.instances["RadarManager"].close()  # the last unit of the order
        with pytest.raises(FmiError, match="freed"):
            m.step(100_000)
        assert {n: i.epoch for n, i in m.instances.items()} == epochs  # nothing was called
        assert (m.steps, m.t_ns) == (steps, t_ns)
