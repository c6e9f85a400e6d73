"""The closed tracking loop of SYSTEM.md with the four models in a plain Python loop.

Same connections as the FMU system (``axir.orchestrator.system.radar_connections``) and the
same Gauss-Seidel order as the master's default (Pedestal → TargetGenerator → Tracker →
RadarManager; each unit takes the latest outputs of the units before it). The step is the PRI
the manager outputs. Used by the models-only end-to-end tests and as the reference ("direct
loop") of the FMU-loop benchmark. No FMI anywhere.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .manager import RadarManager
from .pedestal import Pedestal
from .target_generator import TargetGenerator
from .tracker import Tracker

ORDER = ("Pedestal", "TargetGenerator", "Tracker", "RadarManager")


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
        # Initial outputs: the units' outputs at their initial state (the FMUs' start values).
        self.out = {
            "Pedestal": self.ped.outputs(),
            "RadarManager": self.mgr.outputs(),
            "Tracker": {"cmd.az": 0.0, "cmd.el": 0.0, "gate.start": 0.0, "sum": None,
                        "track.range": 0.0, "track.range_rate": 0.0, "maneuver": False},
        }

    @classmethod
    def from_params(cls, params: dict[str, dict[str, Any]] | None = None) -> DirectLoop:
        """Build the loop from per-unit parameter overrides (keys: unit names)."""
        p = params or {}
        return cls(
            gen=TargetGenerator(**p.get("TargetGenerator", {})),
            trk=Tracker(**p.get("Tracker", {})),
            ped=Pedestal(**p.get("Pedestal", {})),
            mgr=RadarManager(**p.get("RadarManager", {})),
        )

    def step(self) -> float:
        """One macro step of the current PRI [s]; returns the step taken."""
        o = self.out
        m, tr = o["RadarManager"], o["Tracker"]
        h = float(m["pri"])
        ped = self.ped.step(h, {"cmd.az": tr["cmd.az"], "cmd.el": tr["cmd.el"],
                                "bandwidth": m["bandwidth"]})
        gen = self.gen.step(h, {"antenna.az": ped["az"], "antenna.el": ped["el"],
                                "gate.start": tr["gate.start"],
                                "doppler.centre": m["doppler.centre"], "pri": m["pri"]})
        trk = self.trk.step(h, {"beam": gen["beam"], "ped.az": ped["az"], "ped.el": ped["el"],
                                "mode": m["mode"], "alpha": m["alpha"], "beta": m["beta"],
                                "range.offset": m["range.offset"],
                                "gate.command": m["gate.command"]})
        mgr = self.mgr.step(h, {"sum": trk["sum"], "gate.start": trk["gate.start"],
                                "track.range": trk["track.range"],
                                "track.range_rate": trk["track.range_rate"],
                                "maneuver": trk["maneuver"]})
        o["Pedestal"], o["TargetGenerator"], o["Tracker"], o["RadarManager"] = ped, gen, trk, mgr
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
