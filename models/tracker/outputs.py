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


#: the output names in the order of :data:`~.ports.OUTPUTS` (the mapping's key order):
#: :func:`outputs_flat` fills a copy of this template (issue 14, round 2)
_TEMPLATE: dict[str, Any] = dict.fromkeys((
    "sum", "dev.az", "dev.el", "dev.lat", "dev.range", "track.x", "track.y", "track.z", "track.vx",
    "track.vy", "track.vz", "track.range", "track.range_rate", "track.az", "track.el", "cmd.az",
    "cmd.el", "gate.start", "maneuver", "maneuver.statistic", "maneuver.threshold", "track.n",
    "track.valid", "coasting", "innovation.x", "innovation.y", "innovation.z", "ddre.range",
    "ddre.smoothed", "ddre.predicted", "ddre.valid", "track.range_acc", "track.acc.x",
    "track.acc.y", "track.acc.z", "track.P_rr", "track.P_rv", "track.P_vv",
), 0.0)
#: the template with the values the α-β axes without DDRE give every step (track.acc.* 0.0,
#: ddre.* NO_DDRE): the copy BeamTracker.step fills then (issue 14, round 10; here: round 11)
TEMPLATE_ND: dict[str, Any] = {**_TEMPLATE, "track.acc.x": 0.0, "track.acc.y": 0.0,
                               "track.acc.z": 0.0, **dict(zip(
                                   ("ddre.range", "ddre.smoothed", "ddre.predicted",
                                    "ddre.valid"), NO_DDRE, strict=True))}


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
    return outputs_flat(
        sums, dev_az, dev_el, dev_lat, dev_range, pos[0], pos[1], pos[2], vel[0], vel[1],
        vel[2], rng, range_rate, az, el, cmd_az, cmd_el, gate_start, maneuver, statistic,
        threshold, n, valid, coasting, nu[0], nu[1], nu[2], ddre, range_acc, acc[0], acc[1],
        acc[2], P[0], P[1], P[2])


def outputs_flat(
    sums: np.ndarray, dev_az: float, dev_el: float, dev_lat: float, dev_range: float,
    x: float, y: float, z: float, vx: float, vy: float, vz: float, rng: float,
    range_rate: float, az: float, el: float, cmd_az: float, cmd_el: float, gate_start: float,
    maneuver: bool, statistic: float, threshold: float, n: int, valid: bool, coasting: bool,
    nu_x: float, nu_y: float, nu_z: float, ddre: tuple[float, float, float, bool],
    range_acc: float, acc_x: float, acc_y: float, acc_z: float, p_rr: float, p_rv: float,
    p_vv: float,
) -> dict[str, Any]:
    """:func:`outputs_dict` with the vectors as their components (units as in
    :class:`TrackerOutputs`): the beams tracker's tracking path calls it with the scalars it
    has, without building and indexing six 3-tuples per PRI (issue 14, round 2)."""
    # a copy of the 38-key template filled in place costs about half of building the
    # same dict from a literal (≈ 0.9 vs ≈ 2 µs): same keys, same order, same values
    d = _TEMPLATE.copy()
    d["sum"] = sums
    d["dev.az"] = dev_az
    d["dev.el"] = dev_el
    d["dev.lat"] = dev_lat
    d["dev.range"] = dev_range
    d["track.x"] = x
    d["track.y"] = y
    d["track.z"] = z
    d["track.vx"] = vx
    d["track.vy"] = vy
    d["track.vz"] = vz
    d["track.range"] = rng
    d["track.range_rate"] = range_rate
    d["track.az"] = az
    d["track.el"] = el
    d["cmd.az"] = cmd_az
    d["cmd.el"] = cmd_el
    d["gate.start"] = gate_start
    d["maneuver"] = maneuver
    d["maneuver.statistic"] = statistic
    d["maneuver.threshold"] = threshold
    d["track.n"] = n
    d["track.valid"] = valid
    d["coasting"] = coasting
    d["innovation.x"] = nu_x
    d["innovation.y"] = nu_y
    d["innovation.z"] = nu_z
    d["ddre.range"] = ddre[0]
    d["ddre.smoothed"] = ddre[1]
    d["ddre.predicted"] = ddre[2]
    d["ddre.valid"] = ddre[3]
    d["track.range_acc"] = range_acc
    d["track.acc.x"] = acc_x
    d["track.acc.y"] = acc_y
    d["track.acc.z"] = acc_z
    d["track.P_rr"] = p_rr
    d["track.P_rv"] = p_rv
    d["track.P_vv"] = p_vv
    return d
