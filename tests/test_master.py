"""The master algorithm with stub slaves (plain Python, no FMU, no fmpy instance): Gauss-Seidel
vs Jacobi data flow, variable step from an output, integer-nanosecond time, observers, and
every slave freed."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from axir.models.system import Connection
from axir.orchestrator.errors import AxirError
from axir.orchestrator.master import NS, Master
from axir.orchestrator.system import SystemDescription, UnitSpec


class StubSlave:
    """A unit of Real variables ``(name, causality)``; ``dynamics(t, h, values)`` updates the
    outputs at each step (``values``: name → value). Implements what the master calls."""

    def __init__(self, name: str, variables: list[tuple[str, str]], dynamics: Any) -> None:
        self.name = name
        self.vars = [SimpleNamespace(name=n, causality=c, type="Real", valueReference=i)
                     for i, (n, c) in enumerate(variables)]
        self.md = SimpleNamespace(modelVariables=self.vars)
        self.values = {v.name: 0.0 for v in self.vars}
        self.dynamics = dynamics
        self.epoch = 0
        self.calls: list[str] = []
        self.closed = False

    def variable(self, name: str) -> Any:
        return next(v for v in self.vars if v.name == name)

    def bind(self, function: str, vr: Any, n: int, buf: Any) -> Any:
        names = [self.vars[vr[i]].name for i in range(n)]

        def get() -> int:
            for i, name in enumerate(names):
                buf[i] = self.values[name]
            return 0

        def set_() -> int:
            self.epoch += 1
            for i, name in enumerate(names):
                self.values[name] = buf[i]
            return 0

        return get if function.startswith("fmi2Get") else set_

    def call(self, function: str, *args: Any) -> int:
        self.calls.append(function)
        self.epoch += 1
        return 0

    def setup(self, start: float = 0.0, stop: float | None = None) -> None:
        self.calls.append("setup")

    def set_parameter(self, name: str, value: Any) -> None:
        self.epoch += 1
        self.values[name] = float(value)

    def enter_init(self) -> None:
        self.calls.append("enter_init")

    def exit_init(self) -> None:
        self.calls.append("exit_init")

    def do_step(self, t: float, h: float) -> None:
        self.epoch += 1
        self.calls.append("do_step")
        self.dynamics(t, h, self.values)

    def close(self) -> None:
        self.closed = True


def _count(t: float, h: float, v: dict[str, float]) -> None:
    v["y"] += 1.0


def _copy(t: float, h: float, v: dict[str, float]) -> None:
    v["z"] = v["u"]


def _system(conns: list[Connection], **params: dict[str, Any]) -> SystemDescription:
    units = {n: UnitSpec(n, Path(f"{n}.fmu"), dict(params.get(n, {}))) for n in ("A", "B")}
    return SystemDescription(units, conns)


def _stubs(made: dict[str, StubSlave], step_output: float = 0.0):
    def factory(spec: UnitSpec, logging_on: bool) -> StubSlave:
        if spec.name == "A":
            s = StubSlave("A", [("y", "output"), ("h", "output"), ("k", "parameter")], _count)
            s.values["h"] = step_output
        else:
            s = StubSlave("B", [("u", "input"), ("z", "output")], _copy)
        made[spec.name] = s
        return s

    return factory


@pytest.mark.parametrize(("algorithm", "expected_z"), [("gauss-seidel", 1.0), ("jacobi", 0.0)])
def test_gauss_seidel_feeds_later_units_the_new_outputs(algorithm: str, expected_z: float):
    made: dict[str, StubSlave] = {}
    with Master(_system([Connection("A", "y", "B", "u")]), algorithm=algorithm,
                order=["A", "B"], step=0.5, slave_factory=_stubs(made)) as m:
        m.initialize(0.0, 1.0)
        m.step(m.next_step_ns())
    # A counted once; B copied A's output of this step (Gauss-Seidel) or of the last (Jacobi)
    assert made["A"].values["y"] == 1.0
    assert made["B"].values["z"] == expected_z


def test_variable_step_is_read_from_the_step_output_in_integer_nanoseconds():
    made: dict[str, StubSlave] = {}
    with Master(_system([]), order=["A", "B"], step_from="A.h", initial_step=0.3,
                slave_factory=_stubs(made)) as m:
        m.initialize(0.0, 1.0)
        assert m.next_step_ns() == 300_000_000  # no valid step output yet: the initial step
        m.step(m.next_step_ns())
        made["A"].values["h"] = 0.1
        made["A"].epoch += 1
        assert m.run(1.0)
        assert m.t_ns == NS  # 0.3 s + 7 × 0.1 s, no float drift
        assert m.steps == 8


def test_an_invalid_step_output_after_the_first_step_is_an_error():
    made: dict[str, StubSlave] = {}
    with Master(_system([]), order=["A", "B"], step_from="A.h", initial_step=0.1,
                slave_factory=_stubs(made)) as m:
        m.initialize(0.0, 1.0)
        m.step(m.next_step_ns())
        with pytest.raises(AxirError, match="invalid step"):
            m.next_step_ns()


def test_parameters_initialization_order_and_observers():
    made: dict[str, StubSlave] = {}
    seen: list[tuple[str, int]] = []

    class Obs:
        def start(self, master: Master) -> None:
            seen.append(("start", master.t_ns))

        def step(self, master: Master, t_ns: int) -> None:
            seen.append(("step", t_ns))

        def finish(self, master: Master, complete: bool) -> None:
            seen.append(("finish", int(complete)))

    with Master(_system([Connection("A", "y", "B", "u")], A={"k": 4.0}), order=["A", "B"],
                step=0.25, slave_factory=_stubs(made)) as m:
        m.initialize(0.0, 0.5)
        assert made["A"].values["k"] == 4.0
        assert made["A"].calls[:3] == ["setup", "enter_init", "exit_init"]
        assert m.run(0.5, [Obs()])
    assert seen == [("start", 0), ("step", 250_000_000), ("step", 500_000_000), ("finish", 1)]
    assert made["A"].closed and made["B"].closed


def test_a_system_that_does_not_match_the_slaves_is_rejected_and_freed():
    made: dict[str, StubSlave] = {}
    m = Master(_system([Connection("A", "nope", "B", "u")]), order=["A", "B"], step=0.1,
               slave_factory=_stubs(made))
    with pytest.raises(AxirError, match="has no variable 'nope'"):
        m.__enter__()
    assert made["A"].closed and made["B"].closed


def test_realtime_factor_counts_the_simulated_time_of_run():
    """``run`` accounts the simulated seconds it covered and its wall time (the real-time
    factor ``axir run`` can print); ``initialize`` starts the count again."""
    made: dict[str, StubSlave] = {}
    with Master(_system([Connection("A", "y", "B", "u")]), order=["A", "B"], step=0.25,
                slave_factory=_stubs(made)) as m:
        m.initialize(0.0, 1.0)
        assert m.realtime_factor == 0.0 and m.run_simulated_s == 0.0
        assert m.run(0.5) and m.run(1.0)
        assert m.run_simulated_s == 1.0 and m.steps == 4
        assert m.run_wall_s > 0.0
        assert m.realtime_factor == m.run_simulated_s / m.run_wall_s
        m.initialize(0.0, 1.0)
        assert m.run_simulated_s == 0.0 and m.run_wall_s == 0.0
