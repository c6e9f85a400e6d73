"""The co-simulation master algorithm (on fmpy's low-level API, through :mod:`.fmi`).

- Time is an integer count of nanoseconds (libcosim style): no drift over 10⁷ steps; the float
  time handed to the FMUs is ``t_ns * 1e-9`` computed afresh each step.
- Step size: fixed, or variable — read after every macro step from an output (by default
  ``RadarManager.pri``, the PRI the manager commands), rounded to the nanosecond.
- Orders: **Jacobi** (all inputs taken from the outputs at t, then every unit steps) or
  **Gauss-Seidel** (units step in ``order``; just before a unit steps, its inputs are taken from
  the latest outputs, so units earlier in the order feed those later with values at t + h).
- Observers (recorders, progress bars) are told after each macro step; the master knows nothing
  of CSV files or plots.
- Every instance is freed (fmi2FreeInstance then freeLibrary) on every path: use the master as
  a context manager.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from .errors import AxirError, FmiError, SystemDescriptionError
from .fmi import _CTYPE, FmuInstance, fmi2ValueReference
from .system import Connection, SystemDescription, validate_system

NS = 1_000_000_000


def to_ns(seconds: float) -> int:
    """Seconds → integer nanoseconds (rounded)."""
    return round(seconds * NS)


class Observer(Protocol):
    def start(self, master: Master) -> None: ...
    def step(self, master: Master, t_ns: int) -> None: ...
    def finish(self, master: Master, complete: bool) -> None: ...


@dataclass
class _Transfer:
    """Values of one type moved from one instance to another through a shared buffer."""

    src: FmuInstance
    dst: FmuInstance
    kind: str
    src_vr: Any
    dst_vr: Any
    buf: Any

    def __call__(self) -> None:
        self.src.get_into(self.kind, self.src_vr, self.buf)
        self.dst.set_from(self.kind, self.dst_vr, self.buf)


class Master:
    """Loads a :class:`SystemDescription`, initialises it and steps it."""

    def __init__(
        self,
        system: SystemDescription,
        *,
        algorithm: str = "gauss-seidel",
        order: Sequence[str] | None = None,
        step: float | None = None,
        step_from: str | None = "RadarManager.pri",
        initial_step: float = 1e-4,
        logging_on: bool = False,
    ) -> None:
        if algorithm not in ("gauss-seidel", "jacobi"):
            raise AxirError(f"unknown algorithm {algorithm!r} (gauss-seidel or jacobi)")
        self.system = system
        self.algorithm = algorithm
        self.order = list(order or system.units)
        self.fixed_step_ns = None if step is None else to_ns(step)
        self.step_from = step_from
        self.initial_step_ns = to_ns(initial_step)
        self.logging_on = logging_on
        self.instances: dict[str, FmuInstance] = {}
        self.t_ns = 0
        self.steps = 0
        self.connections: list[Connection] = []
        self._transfers_into: dict[str, list[_Transfer]] = {}
        self._step_port = None

    # -- life cycle -------------------------------------------------------------------------
    def __enter__(self) -> Master:
        try:
            self.load()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def load(self) -> None:
        """Instantiate every FMU and check the connections against the model descriptions."""
        for name in self.order:
            spec = self.system.units[name]
            self.instances[name] = FmuInstance(spec.fmu, name, self.logging_on)
        mds = {n: i.md for n, i in self.instances.items()}
        self.connections, problems = validate_system(self.system, mds)
        if problems:
            raise SystemDescriptionError("invalid system: " + "; ".join(problems))
        self._build_transfers()
        if self.fixed_step_ns is None:
            if not self.step_from:
                raise AxirError("variable step needs step_from = 'Unit.variable'")
            unit, _, var = self.step_from.partition(".")
            if unit not in self.instances:
                raise AxirError(f"step_from {self.step_from!r}: unknown unit {unit!r}")
            self._step_port = self.instances[unit].port([var])

    def close(self) -> None:
        """Free every instance and its library (idempotent)."""
        errors = []
        for inst in self.instances.values():
            try:
                inst.close()
            except Exception as e:  # keep freeing the others
                errors.append(e)
        if errors:
            raise errors[0]

    def _build_transfers(self) -> None:
        groups: dict[tuple[str, str, str], list[Connection]] = {}
        for c in self.connections:
            kind = self.instances[c.src_unit].variable(c.src_var).type
            groups.setdefault((c.src_unit, c.dst_unit, kind), []).append(c)
        self._transfers_into = {n: [] for n in self.instances}
        for (su, du, kind), cs in groups.items():
            src, dst = self.instances[su], self.instances[du]
            n = len(cs)
            self._transfers_into[du].append(_Transfer(
                src, dst, kind,
                (fmi2ValueReference * n)(*[src.variable(c.src_var).valueReference for c in cs]),
                (fmi2ValueReference * n)(*[dst.variable(c.dst_var).valueReference for c in cs]),
                (_CTYPE[kind] * n)(),
            ))

    def initialize(self, start: float = 0.0, stop: float | None = None) -> None:
        """Set parameters, run the initialization mode, then propagate initial outputs."""
        for name in self.order:
            inst, spec = self.instances[name], self.system.units[name]
            inst.setup(start, stop)
            for pname, value in spec.parameters.items():
                inst.set_parameter(pname, value)
            inst.enter_init()
        for name in self.order:
            self.instances[name].exit_init()
        self.t_ns = to_ns(start)
        self._propagate(self.order)

    def _propagate(self, units: Iterable[str]) -> None:
        for u in units:
            for tr in self._transfers_into[u]:
                tr()

    # -- stepping ---------------------------------------------------------------------------
    def next_step_ns(self) -> int:
        """Size of the next macro step: fixed, or read from ``step_from`` (the initial step
        is used while that output is not yet a valid duration, i.e. before the first step)."""
        if self.fixed_step_ns is not None:
            return self.fixed_step_ns
        h = float(self._step_port.read()[0])
        if math.isfinite(h) and h > 0.0:
            return to_ns(h)
        if self.steps == 0:
            return self.initial_step_ns
        raise AxirError(f"{self.step_from} gave an invalid step {h!r} s at t = "
                        f"{self.t_ns / NS:.9f} s")

    def step(self, h_ns: int) -> None:
        """One macro step of ``h_ns`` nanoseconds."""
        t = self.t_ns / NS
        h = h_ns / NS
        if self.algorithm == "jacobi":
            self._propagate(self.order)
            for name in self.order:
                self.instances[name].do_step(t, h)
        else:
            for name in self.order:
                for tr in self._transfers_into[name]:
                    tr()
                self.instances[name].do_step(t, h)
        self.t_ns += h_ns
        self.steps += 1

    def run(self, stop: float, observers: Sequence[Observer] = ()) -> bool:
        """Step until ``stop`` [s]. Returns True when complete, False when interrupted (Ctrl-C).

        Observers are always finished, also on errors, so recorded data is never lost.
        """
        stop_ns = to_ns(stop)
        for o in observers:
            o.start(self)
        complete = False
        try:
            while self.t_ns < stop_ns:
                self.step(min(self.next_step_ns(), stop_ns - self.t_ns))
                for o in observers:
                    o.step(self, self.t_ns)
            complete = True
        except KeyboardInterrupt:
            complete = False
        finally:
            for o in observers:
                o.finish(self, complete)
        return complete


__all__ = ["NS", "FmiError", "Master", "Observer", "to_ns"]
