"""The closed tracking loop of SYSTEM.md with the four models in a plain Python loop.

Same connections (:data:`.system.CONNECTIONS`) and the same Gauss-Seidel order
(:data:`.system.GAUSS_SEIDEL_ORDER`: each unit takes the latest outputs of the units before
it) as the FMU master's default. The step is the PRI the manager outputs
(:data:`.system.STEP_SOURCE`). Used by the models-only end-to-end tests and as the reference
("direct loop") of the FMU-loop benchmark. No FMI anywhere.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .manager import RadarManager
from .pedestal import Pedestal
from .radar.unit import Unit
from .system import (
    CONNECTIONS,
    GAUSS_SEIDEL_ORDER,
    PEDESTAL,
    RADAR_MANAGER,
    STEP_SOURCE,
    TARGET_GENERATOR,
    TRACKER,
    Connection,
)
from .target_generator import TargetGenerator
from .tracker import Tracker

#: (input key, source unit, output key) per destination unit
Wires = dict[str, list[tuple[str, str, str]]]
_UNSET = object()  # a unit's outputs not yet in the run loop's locals (gs_step)


def _model_key(unit: Unit, var: str, outputs: bool) -> str:
    """The ``step`` mapping key of a connected variable: the variable itself, or the array
    port it labels (``beam.up`` → ``beam``: the model passes the 4 beams as one array)."""
    ports = type(unit).OUTPUTS if outputs else type(unit).INPUTS
    for p in ports:
        if p.name == var:
            return var
        if p.labels is not None and var.startswith(p.name + ".") \
                and var[len(p.name) + 1:] in p.labels:
            return p.name
    return var


def wiring(units: dict[str, Unit], connections: tuple[Connection, ...] = CONNECTIONS) -> Wires:
    """Per destination unit, its inputs as (key, source unit, source key), computed once from
    the connections (an array connected label by label becomes one wire)."""
    out: Wires = {name: [] for name in units}
    for c in connections:
        wire = (_model_key(units[c.dst_unit], c.dst_var, False), c.src_unit,
                _model_key(units[c.src_unit], c.src_var, True))
        if wire not in out[c.dst_unit]:
            out[c.dst_unit].append(wire)
    return out


def _run_step(unit: Any) -> Any:
    """What the run loop calls for ``unit``'s step: its ``run_step()``
    (:meth:`~.radar.unit.Unit.run_step`), or ``step`` itself for an object without one."""
    run_step = getattr(unit, "run_step", None)
    return unit.step if run_step is None else run_step()


def _step_args(unit: Any, keys: tuple[str, ...]) -> Any:
    """The positional step of ``unit`` (:meth:`~.radar.unit.Unit.run_step_args`) if it takes
    exactly ``keys`` in that order, else None (the run loop then passes the mapping)."""
    run_step_args = getattr(unit, "run_step_args", None)
    found = None if run_step_args is None else run_step_args()
    return found[0] if found is not None and tuple(found[1]) == keys else None


def _positional_keys(unit: Any, wires: list[tuple[str, str, str]]) -> tuple[str, ...] | None:
    """The keys of ``unit``'s positional step when its wires give each of them once and
    nothing else (then the run loop may call it positionally), else None."""
    run_step_args = getattr(unit, "run_step_args", None)
    found = None if run_step_args is None else run_step_args()
    keys = [key for key, _, _ in wires]
    if found is None or len(set(keys)) != len(keys) or set(keys) != set(found[1]):
        return None
    return tuple(found[1])


def gs_step(plan: list[tuple[str, Unit, list[tuple[str, str, str]]]],
            step_source: tuple[str, str] = STEP_SOURCE) -> tuple[Any, Any]:
    """The Gauss-Seidel pass of ``plan`` ((name, unit, wires) per unit, in order) as the
    functions ``(f(out, h, *units), run(loop, duration, out, *units))``: ``f`` steps each unit in
    turn by ``h`` with its inputs read from the latest outputs (``out``: unit name -> output
    mapping, updated in place); ``run`` repeats that pass while ``loop.t < duration``, each
    with the step ``h = float(out[step_source[0]][step_source[1]])``, advancing ``loop.t`` by
    ``h`` and ``loop.steps`` by 1 after each pass (what :meth:`DirectLoop.step` does; held in
    locals and stored with the outputs when the loop ends, by an exception too).

    They do what the plain loop ``inputs = {key: out[src][skey] for key, src, skey in wires};
    out[name] = unit.step(h, inputs)`` does, written out once per wiring as Python source —
    one dict display per unit, the outputs each unit reads held in locals (as ``dataclasses``
    writes out ``__init__``) — because the loop's own bytecode was ≈ 400 instructions per PRI
    (issue 14). Same mappings (keys in wire order), same order of calls; ``unit.step`` is
    looked up at each call of ``f`` (benchmarks wrap it); ``run`` takes each unit's
    :meth:`~.radar.unit.Unit.run_step` once when it starts (:func:`_run_step`: ``step`` itself,
    or for the Tracker its input mode's step, one frame fewer per pass; issue 14, round 10:
    ``h`` is a float there), so a ``step`` wrapped before the run is the one called. A unit
    whose wires give exactly its ``STEP_ARGS`` is called by ``run`` as ``f(h, None, *values)``
    when its :meth:`~.radar.unit.Unit.run_step_args` offers that call at the run's start
    (round 11: no input dict built or read; the same outputs and state), else with the
    mapping."""
    index = {name: k for k, (name, _, _) in enumerate(plan)}
    units = ", ".join(f"u{k}" for k in range(len(plan)))
    first: list[str] = []  # outputs read before their unit steps in a pass: loaded once
    body: list[str] = []
    run_body: list[str] = []  # the run loop's pass: each unit's run_step, taken at its start
    fresh: set[str] = set()  # units stepped earlier in this pass: their outputs in locals
    run_args: list[str] = []  # the positional steps taken at the run's start (round 11)
    for k, (name, unit, wires) in enumerate(plan):
        for src in dict.fromkeys(src for _, src, _ in wires):
            if src not in fresh and f"o{index[src]} = out[{src!r}]" not in first:
                first.append(f"o{index[src]} = out[{src!r}]")  # last step's outputs
        items = ", ".join(f"{key!r}: o{index[src]}[{skey!r}]" for key, src, skey in wires)
        body.append(f"out[{name!r}] = o{k} = u{k}.step(h, {{{items}}})")
        pos = _positional_keys(unit, wires)  # round 11: the values positionally when it can
        if pos is None:
            run_body.append(f"o{k} = s{k}(h, {{{items}}})")
        else:
            wired = {key: f"o{index[src]}[{skey!r}]" for key, src, skey in wires}
            run_body += [f"if a{k} is not None:",
                         f"    o{k} = a{k}(h, None, {', '.join(wired[key] for key in pos)})",
                         "else:", f"    o{k} = s{k}(h, {{{items}}})"]
            run_args.append(f"a{k} = _step_args(u{k}, {pos!r})")
        fresh.add(name)
    src_unit, src_key = step_source
    load_src = f"o{index[src_unit]} = out[{src_unit!r}]"
    run_first = first if load_src in first else [*first, load_src]
    # the run loop keeps the outputs, t and the step count in locals and stores them into
    # ``out`` and ``loop`` when it ends, normally or by an exception (issue 14, round 9: no
    # dict store or attribute update per pass): the same values as storing them as it goes
    loaded = {line.split(" = ")[0] for line in run_first}
    unset = [f"o{k} = _UNSET" for k in range(len(plan)) if f"o{k}" not in loaded]
    store = [f"if o{k} is not _UNSET: out[{name!r}] = o{k}" if f"o{k}" not in loaded
             else f"out[{name!r}] = o{k}" for k, (name, _, _) in enumerate(plan)]
    lines = [f"def _gs_step(out, h, {units}):", *(f"    {x}" for x in first + body),
             f"def _gs_run(loop, duration, out, {units}):",
             *(f"    {x}" for x in run_first + unset),
             *(f"    s{k} = _run_step(u{k})" for k in range(len(plan))),
             *(f"    {x}" for x in run_args),
             "    t = loop.t", "    steps = loop.steps", "    try:",
             "        while t < duration:",
             f"            h = float(o{index[src_unit]}[{src_key!r}])",
             *(f"            {x}" for x in run_body),
             "            t = t + h", "            steps += 1",
             "    finally:", *(f"        {x}" for x in store),
             "        loop.t = t", "        loop.steps = steps"]
    ns: dict[str, Any] = {"_UNSET": _UNSET, "_run_step": _run_step, "_step_args": _step_args}
    exec(compile("\n".join(lines), f"<gs_step of {', '.join(index)}>", "exec"), ns)
    return ns["_gs_step"], ns["_gs_run"]


@dataclass
class DirectLoop:
    """The four units wired per SYSTEM.md; :meth:`step` advances one manager PRI."""

    gen: TargetGenerator
    trk: Tracker
    ped: Pedestal
    mgr: RadarManager
    t: float = 0.0
    steps: int = 0
    out: dict[str, dict[str, Any]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.units: dict[str, Unit] = {TARGET_GENERATOR: self.gen, TRACKER: self.trk,
                                       PEDESTAL: self.ped, RADAR_MANAGER: self.mgr}
        wires = wiring(self.units)
        self._plan = [(name, self.units[name], wires[name]) for name in GAUSS_SEIDEL_ORDER]
        self._gs: tuple[Any, ...] = (None,)  # see _pass
        # Initial outputs: the units' outputs at their initial state (the FMUs' start values);
        # the Tracker computes none before its first step: its ports' start values.
        self.out = {
            PEDESTAL: self.ped.outputs(),
            RADAR_MANAGER: self.mgr.outputs(),
            TRACKER: {p.name: p.initial for p in Tracker.OUTPUTS},
        }

    @classmethod
    def from_params(cls, params: dict[str, dict[str, Any]] | None = None) -> DirectLoop:
        """Build the loop from per-unit parameter overrides (keys: unit names)."""
        p = params or {}
        return cls(
            gen=TargetGenerator(**p.get(TARGET_GENERATOR, {})),
            trk=Tracker(**p.get(TRACKER, {})),
            ped=Pedestal(**p.get(PEDESTAL, {})),
            mgr=RadarManager(**p.get(RADAR_MANAGER, {})),
        )

    def __getstate__(self) -> dict[str, Any]:
        """Pickled without the written-out pass (rewritten at the next step)."""
        return {**self.__dict__, "_gs": (None,)}

    def _pass(self) -> tuple[Any, ...]:
        """(plan, its written-out pass and run loop (:func:`gs_step`), its units), (re)written
        when the plan is new or was replaced."""
        gs = self._gs
        if gs[0] is not self._plan:
            plan = self._plan
            gs = self._gs = (plan, *gs_step(plan), tuple(unit for _, unit, _ in plan))
        return gs

    def step(self) -> float:
        """One macro step of the current PRI [s]; returns the step taken."""
        o = self.out
        h = float(o[STEP_SOURCE[0]][STEP_SOURCE[1]])
        gs = self._pass()
        gs[1](o, h, *gs[3])
        self.t += h
        self.steps += 1
        return h

    def run(self, duration: float, every: int = 0, record: list | None = None) -> None:
        """Step until ``duration`` [s]; every ``every`` steps append ``(t, out)`` copies of
        the scalar outputs to ``record`` (if given)."""
        if record is None or not every:  # the written-out loop: the passes of step, no call
            gs = self._pass()
            gs[2](self, duration, self.out, *gs[3])
            return
        while self.t < duration:
            self.step()
            if record is not None and every and self.steps % every == 0:
                record.append((self.t, {u: {k: v for k, v in d.items() if not hasattr(v, "shape")}
                                        for u, d in self.out.items()}))
