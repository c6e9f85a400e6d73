"""The radar system's facts, in one place: its four units, their connections, the
Gauss-Seidel order, the step source, the parameters a Jacobi master needs, per-unit seeding
and the initial PRI (SYSTEM.md, "Units" and "Typical connections").

Pure Python: the direct loop (:mod:`.loop`), the FMU master, the SSP exporter, the cross-check
and interface-doc tools and the benchmarks all read these facts from here.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass

import numpy as np

from .radar.conventions import BEAMS, BIN_S

TARGET_GENERATOR = "TargetGenerator"
TRACKER = "Tracker"
PEDESTAL = "Pedestal"
RADAR_MANAGER = "RadarManager"
#: the four units in the order of SYSTEM.md's table (one FMU each, ``<name>.fmu``)
UNITS: tuple[str, ...] = (TARGET_GENERATOR, TRACKER, PEDESTAL, RADAR_MANAGER)
#: Gauss-Seidel order of the closed loop: each unit takes the latest outputs of the units
#: before it (the pedestal moves, the generator forms the beams where it points, the tracker
#: measures them, the manager decides)
GAUSS_SEIDEL_ORDER: tuple[str, ...] = (PEDESTAL, TARGET_GENERATOR, TRACKER, RADAR_MANAGER)
#: the output whose value is the next communication step [s]: the PRI the manager commands
STEP_SOURCE = (RADAR_MANAGER, "pri")
#: parameter values that depend on the master's algorithm: with a Jacobi master the beams a
#: Tracker receives were formed with the gate it output two steps earlier (models/tracker.py)
JACOBI_PARAMETERS: dict[str, dict[str, object]] = {TRACKER: {"gate_latency": 2}}


@dataclass(frozen=True)
class Connection:
    """``src_unit.src_var`` (an output) drives ``dst_unit.dst_var`` (an input); an array
    variable is named by its prefix (``beam.up`` for ``beam.up[r,f]``)."""

    src_unit: str
    src_var: str
    dst_unit: str
    dst_var: str

    def __str__(self) -> str:
        return f"{self.src_unit}.{self.src_var} -> {self.dst_unit}.{self.dst_var}"


def _connections() -> tuple[Connection, ...]:
    tg, tr, pe, rm = TARGET_GENERATOR, TRACKER, PEDESTAL, RADAR_MANAGER
    c = Connection
    conns = [c(tg, f"beam.{b}", tr, f"beam.{b}") for b in BEAMS]
    conns += [
        c(pe, "az", tr, "ped.az"),
        c(pe, "el", tr, "ped.el"),
        c(pe, "az", tg, "antenna.az"),
        c(pe, "el", tg, "antenna.el"),
        c(tr, "cmd.az", pe, "cmd.az"),
        c(tr, "cmd.el", pe, "cmd.el"),
        c(tr, "sum", rm, "sum"),
        c(tr, "gate.start", tg, "gate.start"),
        c(tr, "gate.start", rm, "gate.start"),
        c(tr, "track.range", rm, "track.range"),
        c(tr, "track.range_rate", rm, "track.range_rate"),
        c(tr, "maneuver", rm, "maneuver"),
        c(rm, "mode", tr, "mode"),
        c(rm, "alpha", tr, "alpha"),
        c(rm, "beta", tr, "beta"),
        c(rm, "range.offset", tr, "range.offset"),
        c(rm, "gate.command", tr, "gate.command"),
        c(rm, "doppler.range_rate", tr, "doppler.range_rate"),
        c(rm, "doppler.resolved", tr, "doppler.resolved"),
        c(rm, "bandwidth", pe, "bandwidth"),
        c(rm, "pri", tg, "pri"),
        c(rm, "doppler.centre", tg, "doppler.centre"),
    ]
    return tuple(conns)


#: the closed tracking loop of SYSTEM.md ("Typical connections"), arrays by prefix
CONNECTIONS: tuple[Connection, ...] = _connections()


def unit_seed(base: int, unit: str) -> int:
    """Stable per-unit seed from the base seed (independent streams per unit): numpy's
    ``SeedSequence(base, spawn_key=(crc32(unit),))``, first 31 bits."""
    ss = np.random.SeedSequence(int(base), spawn_key=(zlib.crc32(unit.encode()),))
    return int(ss.generate_state(1)[0] & 0x7FFFFFFF)


def initial_pri() -> float:
    """The PRI [s] the manager outputs at its initial state with default parameters: the
    acquisition PRI, ``pri<acq_pri_index>_bins`` range-bin durations of ``BIN_S`` each."""
    from .manager import RadarManager  # here: the system's names need no model loaded

    defaults = {p.name: p.default for p in RadarManager.PARAMS}
    return defaults[f"pri{defaults['acq_pri_index']}_bins"] * BIN_S


__all__ = [
    "CONNECTIONS", "GAUSS_SEIDEL_ORDER", "JACOBI_PARAMETERS", "PEDESTAL", "RADAR_MANAGER",
    "STEP_SOURCE", "TARGET_GENERATOR", "TRACKER", "UNITS", "Connection", "initial_pri",
    "unit_seed",
]
