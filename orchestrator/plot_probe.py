"""What the plots need beyond ``results.csv`` (recorded only with ``--plot``, in memory, so
results.csv keeps its columns and bytes): a second :class:`~.record.Recorder` over the
variables of :data:`PLOT_EXTRA` that the FMUs have, and :class:`LockSnapshot`, the
range-Doppler picture (the Tracker's SUM over 16 range bins × 3 Doppler filters) at the
first confirmed step.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .master import NS, Master
from .record import Recorder

#: recorded for the plots: the range variance the filter reports (its 1σ band), the Doppler
#: centre the manager commands and the target's true (unfolded) Doppler
PLOT_EXTRA = ("Tracker.track.P_rr", "RadarManager.doppler.centre",
              "TargetGenerator.truth.doppler")
#: range bins and Doppler filters of the SUM map (SYSTEM.md: sum[r,f], r = 1..16, f = 1..3)
BINS, FILTERS = 16, 3
#: scalars read with the snapshot: (unit, variable, key); the gate, Doppler centre and PRI
#: are the TargetGenerator's inputs (the values that shaped this SUM), the range offset the
#: Tracker's input (true range = apparent + offset)
_SCALARS = (("TargetGenerator", "gate.start", "gate_start_m"),
            ("Tracker", "range.offset", "range_offset_m"),
            ("TargetGenerator", "doppler.centre", "doppler_centre_hz"),
            ("TargetGenerator", "pri", "pri_s"),
            ("TargetGenerator", "truth.range", "truth_range_m"),
            ("TargetGenerator", "truth.doppler", "truth_doppler_hz"),
            ("TargetGenerator", "doppler_spacing", "doppler_spacing_hz"))


def extra_recorder(master: Master, decimation: int) -> Recorder:
    """A recorder of the :data:`PLOT_EXTRA` variables present in the loaded FMUs."""
    have = [ref for ref in PLOT_EXTRA
            if ref.partition(".")[0] in master.instances
            and ref.partition(".")[2] in master.instances[ref.partition(".")[0]].variables]
    return Recorder(have, decimation)


@dataclass
class Snapshot:
    """The SUM map at lock: ``sum[r, f]`` (16 × 3 magnitudes), time [s] and scalars."""

    t: float
    sum: np.ndarray
    values: dict[str, float]


class LockSnapshot:
    """Observer: at the first step in confirmed mode (RadarManager.mode = 2), read the
    Tracker's 48 SUM outputs and the scalars of :data:`_SCALARS` that exist; also reads the
    TargetGenerator's ``beamwidth`` [rad] at the start. Does nothing without a Tracker and a
    RadarManager."""

    def __init__(self) -> None:
        self.snapshot: Snapshot | None = None
        self.beamwidth: float | None = None
        self._mode: Any = None
        self._sum: Any = None
        self._scalars: list[tuple[str, Any]] = []

    def start(self, master: Master) -> None:
        inst = master.instances
        tg = inst.get("TargetGenerator")
        if tg is not None and "beamwidth" in tg.variables:
            self.beamwidth = float(tg.port(["beamwidth"]).read()[0])
        if "Tracker" not in inst or "RadarManager" not in inst \
                or "sum[1,1]" not in inst["Tracker"].variables:
            return
        self._mode = inst["RadarManager"].port(["mode"])
        self._sum = inst["Tracker"].port([f"sum[{r},{f}]" for r in range(1, BINS + 1)
                                          for f in range(1, FILTERS + 1)])
        self._scalars = [(key, inst[u].port([v])) for u, v, key in _SCALARS
                         if u in inst and v in inst[u].variables]

    def step(self, master: Master, t_ns: int) -> None:
        if self._mode is None or self.snapshot is not None:
            return
        if int(self._mode.read()[0]) == 2:
            values = {key: float(port.read()[0]) for key, port in self._scalars}
            self.snapshot = Snapshot(t_ns / NS, np.array(self._sum.read()).reshape(BINS, FILTERS),
                                     values)
            self._mode = None

    def finish(self, master: Master, complete: bool) -> None:
        """Nothing to finish."""
