"""Tracker.fmu declaration: the AXIR_B digital tracker (:mod:`axir.models.tracker`).

Everything else (FMI variables, modelDescription, slave, bundle) is derived by
:mod:`axir.fmus._base` and :mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.radar import BEAMS, N_BINS, N_DOPPLER
from ..models.tracker import Tracker
from ._base import FmuSpec, Var

_R = "Real"
INPUTS = (
    Var("beam", _R, "1", "beam magnitude (Doppler filter output) per range bin r and filter f",
        shape=(4, N_BINS, N_DOPPLER), labels=BEAMS),
    Var("ped.az", _R, "rad", "pedestal azimuth (decoded potentiometers)"),
    Var("ped.el", _R, "rad", "pedestal elevation (decoded potentiometers)"),
    Var("mode", "Integer", description="radar mode: 0 acquisition, 1 tentative, 2 confirmed",
        start=0),
    Var("alpha", _R, "1", "steady alpha gain from the manager (0: evolutive gains only)"),
    Var("beta", _R, "1", "steady beta gain from the manager (0: evolutive gains only)"),
    Var("range.offset", _R, "m", "range ambiguity offset: true range = apparent + offset"),
    Var("gate.command", _R, "m", "gate start (range of bin 1) commanded by the manager"),
    Var("meas.range", _R, "m", "measured range (input_mode = measurement)"),
    Var("meas.az", _R, "rad", "measured azimuth (input_mode = measurement)"),
    Var("meas.el", _R, "rad", "measured elevation (input_mode = measurement)"),
    Var("meas.valid", _R, "1", "1 once a measurement exists (input_mode = measurement)"),
    Var("meas.new", _R, "1", "1 in the step that brings a new measurement (input_mode = "
        "measurement)"),
)
OUTPUTS = (
    Var("sum", _R, "1", "SUM = B1+B2+B3+B4 per range bin and Doppler filter (seed 000 eq. 1)",
        shape=(N_BINS, N_DOPPLER)),
    Var("dev.az", _R, "rad", "azimuth deviation dLat/cos(El) (> 0: target east of boresight)"),
    Var("dev.el", _R, "rad", "elevation deviation (> 0: target above boresight)"),
    Var("dev.lat", _R, "rad", "lateral deviation before division by cos(El)"),
    Var("dev.range", _R, "m", "range deviation (> 0: target beyond the gate centre)"),
    Var("track.x", _R, "m", "filtered East position"),
    Var("track.y", _R, "m", "filtered North position"),
    Var("track.z", _R, "m", "filtered Up position"),
    Var("track.vx", _R, "m/s", "filtered East velocity"),
    Var("track.vy", _R, "m/s", "filtered North velocity"),
    Var("track.vz", _R, "m/s", "filtered Up velocity"),
    Var("track.range", _R, "m", "filtered range"),
    Var("track.range_rate", _R, "m/s", "filtered range rate"),
    Var("track.az", _R, "rad", "filtered azimuth"),
    Var("track.el", _R, "rad", "filtered elevation"),
    Var("cmd.az", _R, "V", "pedestal azimuth rate command"),
    Var("cmd.el", _R, "V", "pedestal elevation rate command"),
    Var("gate.start", _R, "m", "gate start (range of the bin-1 sample) for the next PRI"),
    Var("maneuver", "Boolean", description="maneuver detected (fading-memory NIS test)",
        start=False),
    Var("maneuver.statistic", _R, "1", "fading-memory NIS statistic"),
    Var("maneuver.threshold", _R, "1", "threshold of the maneuver test"),
    Var("track.n", "Integer", description="number of measurements in the track", start=0),
    Var("track.valid", "Boolean", description="a track exists", start=False),
    Var("coasting", "Boolean", description="no usable measurement this step (prediction only)",
        start=False),
    Var("innovation.x", _R, "m", "East innovation of the last update"),
    Var("innovation.y", _R, "m", "North innovation of the last update"),
    Var("innovation.z", _R, "m", "Up innovation of the last update"),
    Var("ddre.range", _R, "m", "DDRE measured range (seed 001 eq. 7; 0 when disabled)"),
    Var("ddre.smoothed", _R, "m", "DDRE smoothed range (seed 001 eq. 8)"),
    Var("ddre.predicted", _R, "m", "DDRE predicted gate range (seed 001 eq. 11)"),
    Var("ddre.valid", "Boolean", description="DDRE estimate valid", start=False),
    Var("track.range_acc", _R, "m/s2", "range acceleration estimate (beams mode: Cartesian "
        "estimate on the line of sight; 0 for filters without an acceleration estimate)"),
    Var("track.acc.x", _R, "m/s2", "filtered East acceleration (0 without an estimate)"),
    Var("track.acc.y", _R, "m/s2", "filtered North acceleration (0 without an estimate)"),
    Var("track.acc.z", _R, "m/s2", "filtered Up acceleration (0 without an estimate)"),
    Var("track.P_rr", _R, "m2", "range variance (measurement mode: range filter; beams mode: "
        "Cartesian covariance projected on the line of sight)"),
    Var("track.P_rv", _R, "m2/s", "range / range-rate covariance (as track.P_rr)"),
    Var("track.P_vv", _R, "m2/s2", "range-rate variance (as track.P_rr)"),
)

SPEC = FmuSpec(
    name="Tracker",
    model=Tracker,
    description="AXIR_B digital tracker: monopulse deviations, Cartesian alpha-beta tracking, "
                "pedestal rate commands, range gate (seed 000), DDRE (seed 001), Kalman/SVD/VD/"
                "IMM filters and measurement input mode (seed 002)",
    inputs=INPUTS,
    outputs=OUTPUTS,
    default_step=1e-4,
)
