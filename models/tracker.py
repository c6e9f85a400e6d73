"""AXIR_B digital tracker: deviations, Cartesian tracking, pedestal commands (seed 000), and the
seed-002 maneuvering-target filters.

One :meth:`Tracker.step` per PRI. Inputs (SYSTEM.md public names):

- ``beam``: magnitudes, numpy array (4, 16, 3) = up (B1), right (B2), down (B3), left (B4) ×
  range bins 1..16 × Doppler filters 1..3;
- ``ped.az``, ``ped.el`` [rad]: pedestal angles;
- ``mode``: 0 acquisition, 1 tentative, 2 confirmed (RadarManager);
- ``alpha``, ``beta`` [1]: steady α-β gains of the manager (0 = not supplied → evolutive only);
- ``range.offset`` [m]: ambiguity offset, true range = apparent range + offset (radar.py);
- ``gate.command`` [m]: gate start (range of bin 1) wanted by the manager;
- ``meas.range`` [m], ``meas.az``, ``meas.el`` [rad], ``meas.valid``, ``meas.new`` [0/1]:
  measurements (``input_mode = "measurement"`` only; TargetGenerator measurement fidelity).

Outputs: ``sum`` (16, 3) (seed 000 eq. 1), ``dev.az``, ``dev.el`` [rad], ``dev.range`` [m],
``track.x/y/z`` [m], ``track.vx/vy/vz`` [m/s], ``track.range`` [m], ``track.range_rate``
[m/s], ``track.az``, ``track.el`` [rad], ``cmd.az``, ``cmd.el`` [V], ``gate.start`` [m],
``maneuver`` (bool); extras ``dev.lat`` [rad] (lateral deviation before /cos El), ``track.n``
(measurements in the track), ``track.valid`` (bool), ``coasting`` (bool: no usable
measurement this step, prediction only), ``innovation.x/y/z`` [m], ``maneuver.statistic``
[1] (fading NIS sum) and ``maneuver.threshold`` [1]; ``ddre.range``, ``ddre.smoothed``,
``ddre.predicted`` [m], ``ddre.valid`` (bool): optional DDRE range estimate (seed 001) on the
SUM range profile of the window (enabled by ``ddre_window`` > 0; 0.0 and false otherwise);
``track.range_acc`` [m/s²], ``track.acc.x/y/z`` [m/s²] (0 for filters without an acceleration
estimate) and the range-axis covariance ``track.P_rr`` [m²], ``track.P_rv`` [m²/s],
``track.P_vv`` [m²/s²] (beams mode: the Cartesian estimates projected on the line of sight,
first order with the unit vector held fixed; measurement mode: the range filter's).

Filters (docs/filters.md): one per-axis filter (:mod:`axir.models.axisfilter`) chosen by
``filter_x/y/z`` (Cartesian axes, beams mode) or ``filter_range/az/el`` (spherical axes,
measurement mode): "alphabeta" (default, seed 000), "kalman", "svd", "svd_reduced", "vd" (seed
002), "imm" (comparison). With α-β on the three Cartesian axes in beams mode (the default) the
tracker is exactly the seed-000 tracker, maneuver test included (3-D NIS,
:class:`~axir.models.alphabeta.ManeuverDetector`); otherwise ``maneuver`` is true when any
axis's fading-memory detector (seed 002 eqs. 11-15) declares a maneuver, and
``maneuver.statistic``/``maneuver.threshold`` are L(k) and I1 of the axis with the largest L/I1.

Measurement mode (``input_mode = "measurement"``, :meth:`Tracker._step_measurement`): the
beams, pedestal angles and mode are ignored; the three spherical filters start on the first
valid measurement and update at each ``meas.new`` with T = time since the previous one;
between measurements the outputs are extrapolated (``coasting``); no pedestal command
(``cmd.*`` = 0), ``dev.*`` and ``innovation.*`` = 0, ``gate.start`` = track range − 6·75 m.

Behaviour:

- mode 0: no track (filter reset). The pedestal is driven toward the designation
  (az, el) by the position loop ω = K·(designation − pedestal angle); ``gate.start`` =
  ``gate.command``. Track outputs report the designation (velocity 0, ``track.valid`` false).
- mode 1/2: the seed's nine steps ("General Algorithm for Tracking"):
  1-2) deviations from the gate cells (bins 6, 7, 8; tentative: Σ over the 3 Doppler filters,
  confirmed: central filter only; SYSTEM.md), angle = ε/k_m (linear law) or atanh(ε)/k_m
  (exact inversion of the pattern), dAz = dLat/cos(El), dR = ε_R·75 m;
  3) (dAz, dEl, dR) → (dXm, dYm, dZm) with the total differences (geometry.sph_to_cart_diff);
  4-5) pedestal angles and gate-centre range → (Xa, Ya, Za); the gate-centre range is the
  gate start used for these beams + 6·75 m + ``range.offset``;
  6) Xm = Xa + dXm …; 7) filtering per axis (α-β: alphabeta.AlphaBetaAxis, the seed's
  equations with the manager's steady gains), measurement variances from ``sigma_range`` and
  ``sigma_angle`` (diagonal of the Cartesian measurement covariance);
  8) smoothed velocity → angle rates (geometry.cart_to_sph_diff) plus a pointing correction
  toward the filtered position, rate-command law
  ω_cmd = ω_track + K·wrap(angle_track − angle_pedestal), cmd = ω_cmd / rate_per_volt [V]
  (clipped to ±cmd_limit);
  9) filtered (ρ, Az, El) out for the manager; predicted range → gate: in mode 1 the gate
  follows ``gate.command``; in mode 2 the tracker places it itself at the range predicted one
  step ahead, gate.start = R_pred − range.offset − 6·75 m (apparent range; the generator folds).
- The filters are initialised on the first usable measurement after the mode becomes ≥ 1
  (n = 1 there) and reset when the mode returns to 0.
- Robustness: NaN/Inf beams, angles, offsets or gate, or a gate signal not above the noise
  (strongest gate-cell SUM of bins 6-8 ≤ min_snr × mean SUM of the side bins 1-4, 10-16),
  never enter the filter:
  the tracker coasts on prediction and reports ``coasting``; all outputs stay finite.

Latency: the beams received at a step were formed with the gate output ``gate_latency`` steps
earlier (1 for a Gauss-Seidel master that steps the generator just before the tracker, 2 for a
Jacobi master); the measured range uses that gate. Pedestal angles are used as received (the
antenna moves by rate × PRI between the two, negligible against the beamwidth).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from .alphabeta import AlphaBetaAxis, ManeuverDetector
from .axisfilter import FILTER_KINDS, AxisFilter, FilterConfig, make_axis_filter
from .ddre import DDRE
from .deviations import dif_sum, early_late
from .fixedpoint import TableQuantiser
from .radar.antenna import MonopulseAntenna
from .radar.conventions import (
    ACQUISITION,
    BEAMS,
    BIN_M,
    CONFIRMED,
    GATE_BIN,
    N_BEAMS,
    N_BINS,
    N_DOPPLER,
)
from .radar.geometry import cart_to_sph, cart_to_sph_diff, sph_to_cart, sph_to_cart_diff, wrap_pi
from .radar.params import Param
from .radar.ports import Port
from .radar.unit import Unit

_GATE_CENTRE_M = (GATE_BIN - 1) * BIN_M  # bin 7 samples gate_start + 6·75 m (radar.py)
_C = GATE_BIN - 1  # 0-based index of bin 7
_SIDE = np.r_[0:_C - 2, _C + 3:16]  # side bins 1-4 and 10-16 (0-based): noise level (seed 000)
_MIN_COS_EL = 1e-3  # clamp of cos(El) in dAz = dLat/cos(El) near the zenith


#: Public inputs of ``step``.
INPUTS: tuple[Port, ...] = (
    Port("beam", float, "1", "beam magnitude (Doppler filter output) per range bin r and filter f",
        shape=(N_BEAMS, N_BINS, N_DOPPLER), labels=BEAMS),
    Port("ped.az", float, "rad", "pedestal azimuth (decoded potentiometers)"),
    Port("ped.el", float, "rad", "pedestal elevation (decoded potentiometers)"),
    Port("mode", int, "1", "radar mode: 0 acquisition, 1 tentative, 2 confirmed"),
    Port("alpha", float, "1", "steady alpha gain from the manager (0: evolutive gains only)"),
    Port("beta", float, "1", "steady beta gain from the manager (0: evolutive gains only)"),
    Port("range.offset", float, "m", "range ambiguity offset: true range = apparent + offset"),
    Port("gate.command", float, "m", "gate start (range of bin 1) commanded by the manager"),
    Port("meas.range", float, "m", "measured range (input_mode = measurement)"),
    Port("meas.az", float, "rad", "measured azimuth (input_mode = measurement)"),
    Port("meas.el", float, "rad", "measured elevation (input_mode = measurement)"),
    Port("meas.valid", float, "1", "1 once a measurement exists (input_mode = measurement)"),
    Port("meas.new", float, "1", "1 in the step that brings a new measurement (input_mode = "
        "measurement)"),
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


class Tracker(Unit):
    """AXIR_B digital tracker (seed 000). See the module docstring for inputs/outputs."""

    INPUTS = INPUTS
    OUTPUTS = OUTPUTS

    PARAMS = (
        Param("rate_per_volt", 0.1, "rad/(s.V)",
              "pedestal rate per command volt (same value as the Pedestal)", low=0.0,
              low_open=True),
        Param("pointing_gain", 2.0, "1/s",
              "position-loop gain K of the pointing correction ω = K·(angle error)", low=0.0,
              high=1e4),
        Param("cmd_limit", 10.0, "V", "saturation of the rate-command voltages", low=0.0,
              low_open=True),
        Param("designation_az", 0.0, "rad", "designated azimuth (acquisition pointing)",
              low=-2 * math.pi, high=2 * math.pi),
        Param("designation_el", 0.1, "rad", "designated elevation (acquisition pointing)",
              low=-math.pi / 2, high=math.pi / 2),
        Param("designation_range", 10_000.0, "m", "designated range (reported in mode 0)",
              low=0.0),
        Param("monopulse_law", "linear", "",
              "angle from DIF/SUM ratio: 'linear' θ = ε/k_m (SYSTEM.md) or 'exact' "
              "θ = atanh(ε)/k_m (inverse of the Gaussian pattern)", choices=("linear", "exact")),
        Param("beamwidth", math.radians(2.5), "rad", "3 dB beamwidth of each squinted beam",
              low=1e-4, high=0.5),
        Param("squint", math.radians(1.25), "rad", "squint of each beam from boresight",
              low=0.0, high=0.5, low_open=True),
        Param("min_snr", 2.0, "1",
              "weak-signal check: coast unless gate-centre SUM > min_snr × mean side-bin SUM",
              low=0.0),
        Param("gate_latency", 1, "1",
              "steps between a gate.start output and the beams formed with it", low=1, high=4),
        Param("n_max", 0, "1",
              "cap of the evolutive gain index (0 = none: growing memory until the manager's "
              "steady gains take over)", low=0, high=10**9),
        Param("sigma_range", 7.5, "m",
              "range measurement accuracy σr: maneuver detector and the filters' measurement "
              "variance (measurement mode: σ of meas.range; seed 002 scenarios: 100 m)",
              low=0.0, low_open=True),
        Param("sigma_angle", 1e-3, "rad",
              "angle measurement accuracy: maneuver detector and the filters' measurement "
              "variance (measurement mode: σ of meas.az and meas.el)", low=0.0, low_open=True),
        Param("maneuver_fading", 0.8, "1",
              "fading factor ρ of the NIS average (memory ≈ 1/(1 − ρ) updates)", low=0.0,
              high=1.0, high_open=True),
        Param("maneuver_pfa", 1e-3, "1", "false-alarm probability of the maneuver test",
              low=0.0, high=1.0, low_open=True, high_open=True),
        Param("ddre_window", 0, "1",
              "DDRE window s in 75 m bins on the SUM profile (0 = DDRE disabled)", low=0,
              high=5),
        Param("ddre_background", "none", "", "DDRE background subtraction (seed 001)",
              choices=("none", "local", "global")),
        Param("ddre_threshold", 0.0, "1", "DDRE threshold on S0(r_max) [SUM magnitude²]",
              low=0.0),
        Param("ddre_memory", 0.5, "s", "DDRE memory τ (seed 001 eq. 10)", low=0.0,
              low_open=True),
        Param("ddre_velocity_cut", 200.0, "m/s", "DDRE velocity cut (0 = none)", low=0.0),
        Param("ddre_t_pred", 0.1, "s", "DDRE prediction shift t_pred (seed 001 eq. 11)",
              low=0.0),
        Param("input_mode", "beams", "",
              "'beams': monopulse beams + pedestal (seed 000 tracker); 'measurement': filter "
              "meas.range/az/el (TargetGenerator measurement fidelity, seed 002 experiments)",
              choices=("beams", "measurement")),
        *(Param(f"filter_{axis}", "alphabeta", "",
                f"filter of the {label} axis ({mode} input mode; docs/filters.md)",
                choices=FILTER_KINDS)
          for axis, label, mode in (("x", "East (X)", "beams"), ("y", "North (Y)", "beams"),
                                    ("z", "Up (Z)", "beams"), ("range", "range", "measurement"),
                                    ("az", "azimuth", "measurement"),
                                    ("el", "elevation", "measurement"))),
        Param("filter_sigma_m", 5.0, "m/s2",
              "process noise σm of the two-state models (seed 002 eq. 4; svd-1: 5, svd-2: 20); "
              "angle axes use σm/ρ", low=0.0, high=1e4),
        Param("filter_sigma_a", 2.0, "m/s2",
              "acceleration noise σa per 1 s: SVD Q_u = σa²·T (seed 002 eqs. 22, 36), VD "
              "three-state and IMM CA white-jerk density σa²/s (assumption)", low=0.0,
              high=1e4),
        Param("fmd_i1", 0.0, "1",
              "FMD detection threshold I1 on L(k) (seed 002 eqs. 11-15); 0 = chi2 quantile at "
              "maneuver_pfa (fading factor a_f = maneuver_fading)", low=0.0, high=1e6),
        Param("fmd_i2", 0.0, "1",
              "FMD end-of-maneuver threshold I2 on the acceleration significance summed over "
              "M = 1/(1 − a_f) updates; 0 = chi2 quantile at fmd_level", low=0.0, high=1e6),
        Param("fmd_level", 0.05, "1", "significance level of the acceleration test (I2)",
              low=0.0, high=1.0, low_open=True, high_open=True),
        Param("svd_pu0", 0.1, "m2/s4", "SVD P_u(0/0) (seed 002 §2.3: 0.1)", low=0.0,
              low_open=True),
        Param("svd_c", "paper", "",
              "full SVD form: C of eqs. 20, 25, 27: 'paper' C = T²/2, 'zero' C = 0 (then equal "
              "to the reduced form)", choices=("paper", "zero")),
        Param("imm_sojourn_cv", 20.0, "s", "IMM mean sojourn time of the CV mode",
              low=0.0, low_open=True),
        Param("imm_sojourn_ca", 5.0, "s", "IMM mean sojourn time of the CA mode",
              low=0.0, low_open=True),
        Param("imm_mu_ca", 0.1, "1", "IMM initial probability of the CA mode", low=0.0,
              high=1.0, low_open=True, high_open=True),
        Param("imm_sigma_acc0", 20.0, "m/s2", "IMM initial acceleration σ", low=0.0),
        Param("fixed_point", False, "",
              "emulate the seed-002 FPGA word lengths (Table 3: 8/12/16-bit buses, rounding, "
              "saturation) in the range filter; needs input_mode = measurement and "
              "filter_range = svd_reduced (docs/fixed_point.md)"),
    )

    def _check(self) -> None:
        if self.fixed_point and (self.input_mode != "measurement"
                                 or self.filter_range != "svd_reduced"):
            raise ValueError(
                f"Tracker: fixed_point = True needs input_mode = 'measurement' and "
                f"filter_range = 'svd_reduced' (got {self.input_mode!r}, "
                f"{self.filter_range!r}): the Table 3 word lengths are those of the seed-002 "
                "range filter"
            )
        if self.squint > self.beamwidth:
            raise ValueError(
                f"Tracker: squint = {self.squint!r} rad must not exceed beamwidth = "
                f"{self.beamwidth!r} rad"
            )

    # ---------------------------------------------------------------------------- state
    def reset(self) -> None:
        self.antenna = MonopulseAntenna(beamwidth=self.beamwidth, squint=self.squint)
        self.inv_slope = 1.0 / self.antenna.slope  # 1/k_m [rad]
        self.exact = self.monopulse_law == "exact"
        cfg = FilterConfig(
            sigma_m=self.filter_sigma_m, sigma_meas=self.sigma_range, sigma_a=self.filter_sigma_a,
            a_f=self.maneuver_fading, i1=self.fmd_i1, i2=self.fmd_i2, pfa=self.maneuver_pfa,
            level=self.fmd_level, pu0=self.svd_pu0, svd_c=self.svd_c,
            imm_sojourn_cv=self.imm_sojourn_cv, imm_sojourn_ca=self.imm_sojourn_ca,
            imm_mu_ca=self.imm_mu_ca, sigma_acc0=self.imm_sigma_acc0, n_max=self.n_max,
        )
        self.measurement_mode = self.input_mode == "measurement"
        #: Cartesian axis filters (beams mode): X, Y, Z
        self.axes: list[AxisFilter] = [make_axis_filter(k, cfg) for k in
                                       (self.filter_x, self.filter_y, self.filter_z)]
        #: spherical axis filters (measurement mode): range, azimuth, elevation; α-β axes take
        #: Kalata's steady gains (no manager in that mode)
        cfg_sph = replace(cfg, auto_gains=True)
        cfg_range = replace(cfg_sph, quant=TableQuantiser()) if self.fixed_point else cfg_sph
        self.sph: list[AxisFilter] = [make_axis_filter(self.filter_range, cfg_range),
                                      make_axis_filter(self.filter_az, cfg_sph),
                                      make_axis_filter(self.filter_el, cfg_sph)]
        #: the seed-000 tracker: α-β on the three axes with the 3-D NIS maneuver detector
        self.legacy_detector = not self.measurement_mode and all(
            isinstance(f, AlphaBetaAxis) for f in self.axes)
        if self.legacy_detector:
            for f in self.axes:
                f.detect = False
        self.detector = ManeuverDetector(self.maneuver_fading, self.maneuver_pfa)
        self.since = 0.0  # measurement mode: time since the last measurement [s]
        self.gate_history: list[float] = []  # gate.start outputs, most recent last
        self.mode = ACQUISITION
        self.coast_count = 0
        self.time = 0.0  # [s], sum of the steps (DDRE time base)
        self.ddre = (
            DDRE(window=self.ddre_window, bin_size=BIN_M, background=self.ddre_background,
                 threshold=self.ddre_threshold, memory=self.ddre_memory,
                 velocity_cut=self.ddre_velocity_cut, t_pred=self.ddre_t_pred)
            if self.ddre_window > 0 else None
        )
        self.ddre_out = (0.0, 0.0, 0.0, False)

    def _reset_track(self) -> None:
        for f in self.axes:
            f.reset()
        for f in self.sph:
            f.reset()
        self.detector.reset()
        self.since = 0.0
        self.coast_count = 0
        if self.ddre is not None:
            self.ddre.reset()
        self.ddre_out = (0.0, 0.0, 0.0, False)

    # ---------------------------------------------------------------------------- helpers
    def _angle(self, eps: float) -> float:
        """Angle off boresight from a monopulse ratio [rad] (SYSTEM.md: angle = ε/k_m)."""
        if self.exact:
            e = -0.999999 if eps < -0.999999 else (0.999999 if eps > 0.999999 else eps)
            return math.atanh(e) * self.inv_slope
        return eps * self.inv_slope

    def _cmd(self, rate: float) -> float:
        """Rate [rad/s] → command voltage [V], clipped to ±cmd_limit (0 if not finite)."""
        if not math.isfinite(rate):
            return 0.0
        v = rate / self.rate_per_volt
        lim = self.cmd_limit
        return lim if v > lim else (-lim if v < -lim else v)

    def _gate_used(self, fallback: float) -> float:
        h = self.gate_history
        return h[-self.gate_latency] if len(h) >= self.gate_latency else fallback

    def _designation_outputs(
        self, sums: np.ndarray, devs: tuple[float, float, float, float], ped_ok: bool,
        az: float, el: float, gate_cmd: float, coasting: bool, nu: tuple[float, float, float],
    ) -> dict[str, Any]:
        """No track: point the pedestal at the designation (position loop), gate from the
        manager, track outputs report the designation."""
        des_az, des_el = self.designation_az, self.designation_el
        kp = self.pointing_gain
        if ped_ok:
            cmd_az = self._cmd(kp * wrap_pi(des_az - az))
            cmd_el = self._cmd(kp * (des_el - el))
        else:
            cmd_az = cmd_el = 0.0
        self._push_gate(gate_cmd)
        x, y, z = sph_to_cart(self.designation_range, des_az, des_el)
        return self._outputs(
            sums, *devs, (x, y, z), (0.0, 0.0, 0.0), self.designation_range, 0.0,
            des_az % (2 * math.pi), des_el, cmd_az, cmd_el, gate_cmd, coasting, False, nu,
        )

    # ---------------------------------------------------------------------------- step
    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """Advance one PRI of ``dt`` [s]; see the module docstring for keys and units."""
        if self.measurement_mode:
            return self._step_measurement(float(dt), inputs)
        beams = np.asarray(inputs["beam"], dtype=float)
        sums = beams.sum(axis=0)  # seed 000 eq. (1): SUM = B1 + B2 + B3 + B4
        mode = int(inputs.get("mode", ACQUISITION))
        az = float(inputs["ped.az"])
        el = float(inputs["ped.el"])
        offset = float(inputs.get("range.offset", 0.0))
        gate_cmd = float(inputs.get("gate.command", math.nan))
        T = float(dt)
        t_ok = T > 0.0 and math.isfinite(T)
        ped_ok = math.isfinite(az) and math.isfinite(el)
        if not math.isfinite(offset):
            offset = math.nan
        if not math.isfinite(gate_cmd):
            gate_cmd = self.gate_history[-1] if self.gate_history else 0.0
        axes = self.axes
        fx = axes[0]
        kp = self.pointing_gain
        if t_ok:
            self.time += T

        if mode <= ACQUISITION:
            # ---------------- acquisition: no track, position loop to the designation
            if self.mode != ACQUISITION or fx.initialised:
                self._reset_track()
            self.mode = ACQUISITION
            return self._designation_outputs(sums, (0.0, 0.0, 0.0, 0.0), ped_ok, az, el,
                                              gate_cmd, False, (0.0, 0.0, 0.0))

        # ---------------- tentative / confirmed tracking (seed 000 steps 1-9)
        confirmed = mode >= CONFIRMED
        self.mode = CONFIRMED if confirmed else mode
        gate_used = self._gate_used(gate_cmd)
        # steps 1-2: gate cells, bins 6, 7, 8 (SYSTEM.md: tentative Σ filters, confirmed central)
        if confirmed:
            cells = beams[:, _C - 1:_C + 2, 1]
            col = sums[:, 1]
        else:
            cells = beams[:, _C - 1:_C + 2, :].sum(axis=2)
            col = sums.sum(axis=1)
        (u6, u7, u8), (r6, r7, r8), (d6, d7, d8), (l6, l7, l8) = cells.tolist()
        s6, s7, s8 = u6 + r6 + d6 + l6, u7 + r7 + d7 + l7, u8 + r8 + d8 + l8
        noise = float(col[_SIDE].sum()) / _SIDE.size  # seed 000: side bins → noise level
        # assumption: angles from the strongest gate cell (bin 7 when centred, as the seed
        # reads it); a target straddling bins 7-8 during a range lag keeps usable angles and
        # the weak-signal check looks at the strongest of bins 6-8, not bin 7 alone.
        if s8 > s7 and s8 >= s6:
            u7, r7, d7, l7, s_max = u8, r8, d8, l8, s8
        elif s6 > s7:
            u7, r7, d7, l7, s_max = u6, r6, d6, l6, s6
        else:
            s_max = s7
        strong = s_max > self.min_snr * noise and s_max > 0.0  # False for NaN too
        dev_lat = dev_el = dev_az = dev_r = 0.0
        valid = False
        if strong and ped_ok and t_ok and math.isfinite(offset) and math.isfinite(gate_used):
            den_el, den_lat, den_r = u7 + d7, r7 + l7, s6 + s7 + s8
            if den_el > 0.0 and den_lat > 0.0 and den_r > 0.0:
                # SYSTEM.md ratios (deviations.py); dR = ε_R · 75 m (triangular response)
                dev_el = self._angle(dif_sum(u7, d7))
                dev_lat = self._angle(dif_sum(r7, l7))
                dev_r = early_late(s6, s7, s8) * BIN_M
                ce = math.cos(el)
                if abs(ce) < _MIN_COS_EL:
                    ce = math.copysign(_MIN_COS_EL, ce)
                dev_az = dev_lat / ce  # seed 000: dAz = dLat/cos(El)
                valid = math.isfinite(dev_el) and math.isfinite(dev_lat) and math.isfinite(dev_r)
        if not valid:
            dev_lat = dev_el = dev_az = dev_r = 0.0
        if self.ddre is not None and math.isfinite(gate_used) and math.isfinite(offset):
            self._ddre_step(col, gate_used + offset)

        nu = (0.0, 0.0, 0.0)
        if valid:
            rho_g = gate_used + _GATE_CENTRE_M + offset  # true gate-centre range (radar.py)
            # step 3: spherical deviations → Cartesian differentials (seed 000)
            dx, dy, dz = sph_to_cart_diff(rho_g, az, el, dev_r, dev_az, dev_el)
            # steps 4-5: pedestal position (seed 000 "Spherical to Cartesian (in Position)")
            xa, ya, za = sph_to_cart(rho_g, az, el)
            # step 6: Xm = Xa + dXm … (seed 000)
            zm = (xa + dx, ya + dy, za + dz)
            valid = math.isfinite(zm[0]) and math.isfinite(zm[1]) and math.isfinite(zm[2])
            if valid:
                # step 7: filtering per axis (seed 000: α-β with the manager's steady gains;
                # or the filter_x/y/z choice), measurement variances from the accuracies
                a_ss = float(inputs.get("alpha", 0.0))
                b_ss = float(inputs.get("beta", 0.0))
                m_az, m_el, m_rho = az + dev_az, el + dev_el, rho_g + dev_r
                rvar = _cartesian_variances(m_rho, m_az, m_el, self.sigma_range,
                                            self.sigma_angle)
                nu_l = [0.0, 0.0, 0.0]
                for i in range(3):
                    f = axes[i]
                    f.set_steady_gains(a_ss, b_ss)
                    nu_l[i] = f.update(zm[i], T, rvar[i])
                nu = (nu_l[0], nu_l[1], nu_l[2])
                self.coast_count = 0
                if self.legacy_detector and fx.n >= 3:
                    q = ManeuverDetector.nis(
                        nu, m_az, m_el, m_rho, self.sigma_range, self.sigma_angle,
                        fx.innovation_factor(),
                    )
                    self.detector.update(q)
        if not valid:
            if fx.initialised and t_ok:
                for f in axes:
                    f.coast(T)  # prediction only (no measurement enters the state)
            self.coast_count += 1

        if not fx.initialised:
            # no track yet: keep pointing at the designation, gate from the manager
            return self._designation_outputs(sums, (dev_az, dev_el, dev_lat, dev_r), ped_ok,
                                              az, el, gate_cmd, not valid, nu)

        # step 8: smoothed velocity → angle rates + pointing correction → command voltages
        (px, vx, ax), (py, vy, ay), (pz, vz, az_) = axes[0].x, axes[1].x, axes[2].x
        rng, t_az, t_el = cart_to_sph(px, py, pz)
        try:
            rdot, az_rate, el_rate = cart_to_sph_diff(px, py, pz, vx, vy, vz)
        except ZeroDivisionError:  # target at the zenith or at the antenna
            rdot = az_rate = el_rate = 0.0
        if ped_ok:
            cmd_az = self._cmd(az_rate + kp * wrap_pi(t_az - az))
            cmd_el = self._cmd(el_rate + kp * (t_el - el))
        else:
            cmd_az, cmd_el = self._cmd(az_rate), self._cmd(el_rate)
        # step 9 and gate: predicted range one step ahead places the gate in confirmed mode
        if confirmed and math.isfinite(offset):
            tp = T if t_ok else 0.0
            qx, qy, qz = axes[0].predict(tp)[0], axes[1].predict(tp)[0], axes[2].predict(tp)[0]
            gate = math.sqrt(qx * qx + qy * qy + qz * qz) - offset - _GATE_CENTRE_M
        else:
            gate = gate_cmd
        self._push_gate(gate)
        out = self._outputs(
            sums, dev_az, dev_el, dev_lat, dev_r, (px, py, pz), (vx, vy, vz), rng, rdot, t_az,
            t_el, cmd_az, cmd_el, gate, not valid, True, nu,
        )
        # line-of-sight projection of the Cartesian estimates (axes independent: the covariance
        # is block-diagonal over X, Y, Z; first order, unit vector u held fixed)
        inv = 1.0 / rng if rng > 0.0 else 0.0
        ux, uy, uz = px * inv, py * inv, pz * inv
        p_rr = p_rv = p_vv = 0.0
        for w, f in ((ux * ux, axes[0]), (uy * uy, axes[1]), (uz * uz, axes[2])):
            a, b, c = f.P
            p_rr += w * a
            p_rv += w * b
            p_vv += w * c
        out.update({
            "track.range_acc": ux * ax + uy * ay + uz * az_,
            "track.acc.x": ax, "track.acc.y": ay, "track.acc.z": az_,
            "track.P_rr": p_rr, "track.P_rv": p_rv, "track.P_vv": p_vv,
        })
        return out

    # ---------------------------------------------------------------------------- measurement
    def _step_measurement(self, T: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """Measurement input mode: the chosen filter per spherical axis (range, az, el) on
        ``meas.range/az/el`` (seed 002: filters "applied with spherical coordinate").

        A new measurement (``meas.new`` = 1, ``meas.valid`` = 1, finite values) updates the
        three filters with T = the time since the previous measurement; otherwise the outputs
        are the estimates extrapolated to the current time (state unchanged) and ``coasting``
        is true. The azimuth measurement is unwrapped around the predicted azimuth; the angle
        axes scale the metric noise parameters by 1/ρ̂ (elevation) and 1/(ρ̂ cos Êl)
        (azimuth). Beams, pedestal angles and the mode are ignored; no pedestal command.
        """
        beam = inputs.get("beam")
        sums = np.asarray(beam, dtype=float).sum(axis=0) if beam is not None else \
            np.zeros((16, 3))
        z_r = float(inputs.get("meas.range", math.nan))
        z_a = float(inputs.get("meas.az", math.nan))
        z_e = float(inputs.get("meas.el", math.nan))
        valid = float(inputs.get("meas.valid", 0.0)) > 0.5
        new = float(inputs.get("meas.new", 0.0)) > 0.5
        if T > 0.0 and math.isfinite(T):
            self.time += T
            self.since += T
        fr, fa, fe = self.sph
        used = (valid and new and math.isfinite(z_r) and math.isfinite(z_a)
                and math.isfinite(z_e))
        if used and not fr.initialised:
            var_a = self.sigma_angle ** 2
            fr.update(z_r, 0.0, self.sigma_range ** 2)
            fa.update(z_a, 0.0, var_a)
            fe.update(z_e, 0.0, var_a)
            self.since = 0.0
        elif used and self.since > 0.0:
            ts = self.since
            var_a = self.sigma_angle ** 2
            fr.update(z_r, ts, self.sigma_range ** 2)
            rho = max(fr.x[0], 1.0)
            e_hat = fe.predict(ts)[0]
            ce = max(abs(math.cos(e_hat)), _MIN_COS_EL)
            a_hat = fa.predict(ts)[0]
            fa.update(a_hat + wrap_pi(z_a - a_hat), ts, var_a, 1.0 / (rho * ce))
            fe.update(z_e, ts, var_a, 1.0 / rho)
            self.since = 0.0
        else:
            used = False
        if not fr.initialised:
            out = self._outputs(sums, 0.0, 0.0, 0.0, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0),
                                0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, True, False,
                                (0.0, 0.0, 0.0))
            return out
        ts = self.since
        (r, rd, rdd), (a, ad, add), (e, ed, edd) = (
            (f.predict(ts) if ts > 0.0 else f.x) for f in self.sph)
        pos, vel, acc = sph_to_cart_kinematics((r, a, e), (rd, ad, ed), (rdd, add, edd))
        out = self._outputs(sums, 0.0, 0.0, 0.0, 0.0, pos, vel, r, rd, a % (2 * math.pi), e,
                            0.0, 0.0, r - _GATE_CENTRE_M, not used, True, (0.0, 0.0, 0.0))
        p_rr, p_rv, p_vv = fr.P
        out.update({
            "track.range_acc": rdd,
            "track.acc.x": acc[0], "track.acc.y": acc[1], "track.acc.z": acc[2],
            "track.P_rr": p_rr, "track.P_rv": p_rv, "track.P_vv": p_vv,
        })
        return out

    def _ddre_step(self, profile: np.ndarray, range_start: float) -> None:
        """Seed 001 DDRE on the SUM profile; bin r (0-based) at range_start + r·75 m."""
        if not np.isfinite(profile).all():
            return
        out = self.ddre.update(profile, self.time, range_start)
        if math.isfinite(out.smoothed):
            self.ddre_out = (out.range, out.smoothed, out.predicted, out.detected)

    def _push_gate(self, gate: float) -> None:
        h = self.gate_history
        h.append(gate)
        if len(h) > 4:
            del h[0]

    def _outputs(
        self, sums: np.ndarray, dev_az: float, dev_el: float, dev_lat: float, dev_r: float,
        pos: tuple[float, float, float], vel: tuple[float, float, float], rng: float,
        rdot: float, t_az: float, t_el: float, cmd_az: float, cmd_el: float, gate: float,
        coasting: bool, valid: bool, nu: tuple[float, float, float],
    ) -> dict[str, Any]:
        if self.legacy_detector:
            det = self.detector
            flag, stat, thr = det.flag, det.d, det.threshold
        else:
            flag, stat, thr = _maneuver_summary(self.sph if self.measurement_mode else self.axes)
        n = (self.sph if self.measurement_mode else self.axes)[0].n
        return {
            "sum": sums,
            "dev.az": dev_az,
            "dev.el": dev_el,
            "dev.lat": dev_lat,
            "dev.range": dev_r,
            "track.x": pos[0],
            "track.y": pos[1],
            "track.z": pos[2],
            "track.vx": vel[0],
            "track.vy": vel[1],
            "track.vz": vel[2],
            "track.range": rng,
            "track.range_rate": rdot,
            "track.az": t_az,
            "track.el": t_el,
            "cmd.az": cmd_az,
            "cmd.el": cmd_el,
            "gate.start": gate,
            "maneuver": flag if valid else False,
            "maneuver.statistic": stat,
            "maneuver.threshold": thr,
            "track.n": n,
            "track.valid": valid,
            "coasting": coasting,
            "innovation.x": nu[0],
            "innovation.y": nu[1],
            "innovation.z": nu[2],
            "ddre.range": self.ddre_out[0],
            "ddre.smoothed": self.ddre_out[1],
            "ddre.predicted": self.ddre_out[2],
            "ddre.valid": self.ddre_out[3],
            "track.range_acc": 0.0,
            "track.acc.x": 0.0,
            "track.acc.y": 0.0,
            "track.acc.z": 0.0,
            "track.P_rr": 0.0,
            "track.P_rv": 0.0,
            "track.P_vv": 0.0,
        }


# -------------------------------------------------------------------------------- helpers
def _cartesian_variances(rho: float, az: float, el: float, sigma_range: float,
                         sigma_angle: float) -> tuple[float, float, float]:
    """Diagonal of the Cartesian measurement covariance [m²] of a measurement at (ρ, θ, φ)
    with range σ ``sigma_range`` [m] and angle σ ``sigma_angle`` [rad] (lateral and elevation:
    ρ·σ across the beam): Σ_k (u_k,i σ_k)² over the spherical unit vectors u_ρ, u_θ, u_φ."""
    ca, sa, ce, se = math.cos(az), math.sin(az), math.cos(el), math.sin(el)
    sr2 = sigma_range * sigma_range
    sc2 = (rho * sigma_angle) ** 2
    return (
        (ce * sa) ** 2 * sr2 + (ca * ca + (se * sa) ** 2) * sc2,
        (ce * ca) ** 2 * sr2 + (sa * sa + (se * ca) ** 2) * sc2,
        se * se * sr2 + ce * ce * sc2,
    )


def _maneuver_summary(filters: list[AxisFilter]) -> tuple[bool, float, float]:
    """(flag, statistic, threshold) over per-axis detectors: flag = any axis; statistic and
    threshold of the axis with the largest L/I1."""
    flag = False
    best, stat, thr = -math.inf, 0.0, 0.0
    for f in filters:
        flag = flag or f.maneuver
        t = f.threshold
        ratio = f.statistic / t if t > 0.0 else f.statistic
        if ratio > best:
            best, stat, thr = ratio, f.statistic, t
    return flag, stat, thr


def sph_to_cart_kinematics(
    s: tuple[float, float, float], sd: tuple[float, float, float],
    sdd: tuple[float, float, float],
) -> tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]:
    """Position [m], velocity [m/s], acceleration [m/s²] in ENU from (ρ, θ, φ) and their first
    and second time derivatives (X = ρ cosφ sinθ, Y = ρ cosφ cosθ, Z = ρ sinφ, differentiated
    twice)."""
    rho, az, el = s
    r1, a1, e1 = sd
    r2, a2, e2 = sdd
    ca, sa, ce, se = math.cos(az), math.sin(az), math.cos(el), math.sin(el)
    # horizontal range h = ρ cosφ and its derivatives
    h = rho * ce
    h1 = r1 * ce - rho * se * e1
    h2 = r2 * ce - 2.0 * r1 * se * e1 - rho * (ce * e1 * e1 + se * e2)
    pos = (h * sa, h * ca, rho * se)
    vel = (h1 * sa + h * ca * a1, h1 * ca - h * sa * a1, r1 * se + rho * ce * e1)
    acc = (
        h2 * sa + 2.0 * h1 * ca * a1 + h * (ca * a2 - sa * a1 * a1),
        h2 * ca - 2.0 * h1 * sa * a1 - h * (sa * a2 + ca * a1 * a1),
        r2 * se + 2.0 * r1 * ce * e1 + rho * (ce * e2 - se * e1 * e1),
    )
    return pos, vel, acc
