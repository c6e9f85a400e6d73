"""Helpers of :class:`.beams.BeamTracker` off its per-PRI tracking path, moved out of
:mod:`.beams` (issue 14, round 8: that module was near the 600-line limit): the monopulse
angle law, the command clip, the range-hypothesis test, the speed limits of a track, the
maneuver summary, the no-track outputs, the gate history and the DDRE step. Methods of a
mixin: they read and write the tracker's own state (attributes set by ``BeamTracker``).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from math import atanh as _atanh
from math import cos as _cos
from math import nan
from math import pi as _pi
from typing import Any

import numpy as np

from ..filters.alphabeta import AlphaBetaAxis
from ..filters.base import AxisFilter, CVEstimate, FilterConfig
from ..filters.registry import make_axis_filter
from ..radar.antenna import MonopulseAntenna
from ..radar.conventions import ACQUISITION, BIN_M, CONFIRMED
from ..radar.geometry import TWO_PI, cart_to_sph_and_diff, sph_to_cart, wrap_pi
from ..radar.params import Configurable
from .cells import _C, _N_BACKGROUND, background_sum
from .ddre import DDRE
from .initiation import no_track_report
from .maneuver import axis_summary, seed000_detector
from .notch import NotchCoast
from .outputs import GATE_CENTRE_M, MIN_COS_EL, NO_DDRE, ZERO3, outputs_dict
from .search import lap_period, search_offset, velocity_known
from .tentative_cells import clutter_free_filters, tentative_edge

_add_reduce = np.add.reduce

#: a jump of the true gate start larger than this [m] is a new range hypothesis (designer's
#: choice: 2 bins; the same hypothesis re-centred at another PRI moves it by ≤ 1 bin, the
#: tracker's own confirmed gate by ≤ max speed × PRI ≪ 1 bin)
HYPOTHESIS_JUMP_M = 2 * BIN_M


class BeamHelpers:
    """Methods of :class:`.beams.BeamTracker` outside its ``step`` (module docstring).

    Args:
        p: the Tracker's parameters (attributes named as in ``Tracker.PARAMS``).
        cfg: tuning of the axis filters.
    """

    # ---------------------------------------------------------------------------- set-up
    # (BeamTracker's __init__ and track reset, moved here for room: issue 14, round 9)
    def __init__(self, p: Configurable, cfg: FilterConfig) -> None:
        self.rate_per_volt = p.rate_per_volt
        self.pointing_gain = p.pointing_gain
        self.cmd_limit = p.cmd_limit
        self.designation = (p.designation_az, p.designation_el, p.designation_range)
        self.min_snr = p.min_snr
        self.track_init_n, self.confirm_reinit_nis = p.track_init_n, p.confirm_reinit_nis
        self.handover_tol = p.handover_range_tolerance  # [m] (session 26)
        # session 9: track initiation by angle information (initiation.reading_angle_variance)
        self._info_req = (1.0 / (p.init_angle_sigma * p.init_angle_sigma)
                          if p.init_angle_sigma > 0.0 else 0.0)
        self._indep = (1.0 - p.reading_pole) / (1.0 + p.reading_pole)
        #: 1/σp² of the boresight prior of a young track's reported direction [1/rad²]
        self._prior_prec = (1.0 / (p.init_prior_sigma * p.init_prior_sigma)
                            if p.init_prior_sigma > 0.0 else 0.0)
        self._info = 0.0  # angle information J of the track's readings [1/rad²]
        self._dil = [0.0, 0.0, 0.0, 0.0]  # (session 15) _tentative_direction
        self._tent_pairs: tuple[float, float, list[float]] = (0.0, 0.0, [0.0] * 16)
        self._tent_dilution = p.tentative_dilution
        #: (session 24) a side filter whose background exceeds this × the quietest filter's
        #: is left out of the tentative angle readings; 0: off. _tent_m: the filters kept
        self._tent_clutter = p.tentative_clutter_ratio
        self._tent_m = 3
        self._tent_known = p.tentative_known_direction  # session 13
        #: (recentre_keep_factor)²: a re-centre keeps a known direction on a reading of
        #: information ≥ J_req / this (session 13: 4² = 16)
        self._keep2 = p.recentre_keep_factor * p.recentre_keep_factor
        #: [time [s], az, el [rad]] of the last measured known-direction tentative report, NaN
        #: none; held on coasting PRIs for tentative_report_hold (session 17)
        self._tent_held = [nan, nan, nan]
        self._tent_hold = p.tentative_report_hold
        #: the tentative report depends on the track (an option on): _tentative_direction
        self._tent_report = self._prior_prec > 0.0 or self._tent_known
        self._handover = False  # the first confirmed measurement is still to be tested
        self.range_noise_correction, self.gate_latency = p.range_noise_correction, p.gate_latency
        #: session 29 (cells.bg_removed): fraction, pole, (p_u, p_d) (reset at a hand-over)
        self._beam_bg, self._bg_pole, self._bg_ema = p.beam_background, p.beam_background_pole, []
        self.sigma_range, self.sigma_angle = p.sigma_range, p.sigma_angle
        antenna = MonopulseAntenna(beamwidth=p.beamwidth, squint=p.squint)
        self.inv_slope = 1.0 / antenna.slope  # 1/k_m [rad]
        self.exact = p.monopulse_law == "exact"
        self._eps_max = math.tanh(antenna.slope * p.exact_max_angle)  # the exact law's clip
        #: session 14: the reported direction inverts the pattern (the linear law only)
        self._invert = p.report_inverts_pattern and not self.exact
        self._slope = antenna.slope  # k_m [1/rad]
        self._max_angle = p.exact_max_angle
        self._eps_max2 = self._eps_max * self._eps_max
        #: session 23: the linear reading beyond which cells.edge_reading is used [rad] (inf:
        #: off), and its (k_m, edge ratio tanh(k_m·edge_reading_angle), edge_reading_snr)
        eps = math.tanh(antenna.slope * p.edge_reading_angle)
        self._edge_dev = eps / antenna.slope if p.edge_reading_angle > 0.0 else math.inf
        self._edge = (antenna.slope, eps, p.edge_reading_snr)
        #: tentative readings: the Σ's deviation beyond which the centre filter's cell is
        #: tested for the edge reading (session 24; inf: off)
        self._tent_edge_dev = (p.tentative_edge_fraction * self._edge_dev
                               if p.tentative_edge_fraction > 0.0 else math.inf)
        self._tent_bin, self._tent_edge_axes = _C, (False, False)
        self.tentative_radial_coast = p.tentative_radial_coast
        #: Cartesian axis filters: X, Y, Z
        self.axes: list[AxisFilter] = [make_axis_filter(k, cfg) for k in
                                       (p.filter_x, p.filter_y, p.filter_z)]
        #: the seed-000 tracker: α-β on the three axes with the 3-D NIS maneuver detector
        self.legacy_detector = all(isinstance(f, AlphaBetaAxis) for f in self.axes)
        #: the axes have a ``vel`` state (α-β, Kalman CV): :meth:`_limit_speed` applies
        self._vel_axes = all(hasattr(f, "vel") for f in self.axes)
        self._notch = NotchCoast(p.notch_coast_speed * self._vel_axes, p.notch_coast_max_el,
                                 p.notch_cross_time)  # (notch.py: a velocity state needed)
        if self.legacy_detector:
            for f in self.axes:
                f.detect = False
        self.detector = seed000_detector(p.maneuver_fading, p.maneuver_pfa)
        #: gate.start outputs, most recent last, and the range.offset received with each
        #: (the last 4: a bounded deque drops the oldest itself, issue 14)
        self.gate_history: deque[float] = deque(maxlen=4)
        self.offset_history: deque[float] = deque(maxlen=4)
        self.max_range = p.max_range
        self.max_speed = p.max_speed
        self.doppler_rate_tol = p.doppler_rate_tol
        self.doppler_rate_n = p.doppler_rate_n
        #: readings below which _doppler_rate applies (0: doppler_rate_tol 0, never), and
        #: for the current track (0 once applied with doppler_rate_once)
        self._rate_n = p.doppler_rate_n if p.doppler_rate_tol > 0.0 else 0
        self._rate_left = self._rate_n
        self._rate_once = p.doppler_rate_once
        self.reacquire_time, self._vel_check = p.reacquire_time, p.reacquire_velocity_check
        #: session 15: the acquisition search around the designation (:mod:`.search`)
        period = lap_period(p.search_period, p.search_radius, p.search_accel,
                            max(math.cos(p.designation_el), MIN_COS_EL))
        self._search = (p.search_dwell, period, p.search_radius, p.search_min_el)
        self._acq_clock = 0.0  # time in acquisition since the search began [s]
        self._acq_last = 0.0  # tracker time of the last acquisition step [s]
        #: (time [s], x, y, z [m], vx, vy, vz [m/s]) of the last confirmed track when it was
        #: lost: where the pedestal looks while re-acquiring (:meth:`_lose_track`); None: none
        self._lost: tuple[float, float, float, float, float, float, float] | None = None
        self._hyp_gate = nan  # true gate start of the current range hypothesis [m]
        self.mode = ACQUISITION
        self.time = 0.0  # [s], sum of the steps (DDRE time base)
        self.ddre = (
            DDRE(window=p.ddre_window, bin_size=BIN_M, background=p.ddre_background,
                 threshold=p.ddre_threshold, memory=p.ddre_memory,
                 velocity_cut=p.ddre_velocity_cut, t_pred=p.ddre_t_pred)
            if p.ddre_window > 0 else None
        )
        self.ddre_out = NO_DDRE

    def _mapping_inputs(self, inputs: Mapping[str, Any]
                        ) -> tuple[int, float, float, float, float, Any, Any, float, bool]:
        """(mode, ped.az [rad], ped.el [rad], range.offset [m], gate.command [m], alpha, beta,
        doppler.range_rate [m/s], doppler.resolved) of an input mapping that is not a dict
        holding every key (BeamTracker.step): absent keys take their defaults (ped.az, ped.el
        have none: KeyError); the gains unconverted."""
        get = inputs.get
        mode = int(get("mode", ACQUISITION))
        az = float(inputs["ped.az"])
        el = float(inputs["ped.el"])
        offset = float(get("range.offset", 0.0))
        gate_cmd = float(get("gate.command", nan))
        return (mode, az, el, offset, gate_cmd, get("alpha", 0.0), get("beta", 0.0),
                get("doppler.range_rate", 0.0), get("doppler.resolved", False))

    def _tentative_cells(self, beams: np.ndarray, sums: np.ndarray) -> tuple[Any, ...]:
        """The gate cells of BeamTracker.step in tentative mode, as gate_cells(beams,
        central_only=False): Σ over the 3 Doppler filters of bins 6-8 of each beam [1], the
        strongest cell's four beams (u, r, d, l), the cells' SUMs s6, s7, s8, the strongest,
        and the SUM profile over the filters (array ``col`` (16,) and its list). Session 24: a
        side filter in clutter is left out of the four beams (:mod:`.tentative_cells`)."""
        kb, ks, m = clutter_free_filters(beams, sums, self._tent_clutter)
        self._tent_m = m
        (u6, u7, u8), (r6, r7, r8), (d6, d7, d8), (l6, l7, l8) = _add_reduce(
            beams[:, _C - 1:_C + 2, :], 2).tolist()
        col = _add_reduce(sums, 1)  # = sums.sum(axis=1)
        s6, s7, s8 = u6 + r6 + d6 + l6, u7 + r7 + d7 + l7, u8 + r8 + d8 + l8
        if s8 > s7 and s8 >= s6:
            u7, r7, d7, l7, s_max, self._tent_bin = u8, r8, d8, l8, s8, _C + 1
        elif s6 > s7:
            u7, r7, d7, l7, s_max, self._tent_bin = u6, r6, d6, l6, s6, _C - 1
        else:
            s_max, self._tent_bin = s7, _C
        cl = col.tolist()
        if m < 3:  # the angles from the kept filters only (SUMs, range, noise: the 3)
            u7, r7, d7, l7 = _add_reduce(kb[:, self._tent_bin, :], 1).tolist()
        self._tent_pairs = (u7 + d7, r7 + l7, cl if m == 3 else _add_reduce(ks, 1).tolist())
        self._tent_edge_axes = (False, False)
        return u7, r7, d7, l7, s6, s7, s8, s_max, col, cl

    def _tentative_edge(self, beams: np.ndarray, sums: np.ndarray, dev_el: float,
                        dev_lat: float) -> tuple[float, float]:
        """A tentative reading beyond ``_tent_edge_dev`` on an axis: the centre filter's cell
        of the strongest gate bin read at the edge (:func:`.tentative_cells.tentative_edge`,
        session 24); (dev_el, dev_lat) [rad]."""
        dev_el, dev_lat, self._tent_edge_axes = tentative_edge(
            beams[:, self._tent_bin, 1].tolist(), sums[:, 1].tolist(), self.inv_slope,
            self._edge, dev_el, dev_lat)
        return dev_el, dev_lat

    def _reset_track(self) -> None:
        for f in self.axes:
            f.reset()
        self._rate_left = self._rate_n
        self._info = 0.0
        self._dil = [0.0, 0.0, 0.0, 0.0]  # Σ(pair − noise/3), Σ pair: elevation, lateral
        self._tent_held, self._bg_ema = [nan, nan, nan], []  # (beam_background's averages)
        self._notch.reset()
        self.detector.reset()
        if self.ddre is not None:
            self.ddre.reset()
        self.ddre_out = NO_DDRE

    def _lose_track(self, t_state: float, pri: float) -> None:
        """The track ends (the manager returned to acquisition): reset it, and when it was a
        confirmed, established track (``track_init_n`` readings and the angle information of
        ``init_angle_sigma``) with a plausible state (finite, range ≤ ``max_range``, speed ≤
        ``max_speed``), keep its position and velocity (the state at ``t_state`` [s], the
        tracker's time of the last step; velocity 0 unless :func:`.search.velocity_known`,
        ``pri`` [s] the step's) for :meth:`_designation_outputs`.

        Session 11 (issue 11; designer's choice: the seed is silent on a lost track): the
        manager re-acquires around the last plausible track range (``_drop_track``); the
        pedestal looked at the designation of t = 0 instead. Traced (docs/envelope.md,
        "Session 11"): 16 km, 2.5°, a 5 g turn, 3 s after t = 0 the designation was 1.5° off
        the target; the antenna slewed back to it after the drop, the target was re-detected
        at the edge of the beam and confirmed 1.3° off boresight — a false confirmation by
        the angle gate (half the beamwidth).

        Session 15: the acquisition search (:meth:`_look_direction`) counts acquisition time
        from this step on; a lost confirmed track restarts it (a dwell on the designation)."""
        self._acq_last = t_state
        if self.mode == CONFIRMED:
            self._acq_clock = 0.0
        if self.mode == CONFIRMED and self.reacquire_time > 0.0:
            fx, fy, fz = self.axes
            if self._direction_known():
                (px, vx, _), (py, vy, _), (pz, vz, _) = fx.x, fy.x, fz.x
                if self._vel_check and not velocity_known(fx.n, self._info, self._info_req,
                                                          pri, self.reacquire_time):
                    vx = vy = vz = 0.0  # session 25: a young track's direction, held
                st = (t_state, px, py, pz, vx, vy, vz)
                r2, v2 = px * px + py * py + pz * pz, vx * vx + vy * vy + vz * vz
                if (all(math.isfinite(v) for v in st) and r2 <= self.max_range ** 2
                        and v2 <= self.max_speed ** 2):
                    self._lost = st
        self._reset_track()

    def _look_direction(self, acquiring: bool = False
                        ) -> tuple[float, float, float, float, float]:
        """(range [m], az [rad], el [rad], az rate, el rate [rad/s]) where the pedestal looks
        without a track: the lost track (:meth:`_lose_track`) extrapolated at constant
        velocity to now while it is at most ``reacquire_time`` old, else the designation
        moved by the acquisition search (session 15, :mod:`.search`; its clock runs only
        while ``acquiring``, the manager in acquisition; in tentative the direction holds,
        rates 0)."""
        lost = self._lost
        if lost is not None:
            age = self.time - lost[0]
            if 0.0 <= age <= self.reacquire_time:
                _t0, px, py, pz, vx, vy, vz = lost
                rng, az, el, _, d_az, d_el = cart_to_sph_and_diff(
                    px + vx * age, py + vy * age, pz + vz * age, vx, vy, vz)
                return rng, az, el, d_az, d_el
            self._lost = None
        des_az, des_el, des_range = self.designation
        dwell, period, radius, min_el = self._search
        if not radius > 0.0:
            return des_range, des_az, des_el, 0.0, 0.0
        if acquiring:  # the time since the last acquisition step counts
            self._acq_clock += self.time - self._acq_last
            self._acq_last = self.time
        d_lat, d_el, r_lat, r_el = search_offset(self._acq_clock, dwell, period, radius)
        if not acquiring:
            r_lat = r_el = 0.0
        el = des_el + d_el
        floor = des_el if des_el < min_el else min_el  # never below min(designation, min_el)
        if el < floor:
            el, r_el = floor, 0.0
        c = _cos(el)
        c = c if c > MIN_COS_EL else MIN_COS_EL  # (|el| ≤ 90°: cos ≥ 0)
        return des_range, (des_az + d_lat / c) % TWO_PI, el, r_lat / c, r_el

    # the attributes the methods use, set by BeamTracker.__init__ and step
    exact: bool
    inv_slope: float
    # ---------------------------------------------------------------------------- helpers
    def _angle(self, eps: float) -> float:
        """Angle off boresight from a monopulse ratio [rad] (SYSTEM.md: angle = ε/k_m)."""
        if self.exact:  # clipped to the main lobe, ±exact_max_angle (session 13)
            m = self._eps_max
            e = -m if eps < -m else (m if eps > m else eps)
            return math.atanh(e) * self.inv_slope
        return eps * self.inv_slope

    def _cmd(self, rate: float) -> float:
        """Rate [rad/s] → command voltage [V], clipped to ±cmd_limit (0 if not finite)."""
        if not math.isfinite(rate):
            return 0.0
        v = rate / self.rate_per_volt
        lim = self.cmd_limit
        return lim if v > lim else (-lim if v < -lim else v)

    def _hypothesis_changed(self, true_gate: float, confirmed: bool) -> bool:
        """True when the range hypothesis of the beams changed (issue 11: every change of
        range hypothesis re-initialises the range filter): in tentative a jump of the true
        gate start (gate + range.offset) by more than ``HYPOTHESIS_JUMP_M`` (the manager moved
        the window to another hypothesis; the same hypothesis at another PRI keeps it within
        a bin), in confirmed any change of it not made by the tracker's own gate, i.e. a
        jump beyond the same bound."""
        prev = self._hyp_gate
        self._hyp_gate = true_gate
        return math.isfinite(prev) and abs(true_gate - prev) > HYPOTHESIS_JUMP_M

    def _limit_speed(self) -> None:
        """No track coasts faster than ``max_speed`` (issue 11): when no measurement enters
        the state, a velocity beyond the physical bound (a young track's two points a few
        PRIs apart) is scaled back onto it, before the coast's prediction (session 16: it
        came after it, so the first coast after an update ran on the update's velocity, up to
        10⁵ m/s); filters with a ``vel`` state (α-β, Kalman CV) only. Measured updates:
        :meth:`_limit_range_rate` in confirmed mode; tentative ones are left to the filter,
        so seed 000's evolutive gains hold exactly (tests/test_reports.py)."""
        if not self._vel_axes:
            return
        fx, fy, fz = self.axes
        v2 = fx.vel * fx.vel + fy.vel * fy.vel + fz.vel * fz.vel
        if v2 > self.max_speed * self.max_speed:
            k = self.max_speed / math.sqrt(v2)
            for f in self.axes:
                f.vel *= k

    def _young_direction(self, t_az: float, t_el: float, az: float,
                         el: float) -> tuple[float, float]:
        """Reported (az, el) [rad] of a confirmed track of ``track_init_n`` readings whose
        angle information J is below 1/init_angle_sigma², and (option on) of a tentative
        track (session 9: the boresight ``az``, ``el``). With ``init_prior_sigma`` σp > 0
        (session 12, docs/filters.md "The direction of a young confirmed track") the
        posterior mean of the direction
        given the boresight as a prior of variance σp² (the target is in the beam that
        detected it) and the track's direction ``t_az``, ``t_el`` of variance 1/J:
        boresight + w·(track − boresight), w = J/(J + 1/σp²), per angle (the azimuth
        difference wrapped to ±π)."""
        if self._prior_prec > 0.0:
            w = self._info / (self._info + self._prior_prec)
            return (az + w * wrap_pi(t_az - az)) % TWO_PI, el + w * (t_el - el)
        return az % TWO_PI, el

    def _inverted(self, t_az: float, t_el: float, az: float, el: float) -> tuple[float, float]:
        """The reported direction (az, el) [rad] of a track whose filtered direction is
        ``t_az``, ``t_el``, the pedestal at ``az``, ``el`` (``report_inverts_pattern``,
        session 14). The filter averages linear-law readings θ = ε/k_m (SYSTEM.md), and the
        noise-free ratio of the Gaussian pattern is ε = tanh(k_m·θ) (radar/antenna.py), so
        the filtered offset d from the boresight estimates tanh(k_m·θ)/k_m: per axis
        (lateral d·cos el, elevation) the report is θ = atanh(k_m·d)/k_m; beyond the exact
        law's clip (|k_m·d| ≥ tanh(k_m·exact_max_angle)) it is max(exact_max_angle, |d|)
        with d's sign: never below the linear value, and an offset beyond exact_max_angle
        keeps the linear report. |θ| ≥ |d|: the same direction for d → 0 (d + k_m²d³/3 + …).
        With the pedestal at or past the zenith (cos el < 1e-3: there the lateral offset
        Δaz·cos el no longer measures the angle off the boresight) or a NaN: ``t_az``,
        ``t_el`` as they are."""
        ce = _cos(el)
        k = self._slope
        d_lat = ((t_az - az + _pi) % TWO_PI - _pi) * ce
        x_lat = k * d_lat
        x_el = k * (t_el - el)
        x2 = self._eps_max2  # (squares: fewer instructions than -xmax < x < xmax, issue 14)
        if x_lat * x_lat < x2 and x_el * x_el < x2 and ce >= 1e-3:
            return (az + _atanh(x_lat) / k / ce) % TWO_PI, el + _atanh(x_el) / k
        if not ce >= 1e-3:
            return t_az, t_el
        lim, xmax = self._max_angle, self._eps_max
        out = []
        for d, x in ((d_lat, x_lat), (t_el - el, x_el)):
            if -xmax < x < xmax:
                out.append(_atanh(x) / k)
            elif x == x:
                out.append(math.copysign(lim if lim > abs(d) else abs(d), d))
            else:
                return t_az, t_el
        return (az + out[0] / ce) % TWO_PI, el + out[1]

    def _doppler_rate(self, rate: Any) -> None:
        """A confirmed track's range rate within ``doppler_rate_tol`` of the manager's
        (``rate`` [m/s], RadarManager ``doppler.range_rate``): the velocity's line-of-sight
        component, u·v (u the unit vector of the filtered position), projected onto
        [rate − tol, rate + tol]; only that component moves (estimate projection onto a
        linear inequality constraint, as :meth:`_limit_range_rate`). Filters with a ``vel``
        state; nothing at position 0 or for a non-finite rate.

        Session 19 (issue 11; seed 000: in confirmed mode "the Doppler frequency is
        calculated by the Radar Manager"): the manager's unfolded Doppler is resolved over
        ≥ 3 PRIs within the coherence tolerance and then followed by its Doppler loop, to a
        few m/s; a young confirmed track's evolutive gains read correlated range noise a PRI
        apart as 10³-10⁴ m/s (docs/filters.md "A velocity prior"), and a track reset at the
        hand-over walked past the range gate on it."""
        if not self._vel_axes:
            return
        v_m = float(rate)
        fx, fy, fz = self.axes
        px, py, pz = fx.pos, fy.pos, fz.pos
        r2 = px * px + py * py + pz * pz
        if not (r2 > 0.0 and math.isfinite(v_m)):
            return
        if self._rate_once:  # (doppler_rate_once: this track's chance, taken)
            self._rate_left = 0
        inv = 1.0 / math.sqrt(r2)
        vr = (px * fx.vel + py * fy.vel + pz * fz.vel) * inv
        tol = self.doppler_rate_tol
        lo, hi = v_m - tol, v_m + tol
        target = lo if vr < lo else (hi if vr > hi else vr)
        if target != vr and math.isfinite(vr):
            d = (target - vr) * inv
            fx.vel += d * px
            fy.vel += d * py
            fz.vel += d * pz

    def _start_handover(self, gate_true: float) -> bool:
        """The step the manager confirms: True when the tentative track goes on (tested by its
        first confirmed measurement, ``_handover``). Range vs the manager's gate centre
        (``gate_true`` = gate.command + range.offset [m], + 6 bins): beyond ``HYPOTHESIS_JUMP_M``
        reset (False; session 16); beyond ``handover_range_tolerance`` moved along its line of
        sight onto it, all else kept (session 26: 1-2 bins off put the target at the edge)."""
        fx, fy, fz = self.axes
        self._bg_ema = []  # a new confirmed track: beam_background's averages start again
        self._notch.reset()
        if not fx.n > 0:
            return False
        px, py, pz = fx.x[0], fy.x[0], fz.x[0]
        r = math.sqrt(px * px + py * py + pz * pz)  # (products: inf, not OverflowError)
        d = r - (gate_true + GATE_CENTRE_M)
        shift = abs(d) > self.handover_tol and r > 0.0 and r > d  # (False for a NaN)
        if abs(d) > HYPOTHESIS_JUMP_M or (shift and not all(isinstance(f, CVEstimate)
                                                           for f in self.axes)):
            self._reset_track()  # (a filter without a CV position: reset, as session 16)
            return False
        for f in self.axes if shift else ():
            f.pos *= 1.0 - d / r
        return True

    def _direction_known(self) -> bool:
        """The track's direction is known (session 9's initiation test): ``track_init_n``
        readings and angle information J ≥ 1/init_angle_sigma²."""
        return self.axes[0].n >= self.track_init_n and self._info >= self._info_req

    def _tentative_direction(self, t_az: float, t_el: float, az: float, el: float,
                             measured: bool) -> tuple[float, float]:
        """Reported (az, el) [rad] of a tentative track whose filtered direction is ``t_az``,
        ``t_el`` (pedestal at ``az``, ``el``), with an option on (``_tent_report``): with
        ``tentative_known_direction`` (session 13), that direction when the track has
        ``track_init_n`` readings and the angle information 1/init_angle_sigma² (what a
        confirmed, established track reports) and a reading entered it at this PRI
        (``measured``: a coasting tentative track's direction is extrapolated on the
        cross-range velocity of weak readings; traced: 42 km, a track coasting 1.67° off the
        target while the boresight was 0.95° off); at a coasting PRI up to
        ``tentative_report_hold`` after such a report (an option, off by default), that report
        (session 17: a coasting PRI at the confirmation reported where the radar looks, off the
        target; traced: 10 km, −53 m/s, 5°, 1 m², seed 2, designation 3° off); otherwise
        :meth:`_young_direction`."""
        dil = self._dil
        dilute = self._tent_dilution and self.mode != CONFIRMED  # (tentative readings only)
        if measured and dilute:
            ud, rl, cl = self._tent_pairs
            m = self._tent_m  # the filters in the Σ: the pair's noise in the m − 1 others
            n3 = (background_sum(cl) / (3.0 * _N_BACKGROUND) if m == 3  # 4 × mean noise/beam
                  else background_sum(cl) * (m - 1) / (2.0 * m * _N_BACKGROUND))
            e_el, e_lat = self._tent_edge_axes  # an edge reading: undiluted (session 24)
            dil[0] += ud if e_el else ud - n3
            dil[1] += ud
            dil[2] += rl if e_lat else rl - n3
            dil[3] += rl
        if measured and self._tent_known and self._direction_known():
            if dilute and dil[1] > 0.0 and dil[3] > 0.0:
                k_el = dil[1] / dil[0] if dil[0] > 0.25 * dil[1] else 4.0
                k_lat = dil[3] / dil[2] if dil[2] > 0.25 * dil[3] else 4.0
                t_el = el + (t_el - el) * k_el
                t_az = az + wrap_pi(t_az - az) * k_lat
            rep = self._inverted(t_az, t_el, az, el) if self._invert else (t_az, t_el)
            if self._tent_hold:  # kept for the coasting PRIs only with the option on
                held = self._tent_held
                held[0], held[1], held[2] = self.time, rep[0], rep[1]
            return rep
        held = self._tent_held
        if not measured and self._tent_hold and self.time - held[0] <= self._tent_hold:
            return held[1], held[2]
        return self._young_direction(t_az, t_el, az, el)

    def _recentred_info(self, j_k: float) -> float:
        """Angle information [1/rad²] of a track re-centred on the first confirmed reading,
        of information ``j_k`` (the hand-over, ``confirm_reinit_nis``): that reading's. With
        ``tentative_known_direction``, a direction already known (J reached) and a reading
        accurate to k × init_angle_sigma (k = ``recentre_keep_factor``: j_k ≥ the requirement
        / k²; session 13's k = 4: 1°; since session 22 k = 8: 2°), at least the requirement:
        the tentative track already reported its direction, and the confirmed reading (the
        central filter, centred on the resolved Doppler) replaces it; falling back to the
        boresight for the PRIs until J was reached again reported a target confirmed 2° off
        boresight outside the angle gate (session 13: readings of 18-23 % of the requirement;
        session 22: 1.8 % and 3.3 %, the boresight 2-2.9° off). A weaker reading (below
        1/k² of the requirement) stays unreported until J is reached."""
        req = self._info_req
        if self._tent_known and self._info >= req and self._keep2 * j_k >= req:
            return j_k if j_k > req else req
        return j_k

    def _radial_velocity(self) -> None:
        """A coasting tentative track keeps only the line-of-sight component of its velocity,
        u·(u·v), u the unit vector of the filtered position (``tentative_radial_coast``; docs/
        filters.md "A tentative track coasts in range"). Its cross-range velocity is the
        angle noise of a few hundred weak readings × range over their span (10⁴ m/s at n ≈ 50,
        1 752 m/s at n = 257 in the default scenario, :meth:`_limit_range_rate`): extrapolated
        through a coast it walked the antenna 1.5° off a 10 km target at 2° elevation, onto
        the clutter below. Filters with a ``vel`` state only; no change at position 0."""
        if not self._vel_axes:
            return
        fx, fy, fz = self.axes
        px, py, pz = fx.pos, fy.pos, fz.pos
        r2 = px * px + py * py + pz * pz
        if not r2 > 0.0:
            return
        k = (px * fx.vel + py * fy.vel + pz * fz.vel) / r2
        fx.vel, fy.vel, fz.vel = k * px, k * py, k * pz

    def _limit_range_rate(self) -> None:
        """A confirmed track's range rate stays within ±``max_speed`` (issue 11): after a
        measured update the velocity is projected onto |u·v| ≤ max_speed, u the filtered
        position's line of sight (projection onto a linear inequality constraint: D. Simon,
        "Kalman filtering with state constraints", IET Control Theory Appl. 4(8), 2010,
        §2.4): only the radial component moves, by the excess. It bounds how fast the gate
        moves (a track confirmed a few PRIs after a reset read 10⁶ m/s, walked 250 m off in 3
        PRIs). Not the full |v|: a young track's cross-range velocity is angle noise × range
        (1 752 m/s at n = 257 at the default lock), and bounding it would change seed 000's
        gains (tests/test_reports.py). Tentative updates: the filter's (the manager's gate)."""
        fx, fy, fz = self.axes
        px, py, pz = fx.pos, fy.pos, fz.pos
        r2 = px * px + py * py + pz * pz
        vr = (px * fx.vel + py * fy.vel + pz * fz.vel)
        lim = self.max_speed
        if r2 > 0.0 and vr * vr > lim * lim * r2:  # |u·v| > lim, without a square root
            inv = 1.0 / math.sqrt(r2)
            excess = vr * inv - math.copysign(lim, vr)
            fx.vel -= excess * px * inv
            fy.vel -= excess * py * inv
            fz.vel -= excess * pz * inv

    def _maneuver(self) -> tuple[bool, float, float]:
        """(flag, statistic, threshold) of the maneuver test in use."""
        if self.legacy_detector:
            det = self.detector
            return det.flag, det.L, det.i1
        return axis_summary(self.axes)

    def _designation_outputs(
        self, sums: np.ndarray, devs: tuple[float, float, float, float], ped_ok: bool,
        az: float, el: float, gate_cmd: float, coasting: bool, nu: tuple[float, float, float],
        hypothesis: bool = False,
    ) -> dict[str, Any]:
        """No track: point the pedestal at :meth:`_look_direction` (the lost track while
        re-acquiring, else the designation; position loop plus its angular rate), gate from
        the manager; the track outputs report that direction, or with ``hypothesis`` (modes
        1-2) where the radar looks (:func:`.initiation.no_track_report`)."""
        des_range, des_az, des_el, rate_az, rate_el = self._look_direction(not hypothesis)
        kp = self.pointing_gain
        if ped_ok:
            cmd_az = self._cmd(rate_az + kp * wrap_pi(des_az - az))
            cmd_el = self._cmd(rate_el + kp * (des_el - el))
        else:
            cmd_az = cmd_el = 0.0
        self._push_gate(gate_cmd, self._offset_in)
        _, stat, thr = self._maneuver()
        dev_az, dev_el, dev_lat, dev_r = devs
        if hypothesis:
            des_range, des_az, des_el = no_track_report(
                (des_az, des_el, des_range), gate_cmd + self._offset_in, az, el, ped_ok)
        return outputs_dict(
            sums, dev_az, dev_el, dev_lat, dev_r, sph_to_cart(des_range, des_az, des_el), ZERO3,
            des_range, 0.0, des_az % (2 * math.pi), des_el, cmd_az, cmd_el, gate_cmd, False,
            stat, thr, self.axes[0].n, False, coasting, nu, self.ddre_out,
        )

    def _push_gate(self, gate: float, offset: float = math.nan) -> None:
        """Remember the ``gate.start`` output and the ``range.offset`` that went with it (the
        last 4)."""
        self.gate_history.append(gate)
        self.offset_history.append(offset)

    def _ddre_step(self, profile: np.ndarray, range_start: float) -> None:
        """Seed 001 DDRE on the SUM profile; bin r (0-based) at range_start + r·75 m."""
        if not np.isfinite(profile).all():
            return
        out = self.ddre.update(profile, self.time, range_start)
        if math.isfinite(out.smoothed):
            self.ddre_out = (out.range, out.smoothed, out.predicted, out.detected)
