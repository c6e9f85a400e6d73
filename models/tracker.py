"""AXIR_B digital tracker: deviations, Cartesian α-β tracking, pedestal commands (seed 000).

One :meth:`Tracker.step` per PRI. Inputs (SYSTEM.md public names):

- ``beam``: magnitudes, numpy array (4, 16, 3) = up (B1), right (B2), down (B3), left (B4) ×
  range bins 1..16 × Doppler filters 1..3;
- ``ped.az``, ``ped.el`` [rad]: pedestal angles;
- ``mode``: 0 acquisition, 1 tentative, 2 confirmed (RadarManager);
- ``alpha``, ``beta`` [1]: steady α-β gains of the manager (0 = not supplied → evolutive only);
- ``range.offset`` [m]: ambiguity offset, true range = apparent range + offset (radar.py);
- ``gate.command`` [m]: gate start (range of bin 1) wanted by the manager.

Outputs: ``sum`` (16, 3) (seed 000 eq. 1), ``dev.az``, ``dev.el`` [rad], ``dev.range`` [m],
``track.x/y/z`` [m], ``track.vx/vy/vz`` [m/s], ``track.range`` [m], ``track.range_rate``
[m/s], ``track.az``, ``track.el`` [rad], ``cmd.az``, ``cmd.el`` [V], ``gate.start`` [m],
``maneuver`` (bool); extras ``dev.lat`` [rad] (lateral deviation before /cos El), ``track.n``
(measurements in the track), ``track.valid`` (bool), ``coasting`` (bool: no usable
measurement this step, prediction only), ``innovation.x/y/z`` [m], ``maneuver.statistic``
[1] (fading NIS sum) and ``maneuver.threshold`` [1]; ``ddre.range``, ``ddre.smoothed``,
``ddre.predicted`` [m], ``ddre.valid`` (bool): optional DDRE range estimate (seed 001) on the
SUM range profile of the window (enabled by ``ddre_window`` > 0; 0.0 and false otherwise).

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
  6) Xm = Xa + dXm …; 7) α-β filtering per axis (alphabeta.AlphaBeta3);
  8) smoothed velocity → angle rates (geometry.cart_to_sph_diff) plus a pointing correction
  toward the filtered position, rate-command law
  ω_cmd = ω_track + K·wrap(angle_track − angle_pedestal), cmd = ω_cmd / rate_per_volt [V]
  (clipped to ±cmd_limit);
  9) filtered (ρ, Az, El) out for the manager; predicted range → gate: in mode 1 the gate
  follows ``gate.command``; in mode 2 the tracker places it itself at the range predicted one
  step ahead, gate.start = R_pred − range.offset − 6·75 m (apparent range; the generator folds).
- The α-β filters are initialised on the first usable measurement after the mode becomes ≥ 1
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
from typing import Any

import numpy as np

from .alphabeta import AlphaBeta3, ManeuverDetector
from .antenna import MonopulseAntenna
from .ddre import DDRE
from .deviations import dif_sum, early_late
from .geometry import cart_to_sph, cart_to_sph_diff, sph_to_cart, sph_to_cart_diff, wrap_pi
from .params import Param
from .radar import ACQUISITION, BIN_M, CONFIRMED, GATE_BIN
from .unit import Unit

_GATE_CENTRE_M = (GATE_BIN - 1) * BIN_M  # bin 7 samples gate_start + 6·75 m (radar.py)
_C = GATE_BIN - 1  # 0-based index of bin 7
_SIDE = np.r_[0:_C - 2, _C + 3:16]  # side bins 1-4 and 10-16 (0-based): noise level (seed 000)
_MIN_COS_EL = 1e-3  # clamp of cos(El) in dAz = dLat/cos(El) near the zenith


class Tracker(Unit):
    """AXIR_B digital tracker (seed 000). See the module docstring for inputs/outputs."""

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
        Param("sigma_range", 7.5, "m", "range measurement accuracy (maneuver detector)",
              low=0.0, low_open=True),
        Param("sigma_angle", 1e-3, "rad", "angle measurement accuracy (maneuver detector)",
              low=0.0, low_open=True),
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
    )

    def _check(self) -> None:
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
        self.ab = AlphaBeta3(self.n_max)
        self.detector = ManeuverDetector(self.maneuver_fading, self.maneuver_pfa)
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
        self.ab.reset()
        self.detector.reset()
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
        ab = self.ab
        kp = self.pointing_gain
        if t_ok:
            self.time += T

        if mode <= ACQUISITION:
            # ---------------- acquisition: no track, position loop to the designation
            if self.mode != ACQUISITION or ab.initialised:
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
                # step 7: α-β filtering per axis (seed 000; gains: manager's steady gains)
                a_ss = float(inputs.get("alpha", 0.0))
                b_ss = float(inputs.get("beta", 0.0))
                nu = ab.update(zm, T, a_ss, b_ss)
                self.coast_count = 0
                if ab.n >= 3:
                    q = ManeuverDetector.nis(
                        nu, az + dev_az, el + dev_el, rho_g + dev_r, self.sigma_range,
                        self.sigma_angle, ab.innovation_factor(),
                    )
                    self.detector.update(q)
        if not valid:
            if ab.initialised and t_ok:
                ab.coast(T)  # prediction only (no measurement enters the state)
            self.coast_count += 1

        if not ab.initialised:
            # no track yet: keep pointing at the designation, gate from the manager
            return self._designation_outputs(sums, (dev_az, dev_el, dev_lat, dev_r), ped_ok,
                                              az, el, gate_cmd, not valid, nu)

        # step 8: smoothed velocity → angle rates + pointing correction → command voltages
        px, py, pz = ab.x
        vx, vy, vz = ab.v
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
            qx, qy, qz = ab.predict(T if t_ok else 0.0)
            gate = math.sqrt(qx * qx + qy * qy + qz * qz) - offset - _GATE_CENTRE_M
        else:
            gate = gate_cmd
        self._push_gate(gate)
        return self._outputs(
            sums, dev_az, dev_el, dev_lat, dev_r, (px, py, pz), (vx, vy, vz), rng, rdot, t_az,
            t_el, cmd_az, cmd_el, gate, not valid, True, nu,
        )

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
        det = self.detector
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
            "maneuver": det.flag if valid else False,
            "maneuver.statistic": det.d,
            "maneuver.threshold": det.threshold,
            "track.n": self.ab.n,
            "track.valid": valid,
            "coasting": coasting,
            "innovation.x": nu[0],
            "innovation.y": nu[1],
            "innovation.z": nu[2],
            "ddre.range": self.ddre_out[0],
            "ddre.smoothed": self.ddre_out[1],
            "ddre.predicted": self.ddre_out[2],
            "ddre.valid": self.ddre_out[3],
        }
