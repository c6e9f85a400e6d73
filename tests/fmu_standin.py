"""A Tracker-sized stand-in unit and its FMU declaration/slave, for the adapter tests
(tests/test_fmu_spec.py, test_fmu_model_description.py, test_fmu_slave.py)."""

from __future__ import annotations

from typing import Any

import numpy as np

from axir.fmus.slave import AxirSlave
from axir.fmus.spec import FmuSpec
from axir.models.radar.params import Param
from axir.models.radar.ports import Port
from axir.models.radar.unit import Unit

BEAMS = ("up", "right", "down", "left")


class StandIn(Unit):
    """Tiny stand-in model with Tracker-like arrays: sum = Σ beams · gain, plus a counter."""

    PARAMS = (
        Param("gain", 1.0, "1", "output gain", low=0.0, high=10.0),
        Param("n_max", 5, "1", "counter limit", low=1, high=100),
        Param("flag", False, "", "a Boolean parameter"),
    )

    INPUTS = (Port("beam", float, "1", "beam magnitudes", shape=(4, 16, 3), labels=BEAMS),
              Port("ped.az", float, "rad", "pedestal azimuth"))
    OUTPUTS = (Port("sum", float, "1", "beam sum", shape=(16, 3)),
               Port("dev.az", float, "rad", "azimuth deviation"),
               Port("count", int, "1", "steps"),
               Port("maneuver", bool, "1", "flag"))

    def reset(self) -> None:
        self.count = 0

    def step(self, dt: float, inputs: dict[str, Any]) -> dict[str, Any]:
        self.count = min(self.count + 1, self.n_max)
        s = self.gain * np.asarray(inputs["beam"]).sum(axis=0)
        return {"sum": s, "dev.az": float(inputs["ped.az"]) * 2.0, "count": self.count,
                "maneuver": bool(self.flag)}


SPEC = FmuSpec(
    name="StandIn",
    model=StandIn,
    tunable=frozenset({"gain"}),
)


class StandInSlave(AxirSlave):
    SPEC = SPEC
