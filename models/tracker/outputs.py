"""The Tracker's outputs of one step as a record, turned into the ``step`` mapping.

Every field defaults to "nothing to report" (0, false, zero vectors), so each input mode fills
only what it computes, by keyword. :meth:`TrackerOutputs.as_dict` gives the public names of
:data:`~.ports.OUTPUTS`, in their order.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..radar.conventions import BIN_M, GATE_BIN

Vec3 = tuple[float, float, float]
ZERO3: Vec3 = (0.0, 0.0, 0.0)

#: gate-centre offset: bin 7 samples gate_start + 6·75 m (radar.conventions) [m]
GATE_CENTRE_M = (GATE_BIN - 1) * BIN_M
#: clamp of cos(El) in dAz = dLat/cos(El) and in the azimuth noise scale near the zenith
MIN_COS_EL = 1e-3
#: DDRE outputs while disabled or before its first estimate: range, smoothed, predicted, valid
NO_DDRE: tuple[float, float, float, bool] = (0.0, 0.0, 0.0, False)


@dataclass(slots=True)  # not frozen: a frozen init costs ≈ 3 µs per step (issue 14)
class TrackerOutputs:
    """One step's outputs (units as in :data:`~.ports.OUTPUTS`).

    Attributes:
        sum: SUM per range bin and Doppler filter, shape (16, 3) [1].
        dev_az, dev_el, dev_lat [rad], dev_range [m]: deviations.
        pos [m], vel [m/s], acc [m/s²]: filtered ENU position, velocity, acceleration.
        range [m], range_rate [m/s], range_acc [m/s²], az, el [rad]: filtered spherical track.
        P: (P_rr [m²], P_rv [m²/s], P_vv [m²/s²]) range-axis covariance.
        cmd_az, cmd_el: pedestal rate commands [V].
        gate_start: gate start for the next PRI [m].
        maneuver, maneuver_statistic, maneuver_threshold: maneuver test (flag, statistic,
            threshold [1]).
        n: measurements in the track; valid: a track exists; coasting: prediction only.
        innovation: innovation of the last update (ENU) [m].
        ddre: (range, smoothed, predicted [m], valid) of the DDRE.
    """

    sum: np.ndarray
    dev_az: float = 0.0
    dev_el: float = 0.0
    dev_lat: float = 0.0
    dev_range: float = 0.0
    pos: Vec3 = ZERO3
    vel: Vec3 = ZERO3
    range: float = 0.0
    range_rate: float = 0.0
    az: float = 0.0
    el: float = 0.0
    cmd_az: float = 0.0
    cmd_el: float = 0.0
    gate_start: float = 0.0
    maneuver: bool = False
    maneuver_statistic: float = 0.0
    maneuver_threshold: float = 0.0
    n: int = 0
    valid: bool = False
    coasting: bool = False
    innovation: Vec3 = ZERO3
    ddre: tuple[float, float, float, bool] = NO_DDRE
    range_acc: float = 0.0
    acc: Vec3 = ZERO3
    P: Vec3 = ZERO3

    def as_dict(self) -> dict[str, Any]:
        """The ``step`` mapping keyed by the public output names."""
        return outputs_dict(
            self.sum, self.dev_az, self.dev_el, self.dev_lat, self.dev_range, self.pos,
            self.vel, self.range, self.range_rate, self.az, self.el, self.cmd_az, self.cmd_el,
            self.gate_start, self.maneuver, self.maneuver_statistic, self.maneuver_threshold,
            self.n, self.valid, self.coasting, self.innovation, self.ddre, self.range_acc,
            self.acc, self.P)


def outputs_dict(
    sums: np.ndarray, dev_az: float, dev_el: float, dev_lat: float, dev_range: float,
    pos: Vec3, vel: Vec3, rng: float, range_rate: float, az: float, el: float,
    cmd_az: float, cmd_el: float, gate_start: float, maneuver: bool, statistic: float,
    threshold: float, n: int, valid: bool, coasting: bool, nu: Vec3,
    ddre: tuple[float, float, float, bool], range_acc: float = 0.0, acc: Vec3 = ZERO3,
    P: Vec3 = ZERO3,
) -> dict[str, Any]:
    """The ``step`` mapping keyed by the public output names, from the fields of
    :class:`TrackerOutputs` in their order (positional: the beams tracker's per-PRI path
    builds it without the record, issue 14)."""
    return {
        "sum": sums,
        "dev.az": dev_az,
        "dev.el": dev_el,
        "dev.lat": dev_lat,
        "dev.range": dev_range,
        "track.x": pos[0],
        "track.y": pos[1],
        "track.z": pos[2],
        "track.vx": vel[0],
        "track.vy": vel[1],
        "track.vz": vel[2],
        "track.range": rng,
        "track.range_rate": range_rate,
        "track.az": az,
        "track.el": el,
        "cmd.az": cmd_az,
        "cmd.el": cmd_el,
        "gate.start": gate_start,
        "maneuver": maneuver,
        "maneuver.statistic": statistic,
        "maneuver.threshold": threshold,
        "track.n": n,
        "track.valid": valid,
        "coasting": coasting,
        "innovation.x": nu[0],
        "innovation.y": nu[1],
        "innovation.z": nu[2],
        "ddre.range": ddre[0],
        "ddre.smoothed": ddre[1],
        "ddre.predicted": ddre[2],
        "ddre.valid": ddre[3],
        "track.range_acc": range_acc,
        "track.acc.x": acc[0],
        "track.acc.y": acc[1],
        "track.acc.z": acc[2],
        "track.P_rr": P[0],
        "track.P_rv": P[1],
        "track.P_vv": P[2],
    }
