"""A validated run definition (:class:`Scenario`), whatever file it was read from (TOML
scenario, :mod:`.scenario`; SSP archive, :mod:`.ssp.importer`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from axir.models.system import Connection

from .config import DEFAULT_INITIAL_STEP, DEFAULT_STEP_FROM
from .errors import AxirError
from .system import SystemDescription, UnitSpec

#: the variables recorded when a scenario names none (those of its units)
DEFAULT_RECORD = (
    "TargetGenerator.truth.x", "TargetGenerator.truth.y", "TargetGenerator.truth.z",
    "TargetGenerator.truth.range", "TargetGenerator.truth.az", "TargetGenerator.truth.el",
    "TargetGenerator.truth.range_rate",
    "Tracker.track.x", "Tracker.track.y", "Tracker.track.z",
    "Tracker.track.range", "Tracker.track.az", "Tracker.track.el",
    "Tracker.dev.az", "Tracker.dev.el", "Tracker.dev.range",
    "Tracker.cmd.az", "Tracker.cmd.el", "Tracker.gate.start",
    "RadarManager.mode", "RadarManager.pri", "RadarManager.bandwidth",
    "Pedestal.az", "Pedestal.el",
)


@dataclass
class Scenario:
    """A validated scenario: units, their parameters and connections, the master's settings
    (algorithm, order, step), what to record, seed and duration."""

    name: str
    source: str
    description: str = ""
    duration: float = 10.0
    seed: int = 1
    algorithm: str = "gauss-seidel"
    order: list[str] = field(default_factory=list)
    step: float | None = None  # None = variable step from `step_from`
    step_from: str = DEFAULT_STEP_FROM
    initial_step: float = DEFAULT_INITIAL_STEP
    decimation: int = 1
    record: list[str] = field(default_factory=list)
    units: dict[str, dict[str, Any]] = field(default_factory=dict)  # name -> {fmu, parameters}
    connections: list[Connection] = field(default_factory=list)

    def with_overrides(self, seed: int | None = None,
                       duration: float | None = None) -> Scenario:
        """A copy with the command line's ``--seed`` / ``--duration`` [s] applied (None: keep);
        :class:`AxirError` naming the option for an invalid value."""
        sc = self
        if seed is not None:
            if int(seed) < 0:
                raise AxirError(f"--seed must be a non-negative integer, got {seed}")
            sc = replace(sc, seed=int(seed))
        if duration is not None:
            if not (duration > 0 and math.isfinite(duration)):
                raise AxirError("--duration must be a positive, finite number of seconds, "
                                f"got {duration}")
            sc = replace(sc, duration=float(duration))
        return sc

    def system(self, fmu_dir: Path) -> SystemDescription:
        """The system description, FMU paths resolved against ``fmu_dir``, seeds applied."""
        units = {}
        for name, spec in self.units.items():
            params = dict(spec.get("parameters", {}))
            units[name] = UnitSpec(name, Path(fmu_dir) / spec.get("fmu", f"{name}.fmu"), params)
        return SystemDescription(units, list(self.connections))
