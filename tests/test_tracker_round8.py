"""Issue 14, round 8 (branch spd15): ``BeamTracker.step`` with ``outputs_flat``, the
background sum, the reading's angle variance, the seed-000 NIS test and the detector update,
and ``_limit_range_rate`` written out, ``fx.initialised`` read as ``fx.n > 0``: bit for bit
the former step (main 684be29, kept below verbatim as the reference) on random sequences of
inputs — modes acquisition → tentative → confirmed and back (drops), range-hypothesis jumps,
NaN/±inf beams, angles, offsets, gates and steps, weak and strong gate signals — for the
default tracker and for the other laws, filters and options; every output and the whole state
after every step. Session 16: the reference carries the session-16 rules (the hand-over's range
test, the speed bound before a coast) and session 12's option (the line-of-sight coast).
"""

from __future__ import annotations

import math
import pickle
import struct
from collections.abc import Mapping
from math import isfinite
from typing import Any

import numpy as np
import pytest

from axir.models.filters.alphabeta import update_axes
from axir.models.filters.gains import innovation_factor
from axir.models.radar.conventions import ACQUISITION, BIN_M, CONFIRMED
from axir.models.radar.geometry import cart_to_sph_and_diff, sph_to_cart_and_diff_cs, wrap_pi
from axir.models.tracker import Tracker
from axir.models.tracker.beams import HYPOTHESIS_JUMP_M, BeamTracker
from axir.models.tracker.cells import (
    _BACKGROUND_BINS,
    _C,
    _N_BACKGROUND,
    _cartesian_variances_cs,
    _early_late_corrected,
    background_sum,
    edge_reading,
)
from axir.models.tracker.deviations import dif_sum
from axir.models.tracker.initiation import (
    handover_mismatch,
    no_track_report,
    reading_angle_variance,
)
from axir.models.tracker.maneuver import axis_summary, nis_cs
from axir.models.tracker.outputs import GATE_CENTRE_M, MIN_COS_EL, ZERO3, outputs_flat

_asarray = np.asarray
_add_reduce = np.add.reduce


def _tracker(**params: Any) -> Tracker:
    """A Tracker for the twins of the former steps: session 29's ``beam_background`` rule
    (cells.bg_removed, tested in tests/test_tracker_beam_background.py) off, as the former
    steps predate it; every other parameter as given."""
    return Tracker(**{"beam_background": 0.0, **params})


class _FormerBeamTracker(BeamTracker):
    """The beams tracker with main 684be29's ``step`` (the reference of this module)."""

    def step(self, T: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """``BeamTracker.step`` of main 684be29, verbatim below this line (the reference).

        Written for speed (issue 14): locals instead of attribute look-ups, the gate and
        offset histories and the seed-000 3-D maneuver test inline, the sines and cosines of
        the measured direction computed once; the arithmetic is that of the helpers it
        replaces, operation for operation."""
        beams = _asarray(inputs["beam"], dtype=float)
        sums = _add_reduce(beams, 0)  # seed 000 eq. (1): SUM = B1 + B2 + B3 + B4 (= .sum(0))
        get = inputs.get
        mode = int(get("mode", ACQUISITION))
        az = float(inputs["ped.az"])
        el = float(inputs["ped.el"])
        offset = float(get("range.offset", 0.0))
        gate_cmd = float(get("gate.command", math.nan))
        t_ok = 0.0 < T < math.inf
        ped_ok = isfinite(az) and isfinite(el)
        if not isfinite(offset):
            offset = math.nan
        self._offset_in = offset_in = offset
        gh = self.gate_history
        if not isfinite(gate_cmd):
            gate_cmd = gh[-1] if gh else 0.0
        axes = self.axes
        fx = axes[0]
        if t_ok:
            self.time += T

        if mode <= ACQUISITION:
            # ---------------- acquisition: no track, position loop to the designation
            if self.mode != ACQUISITION or fx.initialised:
                self._lose_track(self.time - T if t_ok else self.time, T)
            self.mode = ACQUISITION
            self._hyp_gate = math.nan
            return self._designation_outputs(sums, (0.0, 0.0, 0.0, 0.0), ped_ok, az, el,
                                             gate_cmd, False, ZERO3)

        # ---------------- tentative / confirmed tracking (seed 000 steps 1-9)
        confirmed = mode >= CONFIRMED
        if confirmed and self.mode != CONFIRMED:  # issue 11: the tentative track is tested
            self._handover = self._start_handover(gate_cmd + offset)  # (session 16: range)
        self.mode = CONFIRMED if confirmed else mode
        # the gate (and the offset received with it) the current beams were formed with
        lat = self.gate_latency
        if len(gh) >= lat:
            gate_used = gh[-lat]
            if isfinite(offset):
                o = self.offset_history[-lat]
                if isfinite(o):
                    offset = o
        else:
            gate_used = gate_cmd
        # as _hypothesis_changed, inline (issue 14)
        prev = self._hyp_gate
        self._hyp_gate = true_gate = gate_used + offset
        if isfinite(prev) and abs(true_gate - prev) > HYPOTHESIS_JUMP_M and fx.initialised:
            self._reset_track()  # another range hypothesis: a new track (issue 11)
        # steps 1-2: gate cells, bins 6, 7, 8 (SYSTEM.md: tentative Σ filters, confirmed central)
        # assumption: angles from the strongest gate cell (bin 7 when centred, as the seed
        # reads it); a target straddling bins 7-8 during a range lag keeps usable angles and
        # the weak-signal check looks at the strongest of bins 6-8, not bin 7 alone.
        if confirmed:
            # issue 14, round 4: the gate cells' SUMs are the SUM column's (ΣB over axis 0
            # adds B1 + B2 + B3 + B4 in that order, as u + r + d + l: bit for bit, tested),
            # and only the strongest cell's four beams are read
            col = sums[:, 1]
            cl = col.tolist()
            s6, s7, s8 = cl[_C - 1], cl[_C], cl[_C + 1]
            if s8 > s7 and s8 >= s6:
                b, s_max = _C + 1, s8
            elif s6 > s7:
                b, s_max = _C - 1, s6
            else:
                b, s_max = _C, s7
            u7, r7, d7, l7 = beams[:, b, 1].tolist()
        else:  # as gate_cells(beams, central_only=False), without its call
            keep = [0, 1, 2]  # session 24: a side filter in clutter out of the Σ
            if self._tent_clutter > 0.0:
                bg = sums[_BACKGROUND_BINS].sum(axis=0)
                if bg.sum() < math.inf:
                    lo = bg.min() * self._tent_clutter
                    keep = [f for f in (0, 1, 2) if f == 1 or not bg[f] > lo]
            self._tent_m = len(keep)
            (u6, u7, u8), (r6, r7, r8), (d6, d7, d8), (l6, l7, l8) = _add_reduce(
                beams[:, _C - 1:_C + 2, :], 2).tolist()
            col = _add_reduce(sums, 1)  # = sums.sum(axis=1)
            cl = col.tolist()
            s6, s7, s8 = u6 + r6 + d6 + l6, u7 + r7 + d7 + l7, u8 + r8 + d8 + l8
            if s8 > s7 and s8 >= s6:
                u7, r7, d7, l7, s_max, self._tent_bin = u8, r8, d8, l8, s8, _C + 1
            elif s6 > s7:
                u7, r7, d7, l7, s_max, self._tent_bin = u6, r6, d6, l6, s6, _C - 1
            else:
                s_max, self._tent_bin = s7, _C
            # the angles (and the report's noise) from the kept filters only (session 24)
            u7, r7, d7, l7 = beams[:, self._tent_bin, keep].sum(axis=1).tolist()
            kept_col = sums[:, keep].sum(axis=1).tolist()
            self._tent_pairs = (u7 + d7, r7 + l7, kept_col)  # session 15: _tentative_direction's
            self._tent_edge_axes = (False, False)
        noise = background_sum(cl) / _N_BACKGROUND  # seed 000: background bins → noise level
        strong = s_max > self.min_snr * noise and s_max > 0.0  # False for NaN too
        dev_lat = dev_el = dev_az = dev_r = 0.0
        valid = False
        if strong and ped_ok and t_ok and isfinite(offset) and isfinite(gate_used):
            den_el, den_lat, den_r = u7 + d7, r7 + l7, s6 + s7 + s8
            if den_el > 0.0 and den_lat > 0.0 and den_r > 0.0:
                # SYSTEM.md ratios (deviations.py); dR = ε_R · 75 m (triangular response)
                if self.exact:
                    dev_el = self._angle(dif_sum(u7, d7))
                    dev_lat = self._angle(dif_sum(r7, l7))
                else:  # linear law: angle = ε/k_m (SYSTEM.md), as _angle; ε = dif_sum(…)
                    # written out (issue 14, round 3): (a − b)/(a + b), denominators > 0 above
                    k = self.inv_slope
                    dev_el = (u7 - d7) / den_el * k
                    dev_lat = (r7 - l7) / den_lat * k
                    if confirmed and self._edge_dev < math.inf:  # session 23 (its own test)
                        dev_el, dev_lat = edge_reading(u7, r7, d7, l7, noise, dev_el, dev_lat,
                                                       self._edge)
                    elif not confirmed and (abs(dev_el) > self._tent_edge_dev
                                            or abs(dev_lat) > self._tent_edge_dev):
                        # session 24 (its own test): the centre filter's cell at the edge
                        dev_el, dev_lat = self._tentative_edge(beams, sums, dev_el, dev_lat)
                if self.range_noise_correction:  # issue 11: the slope at low SNR
                    dev_r = _early_late_corrected(s6, s7, s8, noise) * BIN_M
                else:
                    # early_late(s6, s7, s8) written out: ε_R = (S8 − S6)/(S6 + S7 + S8)
                    dev_r = (s8 - s6) / den_r * BIN_M
                ce = ce_ped = math.cos(el)  # ce_ped: unclamped, for step 3 below
                if abs(ce) < MIN_COS_EL:
                    ce = math.copysign(MIN_COS_EL, ce)
                dev_az = dev_lat / ce  # seed 000: dAz = dLat/cos(El)
                valid = isfinite(dev_el) and isfinite(dev_lat) and isfinite(dev_r)
        if not valid:
            dev_lat = dev_el = dev_az = dev_r = 0.0
        if self.ddre is not None and isfinite(gate_used) and isfinite(offset):
            self._ddre_step(col, gate_used + offset)

        nu = ZERO3
        if valid:
            rho_g = gate_used + GATE_CENTRE_M + offset  # true gate-centre range (radar.py)
            # step 3: spherical deviations → Cartesian differentials (seed 000), and steps
            # 4-5: pedestal position (seed 000 "Spherical to Cartesian (in Position)"): as
            # sph_to_cart_diff and sph_to_cart, one call, one set of sines/cosines
            xa, ya, za, dx, dy, dz = sph_to_cart_and_diff_cs(
                rho_g, math.cos(az), math.sin(az), ce_ped, math.sin(el), dev_r, dev_az, dev_el)
            # step 6: Xm = Xa + dXm … (seed 000)
            zx, zy, zz = xa + dx, ya + dy, za + dz
            valid = isfinite(zx) and isfinite(zy) and isfinite(zz)
            if valid:
                # step 7: filtering per axis (seed 000: α-β with the manager's steady gains;
                # or the filter_x/y/z choice), measurement variances from the accuracies
                a_ss = float(get("alpha", 0.0))
                b_ss = float(get("beta", 0.0))
                m_az, m_el, m_rho = az + dev_az, el + dev_el, rho_g + dev_r
                ca, sa, ce, se = math.cos(m_az), math.sin(m_az), math.cos(m_el), math.sin(m_el)
                sr, sg = self.sigma_range, self.sigma_angle
                rx, ry, rz = _cartesian_variances_cs(m_rho, ca, sa, ce, se, sr, sg)
                if self.legacy_detector:  # α-β on X, Y, Z: one call, shared schedule
                    nu_x, nu_y, nu_z = update_axes(axes, (zx, zy, zz), T, (rx, ry, rz),
                                                   steady=(a_ss, b_ss))
                else:
                    for f in axes:
                        f.set_steady_gains(a_ss, b_ss)
                    nu_x, nu_y, nu_z = (axes[0].update(zx, T, rx), axes[1].update(zy, T, ry),
                                        axes[2].update(zz, T, rz))
                nu = (nu_x, nu_y, nu_z)
                # session 9: the angle information of the reading (its gate-cell SNR)
                var_k = reading_angle_variance(s_max / noise if noise > 0.0 else math.inf,
                                               self.inv_slope)
                j_k = self._indep / var_k if var_k > 0.0 else math.inf
                self._info += j_k
                if self._handover and confirmed and self.legacy_detector:
                    self._handover = False
                    if handover_mismatch(nu, (ca, sa, ce, se), m_rho, sr, sg, fx,
                                         self.confirm_reinit_nis):
                        for f, z in zip(axes, (zx, zy, zz), strict=True):
                            f.pos = z  # re-centred on the confirmed cells' reading
                        # the direction is now that one reading's: reported once known again
                        # (session 13: unless a known direction was re-centred on an
                        # accurate reading, _recentred_info)
                        self._info = self._recentred_info(j_k)
                if self.legacy_detector and fx.n >= 3:
                    det = self.detector
                    # fx.innovation_factor(), without the method's own call
                    det.innovation(nis_cs(nu, ca, sa, ce, se, m_rho, sr, sg,
                                          innovation_factor(fx.alpha, fx.beta, fx.evolutive)))
                    det.decide()
        if not valid and fx.initialised and t_ok:
            if not confirmed and self.tentative_radial_coast:  # session 12 (an option)
                self._radial_velocity()
            self._limit_speed()  # never coast on a velocity no target can have (session 16:
            for f in axes:  # bounded before the coast)
                f.coast(T)  # prediction only (no measurement enters the state)
        elif confirmed and valid and self._vel_axes:
            self._limit_range_rate()  # issue 11: a confirmed track's gate moves ≤ max_speed

        if not fx.initialised:
            # no track yet: keep pointing at the designation, gate from the manager
            return self._designation_outputs(sums, (dev_az, dev_el, dev_lat, dev_r), ped_ok,
                                             az, el, gate_cmd, not valid, nu, hypothesis=True)

        # step 8: smoothed velocity → angle rates + pointing correction → command voltages
        fy, fz = axes[1], axes[2]
        legacy = self.legacy_detector
        if legacy:  # α-β axes: x = (pos, vel, 0), P = (p11, p12, p22) (CVEstimate), read direct
            px, vx, py, vy, pz, vz = fx.pos, fx.vel, fy.pos, fy.vel, fz.pos, fz.vel
            ax = ay = az_ = 0.0
        else:
            (px, vx, ax), (py, vy, ay), (pz, vz, az_) = fx.x, fy.x, fz.x
        # as cart_to_sph and cart_to_sph_diff (rates 0 at the zenith or at the antenna)
        rng, t_az, t_el, rdot, az_rate, el_rate = cart_to_sph_and_diff(px, py, pz, vx, vy, vz)
        if ped_ok:
            kp = self.pointing_gain
            w_az = az_rate + kp * wrap_pi(t_az - az)
            w_el = el_rate + kp * (t_el - el)
        else:
            w_az, w_el = az_rate, el_rate
        # as _cmd on each, inline (issue 14): rate → voltage, clipped to ±cmd_limit, 0 if not
        # finite
        rpv, lim = self.rate_per_volt, self.cmd_limit
        if isfinite(w_az):
            v = w_az / rpv
            cmd_az = lim if v > lim else (-lim if v < -lim else v)
        else:
            cmd_az = 0.0
        if isfinite(w_el):
            v = w_el / rpv
            cmd_el = lim if v > lim else (-lim if v < -lim else v)
        else:
            cmd_el = 0.0
        # step 9 and gate: predicted range one step ahead places the gate in confirmed mode
        if confirmed and isfinite(offset):
            tp = T if t_ok else 0.0
            if legacy:  # CVEstimate.predict's position, pos + T·vel, from the values read above
                qx, qy, qz = px + tp * vx, py + tp * vy, pz + tp * vz
            else:
                qx, qy, qz = fx.predict(tp)[0], fy.predict(tp)[0], fz.predict(tp)[0]
            # the gate stays in the instrumented range [0, max_range] (issue 11)
            r_pred = min(max(math.sqrt(qx * qx + qy * qy + qz * qz), GATE_CENTRE_M),
                         self.max_range)
            gate = r_pred - offset_in - GATE_CENTRE_M
        else:
            gate = gate_cmd
        gh.append(gate)  # as _push_gate, inline
        self.offset_history.append(offset_in)
        # line-of-sight projection of the Cartesian estimates (axes independent: the covariance
        # is block-diagonal over X, Y, Z; first order, unit vector u held fixed)
        inv = 1.0 / rng if rng > 0.0 else 0.0
        ux, uy, uz = px * inv, py * inv, pz * inv
        wx, wy, wz = ux * ux, uy * uy, uz * uz
        if legacy:
            a0, b0, c0, a1, b1, c1 = fx.p11, fx.p12, fx.p22, fy.p11, fy.p12, fy.p22
            a2, b2, c2 = fz.p11, fz.p12, fz.p22
        else:
            (a0, b0, c0), (a1, b1, c1), (a2, b2, c2) = fx.P, fy.P, fz.P
        p_rr = 0.0 + wx * a0 + wy * a1 + wz * a2  # summed from 0.0 in axis order, as before
        p_rv = 0.0 + wx * b0 + wy * b1 + wz * b2
        p_vv = 0.0 + wx * c0 + wy * c1 + wz * c2
        if legacy:  # as _maneuver
            det = self.detector
            flag, stat, thr = det.flag, det.L, det.i1
        else:
            flag, stat, thr = axis_summary(axes)
        # issue 11, track initiation: a confirmed track of track_init_n measurements is
        # reported; in tentative (the manager tests a hypothesis; the track only steers the
        # antenna) and before, the report is where the radar looks. track.x… stay the
        # filter's state (seed 000's gain law is measured from them)
        established = confirmed and fx.n >= self.track_init_n
        if not established:
            y_az, y_el = t_az, t_el
            rng, t_az, t_el = no_track_report(self.designation, gate_cmd + offset_in, az, el,
                                              ped_ok)
            rdot = 0.0
            if ped_ok and self._tent_report:  # session 12-13 options (tentative_known_direction)
                t_az, t_el = self._tentative_direction(y_az, y_el, az, el, valid)
        elif self._info < self._info_req:
            # session 9: range and range rate known, the direction not yet (angle
            # information): the angles are where the antenna looks
            established = False
            if ped_ok:
                t_az, t_el = az % (2.0 * math.pi), el
        elif ped_ok and self._invert:  # session 14: report_inverts_pattern (on by default)
            t_az, t_el = self._inverted(t_az, t_el, az, el)
        return outputs_flat(
            sums, dev_az, dev_el, dev_lat, dev_r, px, py, pz, vx, vy, vz, rng, rdot, t_az,
            t_el, cmd_az, cmd_el, gate, flag, stat, thr, fx.n, established, not valid, nu[0], nu[1],
            nu[2], self.ddre_out, ux * ax + uy * ay + uz * az_, ax, ay, az_, p_rr, p_rv, p_vv,
        )


def _bits(v: Any) -> Any:
    """A value as its exact bits: floats by their IEEE bytes (NaN payload, −0.0), arrays by
    dtype, shape and bytes, the rest by type and value."""
    if isinstance(v, np.ndarray):
        return ("nd", v.dtype.str, v.shape, v.tobytes())
    if type(v) is float:
        return ("f", struct.pack("<d", v))
    return (type(v).__name__, v)


def _state(core: BeamTracker) -> bytes:
    """The tracker's whole state (axes, detectors, histories, counters) as pickle bytes:
    floats pickled by their 8 bytes."""
    return pickle.dumps(core.__dict__, protocol=4)


def _inputs(rng: np.random.Generator, k: int, mode: int, gate: float, offset: float,
            az: float, el: float, strong: bool) -> dict[str, Any]:
    beams = rng.exponential(1.0, (4, 16, 3))
    if strong:
        beams[:, 5:8, :] += rng.uniform(2.0, 60.0, (4, 3, 3))
    u = rng.random()
    if u < 0.03:  # a non-finite beam cell somewhere (the gate cells or the background)
        beams[rng.integers(4), rng.integers(16), rng.integers(3)] = rng.choice(
            [math.nan, math.inf, -math.inf])
    elif u < 0.05:
        beams[:, 6, :] = 0.0  # a zero gate cell (denominators 0)
    elif u < 0.15:  # clutter in a side filter, stronger in one beam (session 24)
        beams[:, :, rng.choice([0, 2])] += rng.uniform(0.5, 8.0, (4, 1))
    inp: dict[str, Any] = {"beam": beams, "ped.az": az, "ped.el": el, "mode": mode,
                           "range.offset": offset, "gate.command": gate}
    if rng.random() < 0.8:
        inp["alpha"], inp["beta"] = rng.choice([(0.0, 0.0), (0.3, 0.05), (0.9, 0.6), (0.05,
                                                                                      0.001)])
    return inp


def _poison(rng: np.random.Generator, inp: dict[str, Any]) -> None:
    """NaN/±inf in one scalar input, now and then."""
    if rng.random() < 0.04:
        key = rng.choice(["ped.az", "ped.el", "range.offset", "gate.command"])
        inp[key] = rng.choice([math.nan, math.inf, -math.inf])


CASES = [
    {},  # the default tracker
    {"track_init_n": 3, "init_angle_sigma": 0.0},
    {"track_init_n": 2, "confirm_reinit_nis": 0.0, "gate_latency": 2},
    {"monopulse_law": "exact", "range_noise_correction": False, "track_init_n": 4},
    {"confirm_reinit_nis": 1e-3, "max_speed": 30.0, "track_init_n": 3},
    {"filter_x": "kalman", "filter_y": "kalman", "filter_z": "kalman", "track_init_n": 3},
    {"ddre_window": 4, "track_init_n": 3},
    {"min_snr": 0.5, "track_init_n": 3},  # readings at the SNR floor of the angle variance
]


@pytest.mark.parametrize("params", CASES)
def test_step_written_out_equals_the_former_step_bit_for_bit(params: dict[str, Any]) -> None:
    """Twin trackers, one with the former step, fed the same inputs: the same output mapping
    (keys, order, bits of every value) and the same state after every step; the paths of
    interest were taken (confirmed with a valid reading, coasting, drops, hypothesis jumps,
    an established report and the range-rate limit active)."""
    rng = np.random.default_rng(sum(map(ord, repr(params))))
    new = _tracker(**params)
    old = _tracker(**params)
    old.core.__class__ = _FormerBeamTracker
    # a step of 1e-300 s (gains of 1e300/s: overflowing states, non-finite NIS) for the α-β
    # axes; the Kalman axes' own update divides by zero there, before and after alike
    t_odd = [0.0, math.nan, math.inf, 2e-4] + ([] if "filter_x" in params else [1e-300])
    seen = {"confirmed_valid": 0, "coasting": 0, "drops": 0, "established": 0, "jumps": 0}
    used = {"clutter_out": 0, "tent_edge": 0}
    mode, gate, offset, az, el = ACQUISITION, 5000.0, 0.0, 1.0, 0.2
    for k in range(3000):
        r = rng.random()
        if r < 0.01 and mode > ACQUISITION:
            mode = ACQUISITION
            seen["drops"] += 1
        elif r < 0.04:
            mode = min(mode + 1, CONFIRMED)
        elif r < 0.045:
            mode = 1
        if rng.random() < 0.01:
            gate += rng.choice([-1.0, 1.0]) * rng.uniform(2.5 * BIN_M, 3e3)
            seen["jumps"] += 1
        else:
            gate += rng.normal(0.0, 3.0)
        if rng.random() < 0.005:
            offset = float(rng.choice([0.0, 750.0, 1500.0]))
        az = (az + rng.normal(0.0, 1e-3)) % (2 * math.pi)
        el = float(np.clip(el + rng.normal(0.0, 1e-3), -0.2, 1.5707))
        inp = _inputs(rng, k, mode, gate, offset, az, el, strong=rng.random() < 0.85)
        _poison(rng, inp)
        T = 1e-4 if rng.random() < 0.97 else float(rng.choice(t_odd))
        o_old = old.core.step(T, inp)
        o_new = new.core.step(T, inp)
        assert list(o_new) == list(o_old)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _state(new.core) == _state(old.core), k
        if mode == CONFIRMED and not o_new["coasting"] and o_new["track.n"] > 0:
            seen["confirmed_valid"] += 1
        seen["coasting"] += bool(o_new["coasting"] and o_new["track.n"] > 0)
        seen["established"] += bool(o_new["track.valid"])
        if mode == 1 and not o_new["coasting"]:  # session 24's tentative cells
            used["clutter_out"] += new.core._tent_m < 3
            used["tent_edge"] += any(new.core._tent_edge_axes)
    assert min(seen.values()) > 0, seen
    if not params:  # the default tracker (linear law) takes both
        assert min(used.values()) > 0, used


def test_limit_range_rate_written_out_is_active_and_equal() -> None:
    """The written-out range-rate limit: with a low max_speed it moves the velocity (the
    excess branch) on most confirmed updates, and the step still equals the former one."""
    rng = np.random.default_rng(5)
    new, old = _tracker(max_speed=5.0, track_init_n=2), _tracker(max_speed=5.0, track_init_n=2)
    old.core.__class__ = _FormerBeamTracker
    moved = 0
    for k in range(600):
        mode = 1 if k < 20 else CONFIRMED
        inp = _inputs(rng, k, mode, 8000.0 + 0.01 * k, 0.0, 0.5, 0.1, strong=True)
        o_old, o_new = old.core.step(1e-4, inp), new.core.step(1e-4, inp)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()]
        assert _state(new.core) == _state(old.core)
        fx, fy, fz = new.core.axes
        p = np.array([fx.pos, fy.pos, fz.pos])
        v = np.array([fx.vel, fy.vel, fz.vel])
        moved += mode == CONFIRMED and abs(p @ v / np.linalg.norm(p)) > 4.99
    assert moved > 100


@pytest.mark.parametrize("pos", [
    (0.0, 0.0, 0.0), (0.0, 0.0, 5e3), (0.0, 0.0, -5e3), (1e9, 0.0, 0.0), (100.0, 50.0, 0.0),
    (-3e3, 4e3, 1e3), (math.nan, 0.0, 0.0), (math.inf, 1.0, 1.0), (0.0, -math.inf, 0.0),
])
@pytest.mark.parametrize("vel", [(0.0, 0.0, 0.0), (10.0, -20.0, 5.0), (0.0, 0.0, math.nan)])
def test_step_equals_the_former_step_at_edge_track_states(pos: tuple, vel: tuple) -> None:
    """A track set at the antenna, on the vertical axis (the angle rates' division by zero),
    below the gate's minimum and beyond the maximum range, or not finite; then weak (coasting)
    and strong readings, tentative and confirmed: outputs and state as the former step's."""
    rng = np.random.default_rng(17)
    new, old = _tracker(track_init_n=2), _tracker(track_init_n=2)
    old.core.__class__ = _FormerBeamTracker
    steps = [(1, True)] * 10 + [(CONFIRMED, True)] * 10
    for k, (mode, strong) in enumerate(steps):
        inp = _inputs(rng, k, mode, 6000.0, 0.0, 0.3, 0.2, strong=strong)
        old.core.step(1e-4, inp), new.core.step(1e-4, inp)
    for core in (new.core, old.core):
        for f, p, v in zip(core.axes, pos, vel, strict=True):
            f.pos, f.vel = p, v
    for k, (mode, strong) in enumerate([(CONFIRMED, False), (CONFIRMED, False), (1, False),
                                         (CONFIRMED, True), (1, True), (CONFIRMED, False)]):
        inp = _inputs(rng, k, mode, 6000.0, 0.0, 0.3, 0.2, strong=strong)
        if k == 1:
            inp["beam"][:, 5:8, :] = 0.0  # no signal at all: early/late of zero cells
        o_old, o_new = old.core.step(1e-4, inp), new.core.step(1e-4, inp)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _state(new.core) == _state(old.core), k


def _step_or_error(core: BeamTracker, T: float, inp: dict[str, Any]) -> Any:
    try:
        return [_bits(v) for v in core.step(T, inp).values()]
    except (OverflowError, ValueError, ZeroDivisionError) as e:  # the same, before and after
        return type(e).__name__


def test_screening_by_one_sum_equals_the_one_by_one_rule_with_overflowing_sums() -> None:
    """The pedestal angles, range offset and gate command screened by one isfinite of their
    sum (round 8): finite values whose sum overflows (±1e308, 1.7e308), NaN and ±inf in every
    position, tentative and confirmed, on a track: outputs (or the exception raised, before
    and after alike) and state as the former step's."""
    import itertools

    values = [1e308, -1e308, 1.7e308, 0.3, 2e3, math.nan, math.inf, -math.inf]
    rng = np.random.default_rng(3)
    k = 0
    for az, el, off, gate in itertools.product(values[:4] + values[5:6], repeat=4):
        k += 1
        if k % 3 and not (off == gate == 1e308):
            continue  # a third of the 625 combinations, and the non-finite ones below
        new, old = _tracker(track_init_n=2), _tracker(track_init_n=2)
        old.core.__class__ = _FormerBeamTracker
        for j in range(8):
            inp = _inputs(rng, j, 1 if j < 4 else CONFIRMED, 6000.0, 0.0, 0.3, 0.2, True)
            old.core.step(1e-4, inp), new.core.step(1e-4, inp)
        for mode in (CONFIRMED, 1, 1):  # twice tentative: the gate used is the command's
            inp = _inputs(rng, 0, mode, gate, off, az, el, True)
            assert _step_or_error(new.core, 1e-4, inp) == _step_or_error(old.core, 1e-4, inp)
            assert _state(new.core) == _state(old.core)
    for bad in values[5:]:
        for key in ("ped.az", "ped.el", "range.offset", "gate.command"):
            new, old = _tracker(), _tracker()
            old.core.__class__ = _FormerBeamTracker
            for j in range(6):
                inp = _inputs(rng, j, min(j, CONFIRMED), 6000.0, 1e308, 1e308, 0.2, True)
                inp[key] = bad
                assert _step_or_error(new.core, 1e-4, inp) == _step_or_error(old.core, 1e-4,
                                                                             inp)
                assert _state(new.core) == _state(old.core)


def test_isfinite_of_a_sum_or_each_is_isfinite_of_each() -> None:
    """The rule the step's screens use: isfinite(a + b + c) or (isfinite(a) and isfinite(b)
    and isfinite(c)) is isfinite(a) and isfinite(b) and isfinite(c), on every triple of edge
    values (overflowing sums, cancelling infinities, NaN, signed zeros, subnormals)."""
    import itertools

    edge = [0.0, -0.0, 5e-324, 1.0, -2.5, 1e308, -1e308, 1.7976931348623157e308, math.inf,
            -math.inf, math.nan]
    for a, b, c in itertools.product(edge, repeat=3):
        each = isfinite(a) and isfinite(b) and isfinite(c)
        assert (isfinite(a + b + c) or (isfinite(a) and isfinite(b) and isfinite(c))) is each
        assert (isfinite(a + b) or (isfinite(a) and isfinite(b))) is (isfinite(a)
                                                                      and isfinite(b))
