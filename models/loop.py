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

    def step(self) -> float:
        """One macro step of the current PRI [s]; returns the step taken."""
        o = self.out
        h = float(o[STEP_SOURCE[0]][STEP_SOURCE[1]])
        for name, unit, wires in self._plan:
            inputs = {}  # a plain loop: no comprehension frame per unit and PRI (issue 14)
            for key, src, skey in wires:
                inputs[key] = o[src][skey]
            o[name] = unit.step(h, inputs)
        self.t += h
        self.steps += 1
        return h

    def run(self, duration: float, every: int = 0, record: list | None = None) -> None:
        """Step until ``duration`` [s]; every ``every`` steps append ``(t, out)`` copies of
        the scalar outputs to ``record`` (if given)."""
        while self.t < duration:
            self.step()
            if record is not None and every and self.steps % every == 0:
                record.append((self.t, {u: {k: v for k, v in d.items() if not hasattr(v, "shape")}
                                        for u, d in self.out.items()}))
