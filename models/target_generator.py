"""TargetGenerator: target trajectory + clutter + receiver front end + IIR Doppler filters (AXIR_A).

Seed 000 names the front end/Doppler processing board (AXIR_A) only by its output: four beams ×
16 range bins × 3 IIR Doppler filters of magnitudes sent to the tracker. Everything inside is a
documented model (SYSTEM.md, radar.py conventions; ``# assumption:`` where we chose).

Per pulse n (at time t_n, PRI T = ``pri``), per beam b and range bin r, the complex baseband
sample is

    x[n, b, r] = a_n · F_n · g_b(θ_n) · Λ(d_{n,r}/Δ) · exp(−j 4π R_n/λ)        (target)
               + w[n, b, r]                                                    (thermal noise)
               + gc_b · c[n, r]                                                (ground clutter)

- a_n = √SNR(R_n): radar-equation amplitude, SNR(R) = SNR_ref · (σ/σ_ref) · (R_ref/R)⁴.
  # assumption (definition of ``snr_ref_db``): the mean single-pulse SNR of ONE beam at that
  # beam's peak voltage gain (g_b = 1), at the matched-filter peak (target on a bin sample),
  # for RCS ``rcs_ref`` at range ``snr_ref_range``; noise power is 1 per complex sample.
- F_n: Swerling fluctuation. Swerling 0: F = 1. Swerling 1: F ~ CN(0, 1) (Rayleigh amplitude,
  exponential RCS of mean σ, uniform phase), constant over a coherent dwell of ``dwell_pulses``
  pulses (pulses counted from reset) and independent between dwells.
  # assumption: the seed gives no fluctuation model; "dwell" = N pulses, a parameter.
- g_b(θ): voltage gains (up, right, down, left) of :class:`MonopulseAntenna` at the target's
  offsets from boresight (:func:`geometry.boresight_offsets`).
- Λ(u) = max(0, 1 − |u|): matched-filter response of the 0.5 µs rectangular pulse, half-width
  Δ = 75 m (radar.py, pulse straddle); d_{n,r} = R_n − (gate.start + (r − 1)·75 m) taken
  modulo Ru = c·T/2 into [−Ru/2, Ru/2): the window samples apparent delays (gate.start mod Ru)
  and the target is seen at R mod Ru (radar.py), so R + Ru lands in the same bin as R (physical
  range folding; eclipsing is not modelled).
- exp(−j4πR/λ): carrier phase of the two-way path; its pulse-to-pulse rotation is the Doppler
  f_d = −2 Ṙ/λ (radar.py), folded modulo PRF by the sampling itself.
- w ~ CN(0, 1), independent per beam, bin and pulse (``noise`` switches it off).
- c[n, r]: ground clutter, per range bin a complex AR(1) process
  c[n] = ρc c[n−1] + √(CNR (1 − ρc²)) u[n], u ~ CN(0, 1), ρc = exp(−2π B_c T), stationary power
  CNR; its spectrum is Lorentzian around 0 Hz with half-power half-width B_c =
  ``clutter_spread``. The same clutter signal enters the 4 beams through their gains toward the
  horizon at the antenna azimuth (offsets of (az_a, 0) from boresight), floored at
  ``clutter_sidelobe_db`` (# assumption: a sidelobe floor, the Gaussian pattern has none).
  # assumption: CNR is defined like the SNR (one beam at peak gain, per pulse) and is the same
  # in every range bin (clutter fills every apparent range).

Doppler filters (seed 000: 3 IIR filters), for f = 1..3 centred at
f_f = doppler.centre + (f − 2)·spacing (radar.py), spacing = ``doppler_spacing`` or PRF/3 when
0 (the three filters then tile the folded band):

    y_f[n] = p_f · y_f[n − 1] + (1 − ρ) · x[n],   p_f = ρ · exp(j 2π f_f T)

a first-order complex resonator with unit gain at its centre, |H_f(f_f)| = 1, and white-noise
power gain (1 − ρ)/(1 + ρ); ρ = ``pole``. The output ``beam`` is |y| of the last pulse of the
step, shape (4, 16, 3) (up, right, down, left × bins × filters; SYSTEM.md).

Time: a step of ``dt`` processes N = max(1, round(dt/pri)) pulses at t_new − (N − 1 − k)·pri,
k = 0..N − 1 (the last pulse at the end of the step); dt = 0 processes none. All random numbers
come from one ``numpy.random.Generator(PCG64(seed))`` kept in the state, drawn in a fixed
layout of 162 normals per pulse (128 noise, 32 clutter, 2 fluctuation) whatever the switches,
so one step of N·pri gives the same beams as N steps of pri (to rounding), and the noise,
clutter and fluctuation realisations do not depend on each other's switches.

Measurement fidelity (``fidelity = "measurement"``, SYSTEM.md "smaller system"): no front end;
at t = k·T_s (k ≥ 0, T_s = ``meas_interval``) the model measures range, azimuth and elevation
as truth + N(0, σ²) (σ_range, σ_angle on both angles), holding them between samples; beams are
zero. ``meas.new`` is 1 in the step that took a sample, ``meas.valid`` once a sample exists.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from math import asin, atan2, cos, exp, floor, hypot, isfinite, log10, sin, sqrt
from typing import Any

import numpy as np

from .radar import pulse1
from .radar.antenna import MonopulseAntenna
from .radar.conventions import (
    BIN_M,
    DEFAULT_WAVELENGTH,
    N_BEAMS,
    N_BINS,
    N_DOPPLER,
    C,
)
from .radar.geometry import (
    TWO_PI,
)
from .radar.hold import hold_inputs
from .radar.mti import MTI_TAPS_0D, cancel_pulse_into
from .radar.params import Param
from .radar.pulse1 import FLOOR_EL_MAX, PulseCache, clutter_gains_tuple
from .radar.straddle import straddle_bins
from .radar.tg_inputs import (  # noqa: F401 (re-exported: INPUTS, the domains, the input rule)
    _IN_DEFAULTS,
    _IN_FLOORS,
    _IN_NAMES,
    _PRI_MIN,
    ANGLE_MAX,
    DOPPLER_MAX,
    INPUTS,
    RANGE_MAX,
)
from .radar.tg_measure import measure as _tg_measure
from .radar.tg_outputs import MIN_RANGE as _MIN_RANGE
from .radar.tg_outputs import OUTPUTS as OUTPUTS
from .radar.tg_outputs import output_template
from .radar.tg_outputs import outputs as _tg_outputs
from .radar.tg_pulses import N_CLUT, N_NOISE
from .radar.tg_pulses import clutter_gains as _tg_clutter_gains
from .radar.tg_pulses import draws as _tg_draws
from .radar.tg_pulses import filter_poles as _tg_filter_poles
from .radar.tg_pulses import geometry as _tg_geometry
from .radar.tg_pulses import pulses as _tg_pulses
from .radar.trajectory import DEFAULT_TRAJECTORY_JSON, Trajectory, trajectory_from_spec
from .radar.trajectory import ConstantVelocity as _ConstantVelocity
from .radar.unit import Unit

_ANT = MonopulseAntenna.param_map()
_N_NOISE = N_NOISE  # normals per pulse for the thermal noise (128, radar.tg_pulses)
_N_CLUT = N_CLUT  # normals per pulse for the clutter innovation (32)
_N_DRAW = _N_NOISE + _N_CLUT + 2  # + 2 for the Swerling draw: fixed layout, 162 per pulse
_CHUNK = 4096  # pulses processed per vectorised chunk (bounds memory for long steps)
#: pulses of normals drawn at once for the one-pulse path (issue 14): a block of
#: (_DRAW_BLOCK, 162) from the same Generator is the same stream as _DRAW_BLOCK draws of 162
#: (tested); 32 pulses = 41 kB of state
_DRAW_BLOCK = 32
_NO_SEG = (None, 0.0, 0.0, None)  # no trajectory piece cached (step)
#: the output template (key order) and the numpy functions of the one-pulse path as module
#: globals (issue 14, round 11: ``self._otemplate`` is a class attribute and numpy a module
#: with ``__getattr__``, neither read by a specialised LOAD_ATTR in CPython 3.11)
_OTEMPLATE = output_template(OUTPUTS)
_new_outputs, _absolute, _multiply, _subtract = (_OTEMPLATE.copy, np.absolute, np.multiply,
                                                 np.subtract)
_SQRT_HALF = sqrt(0.5)


class TargetGenerator(Unit):
    """Point target + clutter + 4-beam receiver + 3 IIR Doppler filters (see module docstring).

    ``step(dt, inputs)``: inputs ``antenna.az``, ``antenna.el`` [rad], ``gate.start`` [m],
    ``doppler.centre`` [Hz], ``pri`` [s] (absent ones take :data:`INPUTS` defaults); returns
    ``beam`` (numpy (4, 16, 3) magnitudes [1, noise-power normalised]) and the scalars of
    :data:`OUTPUTS`.
    """

    INPUTS = INPUTS
    OUTPUTS = OUTPUTS
    #: step(dt, None, antenna_az, antenna_el, gate_start, doppler_centre, pri_in) (round 11)
    STEP_ARGS = _IN_NAMES
    #: the output mapping of a step (radar/tg_outputs.py) and its template (key order)
    _outputs = _tg_outputs
    _otemplate = _OTEMPLATE
    _measure = _tg_measure  # measurement fidelity: samples up to t_new (radar/tg_measure.py)
    _invalid_noted = False  # set by note_invalid_inputs for the coming step (reset: on self)

    PARAMS = (
        Param("seed", 0, "", "seed of the PCG64 random generator", low=0, high=2**31 - 1),
        Param("fidelity", "frontend", "", "'frontend': beams; 'measurement': noisy r/az/el",
              choices=("frontend", "measurement")),
        Param("trajectory", DEFAULT_TRAJECTORY_JSON, "",
              "target trajectory spec (JSON, see trajectory.trajectory_from_spec)"),
        Param("rcs", 5.0, "m2", "mean radar cross section of the target", low=0.0,
              high=1.0e6),  # 60 dBsm: above the largest ships (ship scenario: 8e4 m²)
        Param("rcs_ref", 1.0, "m2", "reference RCS of snr_ref_db", low=1.0e-6, high=1.0e6),
        Param("snr_ref_db", 20.0, "dB",
              "mean single-pulse SNR of one beam at its peak gain, target on a bin sample, "
              "for rcs_ref at snr_ref_range", low=-100.0, high=200.0),
        Param("snr_ref_range", 10_000.0, "m", "reference range of snr_ref_db",
              low=1.0, high=RANGE_MAX),  # 1 m (range floor of the radar equation) … 10 000 km
        Param("swerling", 0, "", "target fluctuation model: Swerling 0 or 1", choices=(0, 1)),
        Param("dwell_pulses", 32, "", "pulses per coherent dwell (Swerling 1 decorrelation)",
              low=1, high=2**31 - 1),
        Param("noise", True, "", "thermal noise on/off"),
        Param("clutter", True, "", "ground clutter on/off"),
        Param("cnr_db", 30.0, "dB",
              "clutter-to-noise ratio per pulse, one beam at peak gain, per range bin",
              low=-100.0, high=200.0),
        Param("clutter_spread", 15.0, "Hz",
              "half-power half-width of the AR(1) clutter spectrum", low=0.0,
              high=1.0e5),  # ≥ the largest PRF (125 kHz): white clutter
        Param("clutter_sidelobe_db", -30.0, "dB",
              "floor of the beams' power gain toward the clutter (sidelobes)",
              low=-300.0, high=0.0),
        Param("wavelength", DEFAULT_WAVELENGTH, "m", "carrier wavelength", low=1e-3, high=10.0),
        _ANT["beamwidth"],
        _ANT["squint"],
        Param("doppler_spacing", 0.0, "Hz",
              "spacing of the 3 Doppler filters; 0: PRF/3 (tile the folded band)", low=0.0,
              high=DOPPLER_MAX),
        # designer's choice (issue 11, docs/clutter.md, seed 000 silent): a canceller removes
        # the clutter peak that the one-pole Doppler filters' skirts (−24 dB at PRF/3) let
        # through when the beams see the ground (models/radar/mti.py); switched on by antenna
        # elevation only: above, its notch and coloured noise cost more than sidelobe clutter
        Param("mti", 1, "",
              "MTI canceller before the Doppler filters: 0 none, 1 two-pulse, 2 three-pulse "
              "(binomial taps, unit noise power gain), applied below mti_max_el",
              choices=(0, 1, 2)),
        Param("mti_max_el", math.radians(4.5), "rad",
              "antenna elevation below which the MTI canceller is applied (main-beam clutter: "
              "the down beam's gain toward the horizon above −20 dB)", low=-math.pi, high=math.pi),
        Param("mti_hysteresis", math.radians(0.25), "rad",
              "the canceller switches off only above mti_max_el + mti_hysteresis", low=0.0,
              high=math.pi),
        Param("pole", 0.9, "1", "pole radius of the IIR Doppler filters", low=0.0, high=1.0,
              high_open=True),
        Param("meas_sigma_range", 100.0, "m", "measurement fidelity: range noise σ (seed 002)",
              low=0.0, high=1.0e5),
        Param("meas_sigma_angle", 1e-3, "rad", "measurement fidelity: az and el noise σ",
              low=0.0, high=math.pi),
        Param("meas_interval", 1.0, "s", "measurement fidelity: sample interval T (seed 002)",
              low=1.0e-6, high=3600.0),  # 1 µs (a PRI) … 1 h
    )

    # -- configuration -------------------------------------------------------------------
    def _check(self) -> None:
        try:
            self._traj: Trajectory = trajectory_from_spec(self.trajectory)
        except ValueError as exc:
            raise ValueError(f"parameter TargetGenerator.trajectory is invalid: {exc}") from None
        self._antenna = MonopulseAntenna(beamwidth=self.beamwidth, squint=self.squint)
        # amplitude law a(R) = A0 / R², A0 = √(SNR_ref σ/σ_ref) R_ref²   (radar equation, R⁻⁴)
        self._a0 = sqrt(10.0 ** (self.snr_ref_db / 10.0) * self.rcs / self.rcs_ref) * (
            self.snr_ref_range**2
        )
        self._cnr = 10.0 ** (self.cnr_db / 10.0)
        # −4π/λ [rad/m]: the carrier phase −4πR/λ per metre, as (−4j·π/λ)·R's imaginary part
        self._k4pi = -4.0 * math.pi / self.wavelength
        self._sidelobe = 10.0 ** (self.clutter_sidelobe_db / 20.0)  # voltage floor
        self._cg_lo = pulse1.clutter_floor_elevation(self._antenna, self._sidelobe)  # [rad]
        self._cg_floor = (self._sidelobe,) * N_BEAMS  # the clutter gains above _cg_lo

    def reset(self) -> None:
        """Time 0, filters empty, generator reseeded, clutter drawn from its stationary law."""
        self.t = 0.0
        self._last_u = {p.name: p.initial for p in INPUTS}
        self._invalid = False
        self._invalid_count = 0
        self._invalid_noted = False  # an instance attribute (round 11: read every step)
        self._pulse = 0
        self._rng = np.random.Generator(np.random.PCG64(self.seed))
        self._y = np.zeros((N_BEAMS, N_BINS, N_DOPPLER), dtype=complex)
        # MTI: the last pulses × (1 − ρ) (the filters' gain, folded in front: both linear)
        self._xh = np.zeros((self.mti, N_BEAMS, N_BINS), dtype=complex)
        self._mti_on = False  # canceller applied (elevation switch, radar/mti.py)
        # stationary start of the AR(1) clutter: c ~ CN(0, CNR)  (drawn whatever the switch)
        self._c = self._rng.standard_normal(_N_CLUT).view(complex) * sqrt(0.5 * self._cnr)
        # preallocated per-pulse buffers of the one-pulse path (step); normals drawn in
        # blocks of _DRAW_BLOCK pulses, ×√½, consumed row by row (_draws)
        self._dblock = np.empty((_DRAW_BLOCK, _N_DRAW))
        self._dnext = _DRAW_BLOCK  # next unused row (block exhausted: draw a new one)
        self._v: PulseCache | None = None  # derived buffers of the one-pulse path (not state)
        self._seg: tuple[Any, float, float, Any] = _NO_SEG  # the trajectory piece (not state)
        self._cg_key = math.nan  # antenna elevation [rad] of the cached clutter gains
        self._cg_vals: tuple[float, ...] = ()  # the clutter gains (Python floats)
        self._cg_moved = True  # the clutter gains changed at the last evaluation
        self._gp: tuple[float, ...] = (0.0,) * N_BEAMS  # clutter gains pre-added (PulseCache)
        #: (t, trajectory, state, range, az, el) of the last pulse: its truth, for _outputs
        self._truth: tuple[float, Any, Any, float, float, float] = (
            math.nan, None, None, 0.0, 0.0, 0.0)
        self._clut_ab: tuple[float, float, float] = (math.nan, 0.0, 0.0)  # (T, ρc, b)
        self._pf_key: tuple[float, float] | None = None
        self._pf = np.zeros(N_DOPPLER, dtype=complex)
        self._fluct = 1.0 + 0.0j
        self._meas = (0.0, 0.0, 0.0)
        self._meas_valid = False
        self._meas_new = False
        self._k_next = 0  # index of the next measurement sample time k·T

    def note_invalid_inputs(self, names: list[str]) -> None:
        """Out-of-domain inputs were replaced by the caller: flag ``input.invalid`` in the
        coming step (counted once, like an input this unit holds itself)."""
        self._invalid_noted = True

    def outputs(self) -> dict[str, Any]:
        """Outputs at the current time without advancing: after :meth:`reset`, the truth at
        t = 0 and the beams of the empty Doppler filters (0: no pulse received yet)."""
        return self._outputs(self.t, self._last_u["pri"])

    # -- geometry --------------------------------------------------------------------------
    #: the N-pulse path's geometry and clutter gains (radar/tg_pulses.py, moved out for room)
    _geometry = _tg_geometry
    _clutter_gains = _tg_clutter_gains

    _filter_poles = _tg_filter_poles  # p_f of the Doppler filters (radar/tg_pulses.py)
    #: the N-pulse path (vectorised pulses, Doppler filters) and its draws (radar/tg_pulses.py)
    _pulses, _draws = _tg_pulses, _tg_draws

    # -- stepping --------------------------------------------------------------------------
    def step(self, dt: float, inputs: Mapping[str, Any] | None, antenna_az: Any = ...,
             antenna_el: Any = ..., gate_start: Any = ..., doppler_centre: Any = ...,
             pri_in: Any = ...) -> dict[str, Any]:
        """Advance by ``dt`` [s] (≥ 0) and return the outputs (see class docstring). ``inputs``
        None: the five inputs are the next arguments, in :data:`STEP_ARGS` order (the run
        loop's positional call; the same as the mapping of the five; one not given: TypeError).

        One pulse (dt one PRI, the usual case): the former ``_pulse1`` (the scalar fast path
        of :meth:`_pulses`: the same draws and equations; s = 1 − ρ folded into the inputs,
        noise and clutter per block: PulseCache) and ``radar.tg_outputs.outputs`` written out
        here (issue 14, round 9: no call), the same operations in the same order.

        Raises ``ValueError`` naming ``dt`` for a non-finite or negative step (state left
        unchanged). A non-finite input keeps its last valid value (``input.invalid``).
        """
        if dt.__class__ is not float or not 0.0 <= dt < math.inf:  # a float in range: fine
            if not isinstance(dt, (int, float)) or not math.isfinite(dt) or dt < 0.0:
                raise ValueError(
                    f"TargetGenerator step dt = {dt!r} must be a finite number >= 0 [s]")
            dt = float(dt)  # the float the step used (round 10: no float call for a float)
        # the input rule (_hold_valid, radar/hold.py) in its usual case written out: five
        # finite numbers as floats, pri above its floor, nothing noted (issue 14: no calls)
        try:  # a dict holding the five (round 9: subscripts, no get calls; another Mapping or
            if inputs is not None:  # a missing key: hold_inputs, whose first try gets the
                if type(inputs) is not dict:  # defaults: the same values); its values read
                    raise KeyError  # as the positional call has them (round 11)
                antenna_az = inputs["antenna.az"]
                antenna_el = inputs["antenna.el"]
                gate_start = inputs["gate.start"]
                doppler_centre = inputs["doppler.centre"]
                pri_in = inputs["pri"]
            az = float(antenna_az)
            el = float(antenna_el)
            gate = float(gate_start)
            fc = float(doppler_centre)
            pri = float(pri_in)
            usual = isfinite(az + el + gate + fc + pri) and pri >= _PRI_MIN  # as hold_inputs
        except (TypeError, ValueError, KeyError):
            usual = False
        if usual and not self._invalid_noted:
            self._last_u = u = {"antenna.az": az, "antenna.el": el, "gate.start": gate,
                                "doppler.centre": fc, "pri": pri}
            self._invalid = False  # (the count unchanged)
        else:
            if inputs is None:  # the positional call: the mapping it stands for
                vals = (antenna_az, antenna_el, gate_start, doppler_centre, pri_in)
                if any(v is ... for v in vals):
                    raise TypeError("TargetGenerator.step: inputs None takes the STEP_ARGS values")
                inputs = dict(zip(_IN_NAMES, vals, strict=True))
            u = self._hold_valid(inputs)
            az, el, gate, fc, pri = (u["antenna.az"], u["antenna.el"], u["gate.start"],
                                     u["doppler.centre"], u["pri"])
        t_new = self.t + dt
        if self.fidelity == "measurement" or not dt > 0.0 or not dt / pri < 1.5:
            if self.fidelity == "measurement":
                self._measure(t_new)
            elif dt > 0.0:  # several pulses: max(1, round(dt/pri)) > 1 (round half to even)
                n_total = round(dt / pri)
                done = 0
                while done < n_total:  # chunks keep memory bounded for very long steps
                    n = min(_CHUNK, n_total - done)
                    k = np.arange(done, done + n)
                    self._pulses(t_new - (n_total - 1 - k) * pri, u)
                    done += n
            self.t = t_new
            return self._outputs(t_new, pri)
        # ---- one pulse at t_new for the inputs az, el [rad], gate [m], fc [Hz], pri [s]
        clutter = self.clutter
        if clutter:  # the clutter gains (4,) as Python floats, written out (issue 14, round 7):
            # the same tuple object while its values do not change (all at the sidelobe floor
            # between _cg_lo and FLOOR_EL_MAX); _cg_moved when they change
            if el != self._cg_key:
                g = (self._cg_floor if self._cg_lo < el < FLOOR_EL_MAX
                     else clutter_gains_tuple(self._antenna, el, self._sidelobe))
                self._cg_moved = g != self._cg_vals
                if self._cg_moved:
                    self._cg_vals = g
                self._cg_key = el
            elif self._cg_moved:  # the same elevation: the same gains
                self._cg_moved = False
            g = self._cg_vals
        i = self._dnext
        pc = self._v
        if pc is None or pc.blk is not self._dblock:  # reset / set_state / deepcopy
            pc = self._v = PulseCache(self._dblock, _N_NOISE)
        if i == _DRAW_BLOCK:  # a new block: normals, then the rows' noise and clutter
            blk = self._dblock
            self._rng.standard_normal(out=blk)
            blk *= _SQRT_HALF
            i = 0
            pc.key = None
            if self._xh.base is pc.x3b:  # the canceller's memory is the last row: keep it
                self._xh = self._xh.copy()
            # pre-add the clutter gains only while they hold still (above the horizon)
            self._gp = (0.0,) * N_BEAMS if not clutter or self._cg_moved else g
        self._dnext = i + 1
        s = 1.0 - self.pole
        gp = self._gp
        if clutter and self._clut_ab[0] != pri:  # ρc = exp(−2π B_c T), b = √(CNR (1 − ρc²))
            rho_c = math.exp(-2.0 * math.pi * self.clutter_spread * pri)
            self._clut_ab = (pri, rho_c, sqrt(self._cnr * (1.0 - rho_c * rho_c)))
        key = (pri if clutter else 0.0, s, gp, self.noise)  # what the rows depend on
        if pc.key != key or (clutter and self._c is not pc.c_last):  # rows i … to build
            pc.fill(i, s, self._c, self._clut_ab[1:] if clutter else None, gp, self.noise)
            pc.key = key
        # x: s·(noise + pre-added clutter) of this pulse, (4, 16, 3): a copy per filter
        x3 = pc.x3rows[i]
        if clutter:
            c = self._c = pc.c_last = pc.crows[i]  # AR(1) clutter of this pulse
            if g is not gp:  # x += s·(g − gp) ⊗ c: the gains not pre-added
                _multiply(pc.correction(g, gp, s), c, out=pc.xc)
                x3 += pc.xc3
        # truth: trajectory, then (range, az, el) as geometry.cart_to_sph (same operations)
        traj = self._traj
        # (trajectory, lo, hi, piece) of the last pulse (Trajectory.segment), unpacked (round 10)
        s_traj, s_lo, s_hi, pce = self._seg
        if s_traj is traj and s_lo <= t_new < s_hi:  # = traj.state_tuple(t_new) (round 9)
            if type(pce) is _ConstantVelocity:  # its state_tuple written out (round 10: no call)
                tau = t_new - pce.t0
                (px, py, pz), (vx, vy, vz) = pce._p0v0
                px, py, pz = px + vx * tau, py + vy * tau, pz + vz * tau
                ax = ay = az_ = 0.0
                st = (px, py, pz), (vx, vy, vz), (0.0, 0.0, 0.0)
            else:
                (px, py, pz), (vx, vy, vz), (ax, ay, az_) = st = pce.state_tuple(t_new)
        else:
            st = traj.state_tuple(t_new)
            self._seg = (traj, *traj.segment(t_new))
            (px, py, pz), (vx, vy, vz), (ax, ay, az_) = st
        h = hypot(px, py)
        r_t = r = sqrt(h * h + pz * pz)
        az_t, el_t = atan2(px, py) % TWO_PI, atan2(pz, h)
        self._truth = (t_new, traj, st, r, az_t, el_t)
        # boresight_offsets_cart(px, py, pz, r, az, el) (test_tg_round8) written out (issue 14,
        # round 8): the target unit vector p/ρ in the antenna basis → (lateral, elevation)
        if r > 0.0:
            ux, uy, uz = px / r, py / r, pz / r
        else:
            ux, uy, uz = 0.0, 1.0, 0.0
        ca, sa, ce, se = cos(az), sin(az), cos(el), sin(el)
        bo = ux * ce * sa + uy * ce * ca + uz * se  # boresight
        ri = ux * ca - uy * sa  # right (east at az = 0)
        up = -ux * se * sa - uy * se * ca + uz * ce  # up
        up = up if up < 1.0 else 1.0
        lat, elo = atan2(ri, bo), asin(up if up > -1.0 else -1.0)
        r = _MIN_RANGE if r < _MIN_RANGE else r  # max(r, _MIN_RANGE), NaN kept as max keeps it
        # s·a(R)·F·exp(−j4πR/λ): radar equation (R⁻⁴ power), carrier phase → Doppler (radar.py)
        amp = (self._a0 / (r * r)) * s
        kr = self._k4pi * r  # −4πR/λ [rad]
        if self.swerling == 1:
            if self._pulse % self.dwell_pulses == 0:  # new dwell: F ~ CN(0, 1)
                d = self._dblock[i]
                self._fluct = complex(d[_N_NOISE + _N_CLUT], d[_N_NOISE + _N_CLUT + 1])
            coef = amp * self._fluct * complex(cos(kr), sin(kr))
            cr, ci = coef.real, coef.imag
        else:  # F = 1: the products of amp·e^(j·kr) on the parts (equal for finite values)
            cr, ci = amp * cos(kr), amp * sin(kr)
        # antenna.MonopulseAntenna.gains_tuple(lat, elo) written out (round 8)
        ant = self._antenna
        a, sq = ant._a, ant.squint
        vl = exp(-a * lat * lat)
        ve = exp(-a * elo * elo)
        g0 = vl * exp(-a * (elo - sq) ** 2)
        g1 = ve * exp(-a * (lat - sq) ** 2)
        g2 = vl * exp(-a * (elo + sq) ** 2)
        g3 = ve * exp(-a * (lat + sq) ** 2)
        # x[b, j] += c_b · Λ_j in the bins of the straddle (Ru = c·PRI/2, radar.py), with
        # c_b = g_b·coef = s·a·F·g_b·e^(−j4πR/λ); two_adjacent_bins(r, gate, Ru) (test_tg_round8)
        # written out (round 8): two bins j, j + 1 unless the aliased delay is within a bin
        # of bin 0 or j is the last bin (then straddle_bins)
        ru = 0.5 * C * pri
        d1 = (r - gate) % ru
        j = -1
        if not d1 > ru - BIN_M:
            q = d1 / BIN_M
            k = floor(q)
            if k < N_BINS - 1:
                # 1 − |q − k|, 1 − |q − k − 1| with the signs known (round 10: 0 ≤ q − k < 1
                # for k = ⌊q⌋, q ≥ 0; 1 − (−d) is 1 + d exactly): no abs calls
                j, w0, w1 = k, 1.0 - (q - k), 1.0 + (q - (k + 1))
        if j >= 0:  # the usual case: bins j, j + 1
            # c_b·Λ as (re, im): complex × real written out on the parts (the same products
            # for finite values: (g·cr)·w, (g·ci)·w), then two C calls write the target row
            # (zero outside bins j, j + 1; each value once per filter) and one contiguous
            # add puts it into x (x + 0.0 = x elsewhere: the same values, −0.0 aside); one
            # assignment a value (issue 14, round 10: no 4-tuple built and unpacked per line)
            a0 = g0 * cr
            b0 = g0 * ci
            a1 = g1 * cr
            b1 = g1 * ci
            a2 = g2 * cr
            b2 = g2 * ci
            a3 = g3 * cr
            b3 = g3 * ci
            e0 = a0 * w0
            f0 = b0 * w0
            e1 = a0 * w1
            f1 = b0 * w1
            e2 = a1 * w0
            f2 = b1 * w0
            e3 = a1 * w1
            f3 = b1 * w1
            e4 = a2 * w0
            f4 = b2 * w0
            e5 = a2 * w1
            f5 = b2 * w1
            e6 = a3 * w0
            f6 = b3 * w0
            e7 = a3 * w1
            f7 = b3 * w1
            pc.t3_lo[j](e0, f0, e0, f0, e0, f0, e1, f1, e1, f1, e1, f1,
                        e2, f2, e2, f2, e2, f2, e3, f3, e3, f3, e3, f3)
            pc.t3_hi[j](e4, f4, e4, f4, e4, f4, e5, f5, e5, f5, e5, f5,
                        e6, f6, e6, f6, e6, f6, e7, f7, e7, f7, e7, f7)
            x3 += pc.t3  # x[:, j : j + 2] += c_b·Λ (4, 2), in the 3 copies
        else:
            coef = complex(cr, ci)
            gc = np.array((g0 * coef, g1 * coef, g2 * coef, g3 * coef))  # c_b (4,)
            for j, w in straddle_bins(r, gate, ru):
                x3[:, j] += (gc * w)[:, None]
        x = pc.xrows[i]  # this pulse's x (4, 16), target included (filter 1's copy)
        if self.mti:  # MTI canceller Σ_i h_i x[n − i] below mti_max_el (radar/mti.py)
            on = self._mti_on  # mti_switch(on, el, max_el, hysteresis), written out
            max_el = self.mti_max_el
            if el < max_el:
                on = self._mti_on = True
            elif on and el > max_el + self.mti_hysteresis:  # (off stays off: round 10)
                on = self._mti_on = False
            if self.mti == 1:  # two-pulse: h0·(x − x[n−1]) (h1 = −h0); memory: this row
                if on:
                    _subtract(x, self._xh[0], out=pc.mo)
                    pc.mo *= MTI_TAPS_0D[1][0]
                    x3 = pc.mo3
                self._xh = pc.row1[i]  # a (1, 4, 16) view, copied before the rows change
            else:
                cancel_pulse_into(x, self._xh, MTI_TAPS_0D[self.mti], on, pc.mo, pc.mt)
                if on:
                    x3 = pc.mo3
        # Doppler filters: y[n] = p_f y[n−1] + (1 − ρ) x[n]   ((1 − ρ) already in x)
        y = self._y
        pin = pc.pin
        if fc != pin[0] or pri != pin[1]:  # p_f depends on (centre, PRI): re-form P
            pc.poles(self._filter_poles(fc, pri))
            pc.pin = (fc, pri)
        y *= pc.P
        y += x3
        self._pulse += 1

        self.t = t_new
        # ---- the outputs (tg_outputs.outputs, OUTPUTS) of this pulse's truth (st, r_t, …)
        rr = _MIN_RANGE if r_t < _MIN_RANGE else r_t  # max(r, MIN_RANGE), NaN kept as max
        rdot = (px * vx + py * vy + pz * vz) / rr
        # ρ̈ = d/dt (p·v/ρ) = (|v|² + p·a − ṙ²)/ρ (range acceleration along the line of sight)
        rddot = (vx * vx + vy * vy + vz * vz + px * ax + py * ay + pz * az_ - rdot * rdot) / rr
        snr = (self._a0 / (rr * rr)) ** 2
        o = _new_outputs()  # = self._otemplate.copy() (round 11)
        o["beam"] = _absolute(y)  # |y| (the fidelity is "pulse" here; np.abs is np.absolute)
        o["truth.x"] = px
        o["truth.y"] = py
        o["truth.z"] = pz
        o["truth.vx"] = vx
        o["truth.vy"] = vy
        o["truth.vz"] = vz
        o["truth.accel"] = sqrt(ax * ax + ay * ay + az_ * az_)
        o["truth.range"] = r_t
        o["truth.az"] = az_t
        o["truth.el"] = el_t
        o["truth.range_rate"] = rdot
        o["truth.range_acc"] = rddot
        o["truth.apparent_range"] = r_t % ru  # Ru = c·PRI/2: ru above, the same product
        o["truth.doppler"] = -2.0 * rdot / self.wavelength  # radar.py doppler_hz
        # max(snr, 1e-30) as a comparison (NaN kept as max keeps it): floor −300 dB (rcs = 0)
        o["truth.snr_db"] = 10.0 * log10(1e-30 if snr < 1e-30 else snr)
        o["truth.rcs"] = (self.rcs * abs(self._fluct) ** 2 if self.swerling == 1
                          else self.rcs * 1.0)
        m = self._meas
        o["meas.range"] = m[0]
        o["meas.az"] = m[1]
        o["meas.el"] = m[2]
        o["meas.valid"] = self._meas_valid
        o["meas.new"] = False  # bool(meas and …) with meas False
        o["input.invalid"] = self._invalid
        o["input.invalid.count"] = self._invalid_count
        return o

    def get_state(self) -> dict[str, Any]:
        """:meth:`Unit.get_state` without the derived buffers of the one-pulse path."""
        v, seg = self.__dict__.pop("_v", None), self.__dict__.pop("_seg", _NO_SEG)
        try:
            return super().get_state()
        finally:
            self._v, self._seg = v, seg

    def set_state(self, state: Mapping[str, Any]) -> None:
        """:meth:`Unit.set_state`; the buffers of the one-pulse path are rebuilt on first use."""
        super().set_state(state)
        self._v, self._seg = None, _NO_SEG

    def _hold_valid(self, inputs: Mapping[str, Any]) -> dict[str, float]:
        """Inputs as floats; an input that is not a finite number (or a pri shorter than the
        window) keeps its last valid value and flags ``input.invalid`` (assumption: a unit
        degrades, it does not stop)."""
        u, bad = hold_inputs(inputs, self._last_u, _IN_DEFAULTS, _IN_FLOORS)
        self._last_u = u
        if self._invalid_noted:  # see note_invalid_inputs
            self._invalid_noted, bad = False, True
        self._invalid = bad
        self._invalid_count += bad
        return u
