"""The co-simulation master algorithm (on fmpy's low-level API, through :mod:`.fmi`).

- Time is an integer count of nanoseconds (libcosim style): no drift over 10⁷ steps; the float
  time handed to the FMUs is ``t_ns * 1e-9`` computed afresh each step.
- Step size: fixed, or variable — read after every macro step from an output (by default
  ``RadarManager.pri``, the PRI the manager commands: ``axir.models.system.STEP_SOURCE``),
  rounded to the nanosecond.
- Orders: **Jacobi** (all inputs taken from the outputs at t, then every unit steps) or
  **Gauss-Seidel** (units step in ``order``; just before a unit steps, its inputs are taken from
  the latest outputs, so units earlier in the order feed those later with values at t + h).
- Observers (recorders, progress bars) are told after each macro step; the master knows nothing
  of CSV files or plots.
- Every instance is freed (fmi2FreeInstance then freeLibrary) on every path: use the master as
  a context manager.
- The master steps *slaves* (:class:`Slave`, libcosim's term): in production each is an
  :class:`~.fmi.FmuInstance` (FMI through fmpy, in :mod:`.fmi` only); ``slave_factory`` lets
  tests step plain Python stand-ins without FMUs.
- Data movement (docs/performance.md): the outputs of each (source unit, type) that anything
  needs are read with ONE ``fmi2Get*`` call into a preallocated buffer, and only again after
  the source changed (``FmuInstance.epoch``: a doStep or any set); the inputs of each
  (destination unit, type) are gathered from those buffers (contiguous runs copied between
  precomputed memoryviews)
  and sent with ONE ``fmi2Set*`` call, just before they are needed — values and timing as if
  every connection were a get/set pair executed in place. For FMUs the stepping loop makes
  these calls inline from their parts (:class:`~.fmi.RawCall`; ``Master._advance_raw``).
"""

from __future__ import annotations

import ctypes
import math
import signal
import threading
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from .config import DEFAULT_INITIAL_STEP, DEFAULT_STEP_FROM
from .errors import AxirError, FmiError, SystemDescriptionError
from .fmi import _CTYPE, _WARNING, FmuInstance, RawCall, RawDoStep, fmi2ValueReference
from .stepper import CStepPlan
from .stepper import available as cstep_available
from .system import Connection, SystemDescription, UnitSpec, validate_system

NS = 1_000_000_000


def to_ns(seconds: float) -> int:
    """Seconds → integer nanoseconds (rounded)."""
    return round(seconds * NS)


class Observer(Protocol):
    """Told after each macro step (recorders, progress bars); the master knows no more."""

    def start(self, master: Master) -> None: ...
    def step(self, master: Master, t_ns: int) -> None: ...
    def finish(self, master: Master, complete: bool) -> None: ...


class Slave(Protocol):
    """One simulator as the master uses it (what :class:`~.fmi.FmuInstance` provides).

    Call order: ``setup``, ``set_parameter``…, ``enter_init``, ``exit_init``, then per macro
    step the bound ``fmi2Set*`` calls of its inputs and ``do_step``; ``call("fmi2Reset")``
    returns it to the instantiated state; ``close`` frees it. ``md.modelVariables`` describe
    its variables (name, causality, type, valueReference); ``epoch`` counts the calls that
    may have changed its outputs. Optional: ``bind_do_step()`` → a callable ``(t, h)`` the
    master uses instead of ``do_step`` in its loop (:class:`~.fmi.FmuInstance` has one).
    """

    name: str
    md: Any
    epoch: int

    def variable(self, name: str) -> Any: ...
    def bind(self, function: str, *args: Any) -> Callable[[], int]: ...
    def call(self, function: str, *args: Any) -> int: ...
    def setup(self, start: float = 0.0, stop: float | None = None) -> None: ...
    def set_parameter(self, name: str, value: Any) -> None: ...
    def enter_init(self) -> None: ...
    def exit_init(self) -> None: ...
    def do_step(self, t: float, h: float) -> None: ...
    def close(self) -> None: ...


def fmu_slave(spec: UnitSpec, logging_on: bool) -> FmuInstance:
    """The production slave: the unit's FMU instantiated through fmpy."""
    return FmuInstance(spec.fmu, spec.name, logging_on)


@dataclass
class _SourceRead:
    """The needed outputs of one type of one instance, read with one ``fmi2Get*`` call and
    reused until the instance changes (its ``epoch``: doStep, set, ...)."""

    inst: Slave
    kind: str
    vrs: list[int]  # sorted, unique
    vr: Any = None
    buf: Any = None
    read: Any = None
    epoch: int = -1

    def __post_init__(self) -> None:
        n = len(self.vrs)
        self.vr = (fmi2ValueReference * n)(*self.vrs)
        self.buf = (_CTYPE[self.kind] * n)()
        self.read = self.inst.bind(f"fmi2Get{self.kind}", self.vr, n, self.buf)

    def fresh(self) -> Any:
        """The buffer, re-read if the instance changed since the last read."""
        if self.epoch != self.inst.epoch:
            self.read()
            self.epoch = self.inst.epoch
        return self.buf


@dataclass
class _InputWrite:
    """The connected inputs of one type of one instance: gathered from :class:`_SourceRead`
    buffers and sent with one ``fmi2Set*`` call."""

    dst: Slave
    kind: str
    vrs: list[int]
    #: per source: (read, its instance, runs as (destination view, source view) pairs of
    #: memoryviews into the two buffers, precomputed)
    segments: list[tuple[_SourceRead, Slave, list[tuple[memoryview, memoryview]]]] = \
        field(default_factory=list)
    vr: Any = None
    buf: Any = None
    write: Any = None

    def __post_init__(self) -> None:
        n = len(self.vrs)
        self.vr = (fmi2ValueReference * n)(*self.vrs)
        self.buf = (_CTYPE[self.kind] * n)()
        self.write = self.dst.bind(f"fmi2Set{self.kind}", self.vr, n, self.buf)

    def add_source(self, src: _SourceRead, runs: list[tuple[int, int, int]]) -> None:
        """Copy ``runs`` (dst start, src start, length) from ``src`` before each write, each
        with one slice assignment between precomputed memoryviews of the two ctypes buffers
        (a byte copy: exact; ≈ 0.1 µs whatever the length, where a ctypes item copy costs
        ≈ 0.1 µs per element and a ``ctypes.memmove`` call ≈ 0.6 µs)."""
        dst, sbuf = _typed_view(self.buf, self.kind), _typed_view(src.buf, self.kind)
        self.segments.append((src, src.inst, [(dst[d:d + n], sbuf[s:s + n])
                                              for d, s, n in runs]))

    def __call__(self) -> None:
        for src, inst, copies in self.segments:
            if src.epoch != inst.epoch:
                src.fresh()
            for dst, s in copies:
                dst[:] = s
        self.write()


def _send(writes: tuple[tuple[Any, _InputWrite], ...]) -> None:
    """Gather and send ``writes`` of a :meth:`Master._plan` (what each
    :meth:`_InputWrite.__call__` does)."""
    for sources, w in writes:
        for src, inst, copies in sources:
            if src.epoch != inst.epoch:
                src.read()
                src.epoch = inst.epoch
            for dst, s in copies:
                dst[:] = s
        w.write()


def _send_raw(writes: tuple[Any, ...]) -> None:
    """:func:`_send` through a :meth:`Master._raw_plan` (each FMI call inlined; the
    instances checked for being freed before, by :meth:`Master._advance_raw`)."""
    for sources, (winst, wfn, wargs, _, wname) in writes:
        for src, sinst, copies, (rinst, rfn, rargs, _, rname) in sources:
            if src.epoch != sinst.epoch:
                status = rfn(*rargs)
                if status > _WARNING:
                    rinst.fail(rname, status)
                src.epoch = sinst.epoch
            for dst, s in copies:
                dst[:] = s
        winst.epoch += 1
        status = wfn(*wargs)
        if status > _WARNING:
            winst.fail(wname, status)


def _typed_view(buf: Any, kind: str) -> memoryview:
    """A flat memoryview of a ctypes array of ``_CTYPE[kind]`` items, indexed per item."""
    return memoryview(buf).cast("B").cast(_CTYPE[kind]._type_)


def _runs(pairs: list[tuple[int, int]]) -> list[tuple[int, int, int]]:
    """(dst index, src index) pairs → maximal runs (dst start, src start, length) where both
    indices advance by one."""
    runs: list[list[int]] = []
    for d, s in pairs:
        if runs and d == runs[-1][0] + runs[-1][2] and s == runs[-1][1] + runs[-1][2]:
            runs[-1][2] += 1
        else:
            runs.append([d, s, 1])
    return [(d, s, n) for d, s, n in runs]


class Master:
    """Loads a :class:`SystemDescription`, initialises it and steps it."""

    def __init__(
        self,
        system: SystemDescription,
        *,
        algorithm: str = "gauss-seidel",
        order: Sequence[str] | None = None,
        step: float | None = None,
        step_from: str | None = DEFAULT_STEP_FROM,
        initial_step: float = DEFAULT_INITIAL_STEP,
        logging_on: bool = False,
        slave_factory: Callable[[UnitSpec, bool], Slave] = fmu_slave,
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
        self.slave_factory = slave_factory
        self.instances: dict[str, Slave] = {}
        self.t_ns = 0
        self.steps = 0
        #: wall-clock seconds spent in :meth:`run` (stepping and observers) and the simulated
        #: seconds it covered, summed over the runs since :meth:`initialize`
        self.run_wall_s = 0.0
        self.run_simulated_s = 0.0
        self.connections: list[Connection] = []
        self._writes_into: dict[str, list[_InputWrite]] = {}
        self._sequence: list[tuple[Slave, list[_InputWrite]]] = []
        self._steps: list[tuple[list[_InputWrite], Callable[[float, float], Any]]] = []
        self._step_read: tuple[_SourceRead, int] | None = None

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
        """Instantiate every unit and check the connections against the model descriptions."""
        for name in self.order:
            self.instances[name] = self.slave_factory(self.system.units[name], self.logging_on)
        mds = {n: i.md for n, i in self.instances.items()}
        self.connections, problems = validate_system(self.system, mds)
        if problems:
            raise SystemDescriptionError("invalid system: " + "; ".join(problems))
        step_need = None
        if self.fixed_step_ns is None:
            if not self.step_from:
                raise AxirError("variable step needs step_from = 'Unit.variable'")
            unit, _, var = self.step_from.partition(".")
            if unit not in self.instances:
                raise AxirError(f"step_from {self.step_from!r}: unknown unit {unit!r}")
            v = self.instances[unit].variable(var)
            if v.type not in _CTYPE:
                raise AxirError(f"step_from {self.step_from!r}: a {v.type}, not a number")
            step_need = (unit, v.type, v.valueReference)
        self._build_transfers(step_need)

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

    def _build_transfers(self, step_need: tuple[str, str, int] | None = None) -> None:
        """One :class:`_SourceRead` per (source unit, type), one :class:`_InputWrite` per
        (destination unit, type); ``step_need`` (unit, type, vr) is read along."""
        links: list[tuple[str, str, str, int, int]] = []  # (src, dst, kind, src vr, dst vr)
        for c in self.connections:
            sv = self.instances[c.src_unit].variable(c.src_var)
            dv = self.instances[c.dst_unit].variable(c.dst_var)
            links.append((c.src_unit, c.dst_unit, sv.type, sv.valueReference, dv.valueReference))
        needs: dict[tuple[str, str], set[int]] = {}
        for su, _, kind, svr, _ in links:
            needs.setdefault((su, kind), set()).add(svr)
        if step_need is not None:
            needs.setdefault(step_need[:2], set()).add(step_need[2])
        reads = {key: _SourceRead(self.instances[key[0]], key[1], sorted(vrs))
                 for key, vrs in needs.items()}
        pos = {key: {vr: i for i, vr in enumerate(r.vrs)} for key, r in reads.items()}
        if step_need is not None:
            key = step_need[:2]
            self._step_read = (reads[key], pos[key][step_need[2]])
        # destination buffers: grouped by source (first appearance), in source-buffer order,
        # so each source's values land in as few contiguous runs as possible
        by_dst: dict[tuple[str, str], dict[str, list[tuple[int, int]]]] = {}
        for su, du, kind, svr, dvr in links:
            by_dst.setdefault((du, kind), {}).setdefault(su, []).append(
                (pos[(su, kind)][svr], dvr))
        self._writes_into = {n: [] for n in self.instances}
        for (du, kind), per_src in by_dst.items():
            ordered = [(su, sorted(pairs)) for su, pairs in per_src.items()]
            w = _InputWrite(self.instances[du], kind,
                            [dvr for _, pairs in ordered for _, dvr in pairs])
            d = 0
            for su, pairs in ordered:
                w.add_source(reads[(su, kind)],
                             _runs([(d + k, sp) for k, (sp, _) in enumerate(pairs)]))
                d += len(pairs)
            self._writes_into[du].append(w)
        self._sequence = [(self.instances[n], self._writes_into[n]) for n in self.order]
        # per unit: its input writes and its doStep, bound once (FmuInstance.bind_do_step;
        # a slave without it: its do_step)
        self._steps = [(writes, getattr(inst, "bind_do_step", lambda i=inst: i.do_step)())
                       for inst, writes in self._sequence]

    def initialize(
        self,
        start: float = 0.0,
        stop: float | None = None,
        parameters: Mapping[str, Mapping[str, Any]] | None = None,
    ) -> None:
        """Set parameters, run the initialization mode, then propagate initial outputs.

        ``parameters`` (unit → {name: value}) replaces the system description's parameter
        values for this initialization (a campaign run with its own seeds); units absent from
        it keep the description's values.
        """
        for name in self.order:
            inst = self.instances[name]
            values = self.system.units[name].parameters
            if parameters is not None and name in parameters:
                values = parameters[name]
            inst.setup(start, stop)
            for pname, value in values.items():
                inst.set_parameter(pname, value)
            inst.enter_init()
        for name in self.order:
            self.instances[name].exit_init()
        self.t_ns = to_ns(start)
        self.steps = 0
        self.run_wall_s = self.run_simulated_s = 0.0
        self._propagate(self.order)

    def reset(self) -> None:
        """``fmi2Reset`` every instance: back to the state right after instantiation (the
        parameters take their start values again), time 0, so that :meth:`initialize` can run
        the same loaded instances again (Monte Carlo campaigns reuse them run after run).

        pythonfmu 0.7.0 implements ``fmi2Reset`` by constructing a new Python slave object in
        the same loaded library (``PySlaveInstance::Reset`` → ``initialize``); tested
        bit-identical to a fresh instantiation in tests/test_campaign.py.
        """
        for name in self.order:
            self.instances[name].call("fmi2Reset")
        self.t_ns = 0
        self.steps = 0

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall-clock second of :meth:`run` (> 1: faster than the
        radar's real time); 0.0 before any run."""
        return self.run_simulated_s / self.run_wall_s if self.run_wall_s > 0.0 else 0.0

    def _propagate(self, units: Iterable[str]) -> None:
        for u in units:
            for w in self._writes_into[u]:
                w()

    # -- stepping ---------------------------------------------------------------------------
    def next_step_ns(self) -> int:
        """Size of the next macro step: fixed, or read from ``step_from`` (the initial step
        is used while that output is not yet a valid duration, i.e. before the first step)."""
        if self.fixed_step_ns is not None:
            return self.fixed_step_ns
        src, i = self._step_read
        h = float(src.fresh()[i])
        if math.isfinite(h) and h > 0.0:
            return to_ns(h)
        if self.steps == 0:
            return self.initial_step_ns
        raise AxirError(f"{self.step_from} gave an invalid step {h!r} s at t = "
                        f"{self.t_ns / NS:.9f} s")

    def _plan(self) -> tuple[Any, ...]:
        """The per-step work as flat tuples, built from the current transfers (so a
        benchmark's timers wrapped around ``read``/``write``/doStep are kept): per unit in
        order, ``(writes, do_step)`` with ``writes`` = ``((sources, write), ...)`` and
        ``sources`` = ``((source read, its instance, copies), ...)``. Stepping through it
        makes the same calls in the same order as :meth:`_InputWrite.__call__` and
        :meth:`_SourceRead.fresh`, without their Python frames (≈ 0.1 µs each, 12 + 6 per
        PRI)."""
        return tuple((tuple((tuple((src, inst, tuple(copies)) for src, inst, copies
                                   in w.segments), w) for w in writes), do_step)
                     for writes, do_step in self._steps)

    def _raw_plan(self) -> tuple[Any, ...] | None:
        """:meth:`_plan` with every FMI call in parts (:class:`~.fmi.RawCall`,
        :class:`~.fmi.RawDoStep`) for :meth:`_advance_raw`, which makes the same calls with the
        same checks without a Python frame per call (≈ 1 µs per PRI of the closed loop, issue
        14 session 7). None when some call is not such a bound FMI call (a stand-in slave, a
        benchmark's timer around it): then :meth:`_advance` steps through :meth:`_plan`."""
        out, insts = [], {}
        for writes, do_step in self._steps:
            d = getattr(do_step, "raw", None)
            if not isinstance(d, RawDoStep):
                return None
            ws = []
            for w in writes:
                wr = getattr(w.write, "raw", None)
                if not isinstance(wr, RawCall) or not wr.mutates:
                    return None
                sources = []
                for src, inst, copies in w.segments:
                    rr = getattr(src.read, "raw", None)
                    if not isinstance(rr, RawCall) or rr.mutates:
                        return None
                    sources.append((src, inst, tuple(copies), tuple(rr)))
                    insts[id(rr.inst)] = rr.inst
                ws.append((tuple(sources), tuple(wr)))
                insts[id(wr.inst)] = wr.inst
            out.append((tuple(ws), tuple(d)))
            insts[id(d.inst)] = d.inst
        # (the instances, t and h as C doubles set once per step for every doStep, the plan);
        # plain tuples: Python 3.11 unpacks them fastest
        return tuple(insts.values()), (ctypes.c_double(), ctypes.c_double()), tuple(out)

    def _advance_raw(self, plan: tuple[Any, ...], h_ns: int) -> None:
        """:meth:`_advance` through a :meth:`_raw_plan`: the same calls, status checks and
        epochs. A freed instance is found before the step's first call (the bound calls check
        it at each call): FmiError "instance already freed" for its doStep, nothing called."""
        insts, (ct, ch), plan = plan
        for inst in insts:
            if inst.freed:
                inst.fail("fmi2DoStep", None)
        t = self.t_ns / NS
        h = (self.t_ns + h_ns) / NS - t
        ct.value = t
        ch.value = h
        gauss_seidel = self.algorithm != "jacobi"
        if not gauss_seidel:
            for writes, _ in plan:
                _send_raw(writes)
        for writes, (dinst, dfn, comp, _, _, no_set_prior) in plan:
            if gauss_seidel:
                _send_raw(writes)
            dinst.epoch += 1
            status = dfn(comp, ct, ch, no_set_prior)
            if status > _WARNING:
                dinst.fail("fmi2DoStep", status)
        self.t_ns += h_ns
        self.steps += 1

    def step(self, h_ns: int) -> None:
        """One macro step of ``h_ns`` nanoseconds.

        The FMUs get ``h`` = (next point) − (this point) computed in floating point, so that
        t + h is the next communication point (exactly whenever h ≤ t: the subtraction is
        exact; FMI 2.0 fmi2DoStep: t_{i+1} = t_i + h_i), as libcosim does: with the same
        fixed step both masters then hand the FMUs identical values.
        """
        plan, advance = self._stepping()
        advance(plan, h_ns)

    def _stepping(self) -> tuple[Any, Callable[[Any, int], None]]:
        """The fastest way to step the loaded system, as (plan, advance): the C step
        (:class:`~.stepper.CStepPlan`, when the extension is built and every call is a bound
        FMI call), else the inlined Python calls (:meth:`_raw_plan`), else the generic plan
        (stand-in slaves, a benchmark's timers)."""
        raw = self._raw_plan()
        if raw is None:
            return self._plan(), self._advance
        src = self._step_read[0] if self._step_read is not None else None
        if cstep_available() and (src is None or isinstance(getattr(src.read, "raw", None),
                                                            RawCall)):
            try:
                return CStepPlan(raw, self.algorithm == "jacobi", src), self._advance_c
            except TypeError:  # a call replaced by a Python callable (tests)
                pass
        return raw, self._advance_raw

    def _advance_c(self, plan: CStepPlan, h_ns: int) -> None:
        """:meth:`_advance_raw` through a :class:`~.stepper.CStepPlan`: the same FMI calls
        made in C; a freed instance is refused before the step's first call."""
        for inst in plan.instances:
            if inst.freed:
                inst.fail("fmi2DoStep", None)
        t = self.t_ns / NS
        plan.step(t, (self.t_ns + h_ns) / NS - t)
        self.t_ns += h_ns
        self.steps += 1

    def _advance(self, plan: tuple[Any, ...], h_ns: int) -> None:
        """:meth:`step` through a prepared :meth:`_plan`."""
        t = self.t_ns / NS
        h = (self.t_ns + h_ns) / NS - t
        if self.algorithm == "jacobi":
            for writes, _ in plan:
                _send(writes)
            for _, do_step in plan:
                do_step(t, h)
        else:
            for writes, do_step in plan:
                _send(writes)
                do_step(t, h)
        self.t_ns += h_ns
        self.steps += 1

    def run(self, stop: float, observers: Sequence[Observer] = ()) -> bool:
        """Step until ``stop`` [s]. Returns True when complete, False when interrupted (Ctrl-C).

        Observers are always finished, also on errors, so recorded data is never lost.
        """
        stop_ns = to_ns(stop)
        t0_ns, wall0 = self.t_ns, time.perf_counter()
        for o in observers:
            o.start(self)
        complete = False
        interrupted: list[int] = []
        # Ctrl-C sets a flag checked between steps: raised inside an FMU's Python code it
        # would become fmi2Fatal (pythonfmu) and kill the instance instead of stopping cleanly.
        previous = None
        if threading.current_thread() is threading.main_thread():
            previous = signal.signal(signal.SIGINT, lambda signum, frame: interrupted.append(1))
        plan, advance = self._stepping()
        next_step_ns = self.next_step_ns
        try:
            while self.t_ns < stop_ns and not interrupted:
                advance(plan, min(next_step_ns(), stop_ns - self.t_ns))
                for o in observers:
                    o.step(self, self.t_ns)
            complete = not interrupted
        except KeyboardInterrupt:
            complete = False
        finally:
            if previous is not None:
                signal.signal(signal.SIGINT, previous)
            for o in observers:
                o.finish(self, complete)
            self.run_wall_s += time.perf_counter() - wall0
            self.run_simulated_s += (self.t_ns - t0_ns) / NS
        return complete


__all__ = ["NS", "FmiError", "Master", "Observer", "Slave", "fmu_slave", "to_ns"]
