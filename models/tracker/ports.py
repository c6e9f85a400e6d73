"""Inputs and outputs of the Tracker, each declared once (SYSTEM.md public names).

:class:`~axir.models.tracker.Tracker` lists them as ``INPUTS``/``OUTPUTS``; the FMU derives
its variables from them; :class:`~.outputs.TrackerOutputs` fills the outputs in this order.
"""

from __future__ import annotations

from ..radar.conventions import BEAMS, N_BEAMS, N_BINS, N_DOPPLER
from ..radar.ports import Port

#: Input domains (out of domain: the last valid value is held). Beams: noise-normalised
#: magnitudes ≥ 0, ≤ BEAM_MAX = 1e30 (any valid TargetGenerator parameters); angles ±1e6 rad
#: (continuous pedestal angles may wind up); ranges ±1e7 m (10 000 km); α ∈ [0, 2] and
#: β ∈ [0, 4] (the α-β stability triangle 0 < α < 2, 0 < β < 4 − 2α lies inside; 0: evolutive
#: gains); speeds ±1e5 m/s; meas.valid / meas.new are flags in [0, 1]; mode one of 0, 1, 2.
BEAM_MAX = 1.0e30
ANGLE_MAX = 1.0e6  # [rad]
RANGE_MAX = 1.0e7  # [m]
SPEED_MAX = 1.0e5  # [m/s] (100 km/s, as the RadarManager's track.range_rate)

#: Public inputs of ``step``.
INPUTS: tuple[Port, ...] = (
    Port("beam", float, "1", "beam magnitude (Doppler filter output) per range bin r and filter f",
        shape=(N_BEAMS, N_BINS, N_DOPPLER), labels=BEAMS, low=0.0, high=BEAM_MAX),
    Port("ped.az", float, "rad", "pedestal azimuth (decoded potentiometers)",
        low=-ANGLE_MAX, high=ANGLE_MAX),
    Port("ped.el", float, "rad", "pedestal elevation (decoded potentiometers)",
        low=-ANGLE_MAX, high=ANGLE_MAX),
    Port("mode", int, "1", "radar mode: 0 acquisition, 1 tentative, 2 confirmed",
        low=0, high=2),
    Port("alpha", float, "1", "steady alpha gain from the manager (0: evolutive gains only)",
        low=0.0, high=2.0),
    Port("beta", float, "1", "steady beta gain from the manager (0: evolutive gains only)",
        low=0.0, high=4.0),
    Port("range.offset", float, "m", "range ambiguity offset: true range = apparent + offset",
        low=-RANGE_MAX, high=RANGE_MAX),
    Port("gate.command", float, "m", "gate start (range of bin 1) commanded by the manager",
        low=-RANGE_MAX, high=RANGE_MAX),
    Port("doppler.range_rate", float, "m/s",
        "radial speed of the manager's unfolded track Doppler (RadarManager "
        "doppler.range_rate; used while doppler.resolved, doppler_rate_tol > 0)",
        low=-SPEED_MAX, high=SPEED_MAX),
    Port("doppler.resolved", bool, "1",
        "the manager tracks an unfolded Doppler (RadarManager doppler.resolved; false: "
        "doppler.range_rate unused)"),
    Port("meas.range", float, "m", "measured range (input_mode = measurement)",
        low=-RANGE_MAX, high=RANGE_MAX),
    Port("meas.az", float, "rad", "measured azimuth (input_mode = measurement)",
        low=-ANGLE_MAX, high=ANGLE_MAX),
    Port("meas.el", float, "rad", "measured elevation (input_mode = measurement)",
        low=-ANGLE_MAX, high=ANGLE_MAX),
    Port("meas.valid", float, "1", "1 once a measurement exists (input_mode = measurement)",
        low=0.0, high=1.0),
    Port("meas.new", float, "1", "1 in the step that brings a new measurement (input_mode = "
        "measurement)", low=0.0, high=1.0),
)
#: Public outputs of ``step``.
OUTPUTS: tuple[Port, ...] = (
    Port("sum", float, "1", "SUM = B1+B2+B3+B4 per range bin and Doppler filter (seed 000 eq. 1)",
        shape=(N_BINS, N_DOPPLER)),
    Port("dev.az", float, "rad", "azimuth deviation dLat/cos(El) (> 0: target east of boresight)"),
    Port("dev.el", float, "rad", "elevation deviation (> 0: target above boresight)"),
    Port("dev.lat", float, "rad", "lateral deviation before division by cos(El)"),
    Port("dev.range", float, "m", "range deviation (> 0: target beyond the gate centre)"),
    Port("track.x", float, "m", "filtered East position"),
    Port("track.y", float, "m", "filtered North position"),
    Port("track.z", float, "m", "filtered Up position"),
    Port("track.vx", float, "m/s", "filtered East velocity"),
    Port("track.vy", float, "m/s", "filtered North velocity"),
    Port("track.vz", float, "m/s", "filtered Up velocity"),
    Port("track.range", float, "m", "filtered range"),
    Port("track.range_rate", float, "m/s", "filtered range rate"),
    Port("track.az", float, "rad", "filtered azimuth"),
    Port("track.el", float, "rad", "filtered elevation"),
    Port("cmd.az", float, "V", "pedestal azimuth rate command"),
    Port("cmd.el", float, "V", "pedestal elevation rate command"),
    Port("gate.start", float, "m", "gate start (range of the bin-1 sample) for the next PRI"),
    Port("maneuver", bool, "1", "maneuver detected (fading-memory NIS test)"),
    Port("maneuver.statistic", float, "1", "fading-memory NIS statistic"),
    Port("maneuver.threshold", float, "1", "threshold of the maneuver test"),
    Port("track.n", int, "1", "number of measurements in the track"),
    Port("track.valid", bool, "1", "a track exists"),
    Port("coasting", bool, "1", "no usable measurement this step (prediction only)"),
    Port("innovation.x", float, "m", "East innovation of the last update"),
    Port("innovation.y", float, "m", "North innovation of the last update"),
    Port("innovation.z", float, "m", "Up innovation of the last update"),
    Port("ddre.range", float, "m", "DDRE measured range (seed 001 eq. 7; 0 when disabled)"),
    Port("ddre.smoothed", float, "m", "DDRE smoothed range (seed 001 eq. 8)"),
    Port("ddre.predicted", float, "m", "DDRE predicted gate range (seed 001 eq. 11)"),
    Port("ddre.valid", bool, "1", "DDRE estimate valid"),
    Port("track.range_acc", float, "m/s2", "range acceleration estimate (beams mode: Cartesian "
        "estimate on the line of sight; 0 for filters without an acceleration estimate)"),
    Port("track.acc.x", float, "m/s2", "filtered East acceleration (0 without an estimate)"),
    Port("track.acc.y", float, "m/s2", "filtered North acceleration (0 without an estimate)"),
    Port("track.acc.z", float, "m/s2", "filtered Up acceleration (0 without an estimate)"),
    Port("track.P_rr", float, "m2", "range variance (measurement mode: range filter; beams mode: "
        "Cartesian covariance projected on the line of sight)"),
    Port("track.P_rv", float, "m2/s", "range / range-rate covariance (as track.P_rr)"),
    Port("track.P_vv", float, "m2/s2", "range-rate variance (as track.P_rr)"),
)
