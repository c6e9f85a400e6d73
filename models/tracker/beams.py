"""The seed-000 tracker on the monopulse beams (``input_mode = "beams"``, the default).

One :meth:`BeamTracker.step` per PRI:

- mode 0: no track (filters reset). The pedestal is driven toward the designation
  (az, el) by the position loop ω = K·(designation − pedestal angle); ``gate.start`` =
  ``gate.command``. Track outputs report the designation (velocity 0, ``track.valid`` false).
- mode 1/2: the seed's nine steps ("General Algorithm for Tracking"):
  1-2) deviations from the gate cells (bins 6, 7, 8; tentative: Σ over the 3 Doppler filters,
  confirmed: central filter only; SYSTEM.md), angle = ε/k_m (linear law; beyond the edge:
  :func:`.cells.edge_reading`) or atanh(ε)/k_m, dAz = dLat/cos(El), dR = ε_R·75 m;
  3) (dAz, dEl, dR) → (dXm, dYm, dZm) with the total differences (geometry.sph_to_cart_diff);
  4-5) pedestal angles and gate-centre range → (Xa, Ya, Za); the gate-centre range is the
  gate start used for these beams + 6·75 m + ``range.offset``;
  6) Xm = Xa + dXm …; 7) filtering per axis (α-β: filters.alphabeta.AlphaBetaAxis, the seed's
  equations with the manager's steady gains, or the ``filter_x/y/z`` choice), measurement
  variances from ``sigma_range`` and ``sigma_angle`` (diagonal of the Cartesian measurement
  covariance);
  8) smoothed velocity → angle rates (geometry.cart_to_sph_diff) plus a pointing correction
  toward the filtered position, rate-command law ω_cmd = ω_track + K·wrap(angle_track −
  angle_pedestal), cmd = ω_cmd / rate_per_volt [V] (clipped to ±cmd_limit);
  9) filtered (ρ, Az, El) out for the manager; predicted range → gate: in mode 1 the gate
  follows ``gate.command``; in mode 2 the tracker places it itself at the range predicted one
  step ahead, gate.start = R_pred − range.offset − 6·75 m (apparent range; the generator folds).
- Filters initialised on the first usable measurement after the mode becomes ≥ 1 (n = 1), reset
  when it returns to 0. Issue 11 (:mod:`.initiation`): the spherical report waits for a
  confirmed track of ``track_init_n`` measurements; the tentative track is re-centred on a
  first confirmed measurement whose NIS exceeds ``confirm_reinit_nis``.
- Robustness: NaN/Inf beams, angles, offsets or gate, or a gate signal not above the noise
  (strongest gate-cell SUM of bins 6-8 ≤ min_snr × mean SUM of the background bins 1-4, 10-16),
  never enter the filter: the tracker coasts on prediction (``coasting``); outputs stay finite.
- Maneuver: α-β on the three axes (default): the seed-000 3-D NIS test (:mod:`.maneuver`), else
  per-axis detectors. DDRE (seed 001, ``ddre_window`` > 0): the SUM range profile.
- Latency: the beams received were formed with the gate output ``gate_latency`` steps earlier
  (1: Gauss-Seidel, the generator stepped just before the tracker; 2: Jacobi). Pedestal angles
  are used as received (rate × PRI ≪ beam).
"""

from __future__ import annotations

from collections.abc import Mapping
from math import atan2, copysign, cos, hypot, inf, isfinite, nan, pi, sin, sqrt
from typing import Any

import numpy as np

from ..filters.alphabeta import steady_all, update_xyz
from ..filters.gains import prior_q, scheduled_gains
from ..filters.kalman import q_cwna
from ..radar.conventions import ACQUISITION, BIN_M, CONFIRMED
from ..radar.geometry import TWO_PI
from .beam_helpers import HYPOTHESIS_JUMP_M, BeamHelpers
from .cells import _C, _N_BACKGROUND, _NOISE_POWER_RATIO, bg_removed, edge_reading
from .deviations import dif_sum, early_late
from .initiation import _RAYLEIGH_POWER, SNR_FLOOR, handover_mismatch, no_track_report
from .maneuver import axis_summary
from .outputs import _TEMPLATE, GATE_CENTRE_M, MIN_COS_EL, NO_DDRE, TEMPLATE_ND, ZERO3

_asarray = np.asarray
#: the gate cells, bins 6, 7, 8 (indices _C − 1 … _C + 1): their slice and the outer indices
_GATE_CELLS = slice(_C - 1, _C + 2)
_C6, _C8 = _C - 1, _C + 1
_add_reduce = np.add.reduce
_new_outputs = _TEMPLATE.copy  # the output mapping: a copy of the template filled in place
_new_outputs_nd = TEMPLATE_ND.copy  # the same with the α-β axes' values without DDRE
#: (σm·s, T, Q11, Q12, Q22) of the written-out three-axis update's last Q (filters.alphabeta)
_q_last: tuple[float, float, float, float, float] = (nan, nan, 0.0, 0.0, 0.0)

__all__ = ["HYPOTHESIS_JUMP_M", "BeamTracker"]


class BeamTracker(BeamHelpers):
    """State and step of the beams input mode (module docstring).

    Args:
        p: the Tracker's parameters (attributes named as in ``Tracker.PARAMS``).
        cfg: tuning of the axis filters.
    """

    #: step(T, None, beam, …, gate_command, doppler_rate, doppler_ok): the run loop's call
    STEP_ARGS = ("beam", "ped.az", "ped.el", "mode", "alpha", "beta", "range.offset",
                 "gate.command", "doppler.range_rate", "doppler.resolved")

    def step(self, T: float, inputs: Mapping[str, Any] | None, beam: Any = ...,
             ped_az: Any = ..., ped_el: Any = ..., mode_in: Any = ..., alpha: Any = ...,
             beta: Any = ..., range_offset: Any = ..., gate_command: Any = ...,
             doppler_rate: Any = ..., doppler_ok: Any = ...) -> dict[str, Any]:
        """Advance one PRI of T [s]; keys and units: :data:`~.ports.INPUTS`/``OUTPUTS``;
        ``inputs`` None: the inputs are the next arguments (:data:`STEP_ARGS`; ``...``: TypeError).

        Written for speed (issue 14): locals instead of attribute look-ups, the gate and
        offset histories and the seed-000 3-D maneuver test inline, the sines and cosines of
        the measured direction computed once; the arithmetic is that of the helpers it
        replaces, operation for operation."""
        if inputs is not None:  # a mapping: its values read as the positional call has them
            beam = inputs["beam"]
        beams = _asarray(beam, float)  # dtype positional: no keyword parsing
        sums = _add_reduce(beams, 0)  # seed 000 eq. (1): SUM = B1 + B2 + B3 + B4 (= .sum(0))
        try:  # a dict holding every input: subscripts, no get calls (issue 14, round 9)
            if inputs is not None:
                if type(inputs) is not dict:
                    raise KeyError
                mode_in = inputs["mode"]
                ped_az = inputs["ped.az"]
                ped_el = inputs["ped.el"]
                range_offset = inputs["range.offset"]
                gate_command = inputs["gate.command"]
                alpha, beta = inputs["alpha"], inputs["beta"]
                doppler_rate, doppler_ok = inputs["doppler.range_rate"], inputs["doppler.resolved"]
            mode = int(mode_in)
            az = float(ped_az)
            el = float(ped_el)
            offset = float(range_offset)
            gate_cmd = float(gate_command)
            alpha_in, beta_in = alpha, beta  # converted where used
        except KeyError:  # another Mapping or a key missing: the same, with the defaults
            if inputs is None:  # (only a mapping's read raises it)
                raise
            (mode, az, el, offset, gate_cmd, alpha_in, beta_in, doppler_rate,
             doppler_ok) = self._mapping_inputs(inputs)
        t_ok = 0.0 < T < inf
        gh = self.gate_history
        # screened by one isfinite of their sum (issue 14, round 8): a NaN or ±inf makes it
        # non-finite; an overflowing sum of finite values takes the one-by-one rule (the same)
        if isfinite(az + el + offset + gate_cmd):
            ped_ok = True
        else:
            ped_ok = isfinite(az) and isfinite(el)
            if not isfinite(offset):
                offset = nan
            if not isfinite(gate_cmd):
                gate_cmd = gh[-1] if gh else 0.0
        self._offset_in = offset_in = offset
        axes = self.axes
        fx, fy, fz = axes
        if t_ok:
            self.time += T

        if mode <= ACQUISITION:
            # ---------------- acquisition: no track, position loop to the look direction
            if self.mode != ACQUISITION or fx.n > 0:
                # a lost confirmed track is looked for where it went; its state is the one
                self._lose_track(self.time - T if t_ok else self.time, T)  # last step's
            self.mode = ACQUISITION
            self._hyp_gate = nan
            return self._designation_outputs(sums, (0.0, 0.0, 0.0, 0.0), ped_ok, az, el,
                                             gate_cmd, False, ZERO3)

        # ---------------- tentative / confirmed tracking (seed 000 steps 1-9)
        confirmed = mode >= CONFIRMED
        legacy = self.legacy_detector
        if self.mode != CONFIRMED and confirmed:  # issue 11: the tentative track is tested
            self._handover = self._start_handover(gate_cmd + offset)  # (and its range: s16)
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
        # as _hypothesis_changed, inline (issue 14; round 10: the jump first, False for NaN)
        prev = self._hyp_gate
        self._hyp_gate = true_gate = gate_used + offset
        if abs(true_gate - prev) > HYPOTHESIS_JUMP_M and isfinite(prev) and fx.n > 0:
            self._reset_track()  # another range hypothesis: a new track (issue 11)
        # steps 1-2: gate cells, bins 6, 7, 8 (SYSTEM.md: tentative Σ filters, confirmed
        # central); assumption: angles from the strongest gate cell (bin 7 when centred, as the
        # seed reads it): a target straddling bins 7-8 keeps usable angles (and a strong cell)
        if confirmed:
            # issue 14, round 4: the gate cells' SUMs are the SUM column's (ΣB over axis 0 adds
            # B1 + B2 + B3 + B4 as u + r + d + l: bit for bit), the strongest cell's beams read
            col = sums[:, 1]
            cl = col.tolist()
            s6, s7, s8 = cl[_GATE_CELLS]  # cl[_C - 1], cl[_C], cl[_C + 1] (round 10)
            if s8 > s7 and s8 >= s6:
                b, s_max = _C8, s8
            elif s6 > s7:
                b, s_max = _C6, s6
            else:
                b, s_max = _C, s7
            u7, r7, d7, l7 = beams[:, b, 1].tolist()
            if self._beam_bg:  # session 29: the elevation pair's own backgrounds removed
                u7, d7 = bg_removed(beams, u7, d7, self._beam_bg, self._bg_ema, self._bg_pole)
        else:  # Σ over the Doppler filters (round 11: moved into BeamHelpers, tentative only)
            u7, r7, d7, l7, s6, s7, s8, s_max, col, cl = self._tentative_cells(beams, sums)
        # seed 000: background bins → noise level; cells.background_sum(cl) written out
        # (numpy's pairwise order over bins 1-4, 10-16, bit for bit; issue 14, round 8)
        noise = (((((cl[0] + cl[1]) + (cl[2] + cl[3])) + ((cl[9] + cl[10]) + (cl[11] + cl[12])))
                  + cl[13] + cl[14] + cl[15]) / _N_BACKGROUND)
        strong = s_max > self.min_snr * noise and s_max > 0.0  # False for NaN too
        if confirmed and fx.n > 0 and self._notch(axes, doppler_rate if doppler_ok else nan, el, T):
            strong = False  # session 30: in the clutter notch the readings are clutter's
        dev_lat = dev_el = dev_az = dev_r = 0.0
        valid = False
        # (isfinite(a + b) or …: as isfinite(a) and isfinite(b), one call when finite)
        if strong and ped_ok and t_ok and (isfinite(offset + gate_used) or (
                isfinite(offset) and isfinite(gate_used))):
            den_el, den_lat, den_r = u7 + d7, r7 + l7, s6 + s7 + s8
            if den_el > 0.0 and den_lat > 0.0 and den_r > 0.0:
                # SYSTEM.md ratios (deviations.py); dR = ε_R · 75 m (triangular response)
                if self.exact:
                    dev_el = self._angle(dif_sum(u7, d7))
                    dev_lat = self._angle(dif_sum(r7, l7))
                else:  # linear law ε/k_m (SYSTEM.md); dif_sum written out (issue 14, round 3)
                    k = self.inv_slope
                    dev_el = (u7 - d7) / den_el * k
                    dev_lat = (r7 - l7) / den_lat * k
                    e = self._edge_dev if confirmed else self._tent_edge_dev  # sessions 23-24
                    if dev_el > e or dev_el < -e or dev_lat > e or dev_lat < -e:
                        dev_el, dev_lat = (edge_reading(u7, r7, d7, l7, noise, dev_el, dev_lat,
                                           self._edge) if confirmed else
                                           self._tentative_edge(beams, sums, dev_el, dev_lat))
                if self.range_noise_correction:  # issue 11: the slope at low SNR
                    # cells._early_late_corrected(s6, s7, s8, noise) written out (round 8)
                    n2 = _NOISE_POWER_RATIO * noise * noise
                    a6, a7, a8 = s6 * s6 - n2, s7 * s7 - n2, s8 * s8 - n2
                    c6 = sqrt(a6) if a6 > 0.0 else 0.0
                    c7 = sqrt(a7) if a7 > 0.0 else 0.0
                    c8 = sqrt(a8) if a8 > 0.0 else 0.0
                    den = c6 + c7 + c8
                    if den > 0.0 and den < inf:
                        dev_r = (c8 - c6) / den * BIN_M
                    else:
                        dev_r = early_late(s6, s7, s8) * BIN_M
                else:
                    # early_late(s6, s7, s8) written out: ε_R = (S8 − S6)/(S6 + S7 + S8)
                    dev_r = (s8 - s6) / den_r * BIN_M
                ce = ce_ped = cos(el)  # ce_ped: unclamped, for step 3 below
                if abs(ce) < MIN_COS_EL:
                    ce = copysign(MIN_COS_EL, ce)
                dev_az = dev_lat / ce  # seed 000: dAz = dLat/cos(El)
                valid = isfinite(dev_el + dev_lat + dev_r) or (
                    isfinite(dev_el) and isfinite(dev_lat) and isfinite(dev_r))
        if not valid:
            dev_lat = dev_el = dev_az = dev_r = 0.0
        if self.ddre is not None and isfinite(gate_used) and isfinite(offset):
            self._ddre_step(col, gate_used + offset)

        nu = ZERO3
        if valid:
            rho_g = gate_used + GATE_CENTRE_M + offset  # true gate-centre range (radar.py)
            # step 3: spherical deviations → Cartesian differentials (seed 000), and steps
            # 4-5: pedestal position (seed 000 "Spherical to Cartesian (in Position)"): as
            # sph_to_cart_diff and sph_to_cart, one set of sines/cosines
            # (geometry.sph_to_cart_and_diff_cs written out, issue 14, round 8)
            c_az, s_az, s_el = cos(az), sin(az), sin(el)
            rc = rho_g * ce_ped
            xa, ya, za = rc * s_az, rc * c_az, rho_g * s_el  # step 6: Xm = Xa + dXm (seed 000)
            zx = xa + (ce_ped * s_az * dev_r - za * s_az * dev_el + ya * dev_az)
            zy = ya + (ce_ped * c_az * dev_r - za * c_az * dev_el - xa * dev_az)
            zz = za + (s_el * dev_r + rc * dev_el)
            valid = isfinite(zx + zy + zz) or (isfinite(zx) and isfinite(zy) and isfinite(zz))
            if valid:
                # step 7: filtering per axis (seed 000: α-β with the manager's steady gains;
                # or the filter_x/y/z choice), measurement variances from the accuracies
                a_ss = float(alpha_in)  # the manager's steady gains, read above
                b_ss = float(beta_in)
                m_az, m_el, m_rho = az + dev_az, el + dev_el, rho_g + dev_r
                ca = cos(m_az)  # (one assignment a value: no tuple, round 10)
                sa = sin(m_az)
                ce = cos(m_el)
                se = sin(m_el)
                sr, sg = self.sigma_range, self.sigma_angle
                # cells._cartesian_variances_cs(m_rho, ca, sa, ce, se, sr, sg) written out
                sr2 = sr * sr
                sc2 = (m_rho * sg) ** 2
                rx = (ce * sa) ** 2 * sr2 + (ca * ca + (se * sa) ** 2) * sc2
                ry = (ce * ca) ** 2 * sr2 + (sa * sa + (se * ca) ** 2) * sc2
                rz = se * se * sr2 + ce * ce * sc2
                if legacy:  # the key of update_xyz's three-axis case (per-axis priors:
                    n_ax = fx.n  # once the steady gains hold on every axis, session 28)
                    cfg = fx.cfg
                    st = fx._steady
                    three = (n_ax and fy.n == n_ax and fz.n == n_ax and fy.cfg is cfg
                             and fz.cfg is cfg and not cfg.auto_gains and (
                                 (fy._steady is st and fz._steady is st and not cfg.vel_prior_r)
                                 or steady_all(st, fy._steady, fz._steady, a_ss, b_ss)))
                if legacy and not three:
                    nu_x, nu_y, nu_z = update_xyz(fx, fy, fz, zx, zy, zz, T, rx, ry, rz,
                                                  a_ss, b_ss)  # its general path (round 8)
                elif legacy:
                    # α-β on X, Y, Z sharing the key of update_xyz's three-axis case (config,
                    # n ≥ 1, the steady-gain tuple): that case written out (issue 14, round 9:
                    # no call), the same operations; filters/alphabeta.py documents them
                    global _q_last
                    if st is not None and st == (a_ss, b_ss):  # the steady gains hold (and
                        ga, gb = a_ss, b_ss  # were set as α_ss, β_ss when st was: session 17)
                    else:
                        fx.alpha_ss = fy.alpha_ss = fz.alpha_ss = a_ss  # as set_steady_gains
                        fx.beta_ss = fy.beta_ss = fz.beta_ss = b_ss
                        m, k = n_ax + 1, cfg.vel_prior_k
                        if 0 < cfg.n_max < m or k:  # capped, or the velocity-prior option
                            ga, gb, evo = scheduled_gains(  # (session 17): the function itself
                                m, cfg.n_max, a_ss, b_ss, prior_q(k, T))
                        else:  # scheduled_gains(m, n_max, α_ss, β_ss) uncapped (m ≥ 2)
                            dm = m * (m + 1.0)
                            ga = 2.0 * (2.0 * m - 1.0) / dm  # seed 000 "Evolutive coefficients"
                            gb = 6.0 / dm
                            evo = True
                            if 0.0 < a_ss < 2.0 and 0.0 < b_ss < 4.0 - 2.0 * a_ss:  # stable
                                if a_ss >= ga:
                                    ga, evo = a_ss, False
                                if b_ss >= gb:
                                    gb, evo = b_ss, False
                        sched_st = (ga, gb) if (ga, gb) == (a_ss, b_ss) else None
                        fx.evolutive = fy.evolutive = fz.evolutive = evo
                        fx._steady = fy._steady = fz._steady = sched_st
                    fx.alpha = fy.alpha = fz.alpha = ga
                    fx.beta = fy.beta = fz.beta = gb
                    bt = gb / T
                    c1 = 1.0 - ga
                    cc = c1 * c1  # (one assignment a value, round 10)
                    aa = ga * ga
                    abt = ga * bt
                    bt2 = 2.0 * bt
                    btbt = bt * bt
                    sm = 1.0 * cfg.sigma_m  # s·σm, s = 1
                    q_sm, q_dt, q11, q12, q22 = _q_last
                    if sm != q_sm or q_dt != T:
                        q11, q12, q22 = q_cwna(sm * sm, T)  # seed 002 eq. (4)
                        _q_last = (sm, T, q11, q12, q22)
                    # each axis: seed 000 "Beginning period" (DSP form), then the Joseph-form
                    # covariance after ΦPΦᵀ + Q (seed 002 eqs. 4, 7)
                    vel = fx.vel
                    pp = fx.pos + vel * T
                    nu_x = zx - pp
                    fx.pos = pp + ga * nu_x
                    fx.vel = vel + bt * nu_x
                    p12 = fx.p12
                    p22 = fx.p22
                    ap = p12 + T * p22
                    pp11 = fx.p11 + T * (p12 + ap) + q11
                    pp12 = ap + q12
                    fx.p11 = cc * pp11 + aa * rx
                    fx.p12 = c1 * (pp12 - bt * pp11) + abt * rx
                    fx.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + rx)
                    if fx.detect and n_ax >= 2:  # (detect off, the usual: one test)
                        fx.fmd.innovation(nu_x * nu_x / (pp11 + rx))
                        fx.fmd.decide()
                    vel = fy.vel
                    pp = fy.pos + vel * T
                    nu_y = zy - pp
                    fy.pos = pp + ga * nu_y
                    fy.vel = vel + bt * nu_y
                    p12 = fy.p12
                    p22 = fy.p22
                    ap = p12 + T * p22
                    pp11 = fy.p11 + T * (p12 + ap) + q11
                    pp12 = ap + q12
                    fy.p11 = cc * pp11 + aa * ry
                    fy.p12 = c1 * (pp12 - bt * pp11) + abt * ry
                    fy.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + ry)
                    if fy.detect and n_ax >= 2:
                        fy.fmd.innovation(nu_y * nu_y / (pp11 + ry))
                        fy.fmd.decide()
                    vel = fz.vel
                    pp = fz.pos + vel * T
                    nu_z = zz - pp
                    fz.pos = pp + ga * nu_z
                    fz.vel = vel + bt * nu_z
                    p12 = fz.p12
                    p22 = fz.p22
                    ap = p12 + T * p22
                    pp11 = fz.p11 + T * (p12 + ap) + q11
                    pp12 = ap + q12
                    fz.p11 = cc * pp11 + aa * rz
                    fz.p12 = c1 * (pp12 - bt * pp11) + abt * rz
                    fz.p22 = p22 + q22 - bt2 * pp12 + btbt * (pp11 + rz)
                    if fz.detect and n_ax >= 2:
                        fz.fmd.innovation(nu_z * nu_z / (pp11 + rz))
                        fz.fmd.decide()
                    fx.n = fy.n = fz.n = n_ax + 1
                else:
                    for f in axes:
                        f.set_steady_gains(a_ss, b_ss)
                    nu_x, nu_y, nu_z = (axes[0].update(zx, T, rx), axes[1].update(zy, T, ry),
                                        axes[2].update(zz, T, rz))
                nu = (nu_x, nu_y, nu_z)
                # session 9: the angle information of the reading (its gate-cell SNR)
                # (initiation.reading_angle_variance written out, issue 14, round 8)
                ratio = s_max / noise if noise > 0.0 else inf
                if ratio < inf:
                    snr = ratio * ratio / _RAYLEIGH_POWER - 1.0
                    if snr < SNR_FLOOR:  # as max(snr, SNR_FLOOR)
                        snr = SNR_FLOOR
                    k = self.inv_slope
                    var_k = k * k / (4.0 * snr)
                else:
                    var_k = 0.0
                j_k = self._indep / var_k if var_k > 0.0 else inf
                self._info += j_k
                if self._handover and confirmed and legacy:
                    self._handover = False
                    if handover_mismatch(nu, (ca, sa, ce, se), m_rho, sr, sg, fx,
                                         self.confirm_reinit_nis):
                        for f, z in zip(axes, (zx, zy, zz), strict=True):
                            f.pos = z  # re-centred on the confirmed cells' reading
                        # the direction is now that one reading's: reported once known again
                        self._info = self._recentred_info(j_k)
                if legacy and fx.n >= 3:
                    det = self.detector
                    # fx.innovation_factor(), without the method's own call; then
                    # det.innovation(maneuver.nis_cs(nu, …, factor)) and det.decide() written
                    # out (issue 14, round 8: the same operations, three calls fewer)
                    a = fx.alpha  # innovation_factor's evolutive case written out (round 8)
                    if fx.evolutive:
                        factor = 1.0 / (1.0 - a) if a < 1.0 else inf
                    else:  # 1 + prediction_vrr(α, β) (Brookner eq. 1.2-19) written out
                        bb = fx.beta  # (issue 14, round 9: two calls fewer in the mixed phase)
                        den = a * (4.0 - 2.0 * a - bb)
                        if a <= 0.0 or bb <= 0.0 or den <= 0.0:
                            factor = inf  # 1 + inf
                        else:
                            factor = 1.0 + (2.0 * a * a + 2.0 * bb + a * bb) / den
                    q_r = ce * sa * nu_x + ce * ca * nu_y + se * nu_z  # along u_ρ
                    q_a = ca * nu_x - sa * nu_y  # along u_θ
                    q_e = -se * sa * nu_x - se * ca * nu_y + ce * nu_z  # along u_φ
                    # sc2 = (m_rho·σθ)², sr2 = σr·σr: the variances' own, the same operations
                    d = ((q_r * q_r / sr2 + (q_a * q_a + q_e * q_e) / sc2) / factor
                         if sc2 != 0.0 else inf)  # a measurement at range 0: no NIS
                    if isfinite(d):  # seed 002 eq. (11): L(k) = a_f·L(k − 1) + d(k)
                        v = det.a_f * det.L + d
                        det.L = v if det.quant is None else det.quant("L", v)
                    stat = det.L
                    held = det.A if det.end == "acceleration" else stat
                    det.flag = stat > det.i1 or (det.flag and held >= det.i2)
        held = confirmed and 0 < fx.n < self._rate_left and doppler_ok  # session 19
        if not valid and fx.n > 0 and t_ok:
            if not confirmed and self.tentative_radial_coast:
                self._radial_velocity()  # session 12: a tentative track coasts in range only
            if held:
                self._doppler_rate(doppler_rate)
            self._limit_speed()  # never coast on a velocity no target can have (session 16:
            for f in axes:  # bounded before the coast, no longer after it)
                f.coast(T)  # prediction only (no measurement enters the state)
        elif confirmed and valid and self._vel_axes:
            if held:  # session 19: first toward the manager's range rate
                self._doppler_rate(doppler_rate)
            # issue 11: the gate moves ≤ max_speed (_limit_range_rate written out, round 8)
            px, py, pz = fx.pos, fy.pos, fz.pos
            r2 = px * px + py * py + pz * pz
            vr = (px * fx.vel + py * fy.vel + pz * fz.vel)
            lim = self.max_speed
            if r2 > 0.0 and vr * vr > lim * lim * r2:  # |u·v| > lim, without a square root
                inv = 1.0 / sqrt(r2)
                excess = vr * inv - copysign(lim, vr)
                fx.vel -= excess * px * inv
                fy.vel -= excess * py * inv
                fz.vel -= excess * pz * inv

        if not fx.n > 0:
            # no track yet: keep pointing at the designation, gate from the manager
            return self._designation_outputs(sums, (dev_az, dev_el, dev_lat, dev_r), ped_ok,
                                             az, el, gate_cmd, not valid, nu, hypothesis=True)

        # step 8: smoothed velocity → angle rates + pointing correction → command voltages
        if legacy:  # α-β axes: x = (pos, vel, 0), P = (p11, p12, p22) (CVEstimate), read direct
            px = fx.pos  # (one assignment a value, round 10)
            vx = fx.vel
            py = fy.pos
            vy = fy.vel
            pz = fz.pos
            vz = fz.vel
            ax = ay = az_ = 0.0
        else:
            (px, vx, ax), (py, vy, ay), (pz, vz, az_) = fx.x, fy.x, fz.x
        # as cart_to_sph and cart_to_sph_diff (rates 0 at the zenith or at the antenna):
        # geometry.cart_to_sph_and_diff written out (issue 14, round 8)
        h = hypot(px, py)
        h2 = px * px + py * py
        rho2 = h2 + pz * pz
        try:
            xy = px * vx + py * vy
            rdot = (xy + pz * vz) / sqrt(rho2)
            az_rate = (py * vx - px * vy) / h2
            el_rate = (h2 * vz - pz * xy) / (rho2 * sqrt(h2))
        except ZeroDivisionError:
            rdot = az_rate = el_rate = 0.0
        rng, t_az, t_el = sqrt(h * h + pz * pz), atan2(px, py) % TWO_PI, atan2(pz, h)
        if ped_ok:
            kp = self.pointing_gain
            w_az = az_rate + kp * ((t_az - az + pi) % TWO_PI - pi)  # wrap_pi, written out
            w_el = el_rate + kp * (t_el - el)
        else:
            w_az, w_el = az_rate, el_rate
        # as _cmd on each, inline (issue 14): rate → voltage, clipped to ±cmd_limit, 0 if not finite
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
            # the gate in [0, max_range] (issue 11): min(max(√…, GATE_CENTRE_M), max_range)
            r_pred = sqrt(qx * qx + qy * qy + qz * qz)
            if r_pred < GATE_CENTRE_M:
                r_pred = GATE_CENTRE_M
            if self.max_range < r_pred:
                r_pred = self.max_range
            gate = r_pred - offset_in - GATE_CENTRE_M
        else:
            gate = gate_cmd
        gh.append(gate)  # as _push_gate, inline
        self.offset_history.append(offset_in)
        # line-of-sight projection (the covariance block-diagonal over X, Y, Z; u held fixed)
        inv = 1.0 / rng if rng > 0.0 else 0.0
        ux, uy, uz = px * inv, py * inv, pz * inv
        wx, wy, wz = ux * ux, uy * uy, uz * uz
        if legacy:
            a0 = fx.p11  # (one assignment a value, round 10)
            b0 = fx.p12
            c0 = fx.p22
            a1 = fy.p11
            b1 = fy.p12
            c1 = fy.p22
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
        if not established:  # session 12: with init_prior_sigma as below (the manager steps
            y_az, y_el = t_az, t_el  # after the Tracker: its first confirmed sample has this)
            rng, t_az, t_el = no_track_report(self.designation, gate_cmd + offset_in, az, el,
                                              ped_ok)
            rdot = 0.0
            if ped_ok and self._tent_report:  # an option on (session 12: σp; 13: known)
                t_az, t_el = self._tentative_direction(y_az, y_el, az, el, valid)
        elif self._info < self._info_req:  # range and range rate known, the direction not
            established = False  # yet (session 9): the boresight, or the posterior mean
            if ped_ok:
                t_az, t_el = self._young_direction(t_az, t_el, az, el)
        elif ped_ok and self._invert:  # session 14: the pattern inverted on the average
            t_az, t_el = self._inverted(t_az, t_el, az, el)
        # outputs.outputs_flat(…) written out (issue 14, round 8: a call of 35 arguments,
        # built through a list in CPython 3.11, fewer): the template's copy filled in place
        if legacy and self.ddre_out is NO_DDRE:  # (issue 14, round 10: 7 stores fewer)
            out = _new_outputs_nd()  # ddre.* = NO_DDRE, track.acc.* = ax, ay, az_ = 0.0
        else:
            out = _new_outputs()
            (out["ddre.range"], out["ddre.smoothed"], out["ddre.predicted"],
             out["ddre.valid"]) = self.ddre_out
            out["track.acc.x"] = ax
            out["track.acc.y"] = ay
            out["track.acc.z"] = az_
        out["sum"] = sums
        out["dev.az"] = dev_az
        out["dev.el"] = dev_el
        out["dev.lat"] = dev_lat
        out["dev.range"] = dev_r
        out["track.x"] = px
        out["track.y"] = py
        out["track.z"] = pz
        out["track.vx"] = vx
        out["track.vy"] = vy
        out["track.vz"] = vz
        out["track.range"] = rng
        out["track.range_rate"] = rdot
        out["track.az"] = t_az
        out["track.el"] = t_el
        out["cmd.az"] = cmd_az
        out["cmd.el"] = cmd_el
        out["gate.start"] = gate
        out["maneuver"] = flag
        out["maneuver.statistic"] = stat
        out["maneuver.threshold"] = thr
        out["track.n"] = fx.n
        out["track.valid"] = established
        out["coasting"] = not valid
        out["innovation.x"], out["innovation.y"], out["innovation.z"] = nu
        out["track.range_acc"] = ux * ax + uy * ay + uz * az_
        out["track.P_rr"] = p_rr
        out["track.P_rv"] = p_rv
        out["track.P_vv"] = p_vv
        return out
