"""Two-axis servo pedestal with double potentiometers (seed 000 "Pedestal", Figs 6-7 lost).

Seed facts (seed 000 "Pedestal"): the antenna is free to rotate 360° in azimuth *and* in
elevation; pedestal angles are available at each PRI; each axis is read by double
potentiometers giving a voltage proportional to the angle, "for example 1 V/degree"; the second
potentiometer removes the 360° → 0° discontinuity of a single one. Figures 6-7 (the devices)
are lost; everything below that is not in that paragraph is a documented assumption.

Axis dynamics (per axis, azimuth θ and elevation φ alike)
-------------------------------------------------------
The tracker sends a *rate command* voltage u [V] (SYSTEM.md: ``cmd.az``, ``cmd.el``). The
pedestal is a rate servo (assumption: velocity-loop motor drive, the usual low-cost robotic
drive the seed mentions), modelled as the type-1 second-order servo

    θ(s) / u(s) = K / (s (1 + τ s)),   K = ``rate_per_volt`` [rad/s/V],  τ = 1 / (2π B)

i.e. the commanded rate r = K·u is followed by the motor rate ω through a first-order lag of
time constant τ, whose −3 dB bandwidth B [Hz] is the ``bandwidth`` input (commanded by the
radar manager, AXIR_C; assumption: B is the rate-loop bandwidth), and the angle is the integral
of ω. With the two limits (assumption: motor/amplifier saturations):

    r   = clip(K·u, −ω_max, +ω_max)                       # rate limit ``rate_limit_*``
    dω/dt = clip((r − ω)/τ, −a_max, +a_max)               # acceleration limit ``accel_limit_*``
    dθ/dt = ω

Sign convention (SYSTEM.md): a positive ``cmd.az`` turns the antenna clockwise (North → East),
a positive ``cmd.el`` raises it. Because ω moves monotonically towards r without overshoot,
|ω| ≤ ω_max and |dω/dt| ≤ a_max hold exactly (the results are also clipped against rounding).

Integration is *exact* for a command held constant over the communication step (zero-order
hold, the FMI co-simulation semantics), piecewise analytic: first a constant-acceleration
phase while |r − ω| > a_max τ, then the exponential phase. There is no internal step, so any
``dt`` (50 µs … 0.1 s and beyond) gives the same trajectory up to rounding, and a change of
``bandwidth`` between steps is simply a new τ for the next step.

Potentiometers and decoding (seed 000 Figs 6-7, restated in SYSTEM.md)
--------------------------------------------------------------------
Pot A reads the shaft angle modulo 360°:  V_A = k · (θ mod 2π),  k = ``pot_gain`` [V/rad]
(default 180/π V/rad = 1 V/deg, seed). Pot B is identical, mounted with its zero rotated by
``pot_b_offset`` (default π = 180°, assumption: our reading of "calibrated to 0° when the first
passed 360°", the offset that puts the two discontinuities as far apart as possible):
V_B = k · ((θ − offset) mod 2π). Each voltage gets additive Gaussian noise σ = ``pot_noise``
[V] (assumption) and is converted by an ``adc_bits`` ADC spanning [0, k·2π) (assumption): code =
round(V / LSB) clipped to [0, 2^bits − 1], LSB = k·2π / 2^bits.

The decoder (:func:`decode_pots`, pure) reads both pots and uses the one whose reading is
farther from its own discontinuity (0 ≡ 360°); with an offset in [90°, 270°] the chosen pot is
always ≥ 45° away from its jump, so noise or quantization never straddle it. The stateful
continuous-angle tracker (:func:`unwrap_step`) then adds the wrapped difference to the
previous continuous angle, so the decoded angle crosses 360° → 0° (and 0° → 360°) without a
jump. This is unambiguous as long as the shaft moves less than π per communication step
(|ω| ≤ ``rate_limit`` ≤ 20 rad/s → any dt < 0.157 s). Outputs: ``az`` wrapped to [0, 2π) (the
tracker's azimuth convention), ``el`` continuous (the elevation axis turns over freely), both
from the decoded pots, i.e. what the tracker reads.

Invalid inputs: a non-finite ``cmd.az``/``cmd.el`` is treated as 0 V for that step (the motor
is driven towards rest); a non-finite or non-positive ``bandwidth`` keeps the last valid one;
either case sets the Boolean output ``input.invalid`` for that step and increments the
``input.invalid.count`` counter. A finite bandwidth outside the ``bandwidth`` parameter range
[0.01, 100] Hz is clipped to it (not counted as invalid). Missing inputs: 0 V commands, last
bandwidth (initially the ``bandwidth`` parameter).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from math import isfinite
from typing import Any

import numpy as np

from .radar.params import Param
from .radar.ports import Port
from .radar.unit import Unit

TWO_PI = 2.0 * math.pi
BW_MIN = 0.01  # smallest accepted servo bandwidth [Hz] (assumption)
BW_MAX = 100.0  # largest accepted servo bandwidth [Hz] (assumption)
BANDWIDTH0 = 2.0  # servo bandwidth before the input provides one [Hz] (assumption)
CMD_MAX = 1.0e6  # [V] domain of the rate commands (out of domain: 0 V, as non-finite ones)
_NOISE_BLOCK = 256  # standard normals drawn per refill of the noise block (multiple of 4)

#: Public inputs.
INPUTS: tuple[Port, ...] = (
    Port("cmd.az", float, "V", "azimuth rate command (positive: clockwise, North to East)",
         low=-CMD_MAX, high=CMD_MAX, invalid="start"),
    Port("cmd.el", float, "V", "elevation rate command (positive: upwards)",
         low=-CMD_MAX, high=CMD_MAX, invalid="start"),
    Port("bandwidth", float, "Hz", "servo (rate-loop) bandwidth B, time constant 1/(2 pi B)",
         start=BANDWIDTH0, low=0.0, high=1.0e6),
)

#: Public outputs.
OUTPUTS: tuple[Port, ...] = (
    Port("az", float, "rad", "azimuth decoded from the potentiometers, in [0, 2 pi)"),
    Port("el", float, "rad", "elevation decoded from the potentiometers, continuous"),
    Port("az.rate", float, "rad/s", "azimuth rate"),
    Port("el.rate", float, "rad/s", "elevation rate"),
    Port("az.acc", float, "rad/s2", "azimuth acceleration at the end of the step"),
    Port("el.acc", float, "rad/s2", "elevation acceleration at the end of the step"),
    Port("pot.az.a", float, "V", "azimuth potentiometer A (ADC output)"),
    Port("pot.az.b", float, "V", "azimuth potentiometer B (ADC output)"),
    Port("pot.el.a", float, "V", "elevation potentiometer A (ADC output)"),
    Port("pot.el.b", float, "V", "elevation potentiometer B (ADC output)"),
    Port("az.unwrapped", float, "rad", "azimuth decoded from the potentiometers, continuous"),
    Port("az.true", float, "rad", "true azimuth shaft angle, in [0, 2 pi)"),
    Port("el.true", float, "rad", "true elevation shaft angle, continuous"),
    Port("input.invalid", bool, "1", "true if this step had a non-finite command or invalid "
         "bandwidth"),
    Port("input.invalid.count", int, "1", "number of steps with invalid inputs since reset"),
)


def propagate_axis(
    theta: float, omega: float, r: float, tau: float, a_max: float, dt: float,
    em: float | None = None,
) -> tuple[float, float, float]:
    """Advance one axis exactly over ``dt`` [s] with the rate target held constant.

    Solves dω/dt = clip((r − ω)/τ, ±a_max), dθ/dt = ω  (module docstring; assumption):
    :func:`_servo_axis` without a rate limit (its clips leave every value, NaN included,
    unchanged at ±inf).

    Args:
        theta: angle [rad] at the start of the step (continuous, unwrapped).
        omega: rate [rad/s] at the start of the step.
        r: rate target [rad/s], already clipped to the rate limit.
        tau: time constant [s] (> 0).
        a_max: acceleration limit [rad/s²] (> 0).
        dt: step [s] (≥ 0).
        em: exp(−dt/τ) − 1 for this dt and τ when the caller already has it (the Pedestal
            computes it once for both axes, issue 14); None: computed here. Not used when a
            ramp phase shortens the exponential one.

    Returns:
        (theta, omega, acceleration) at the end of the step [rad, rad/s, rad/s²].
    """
    return _servo_axis(theta, omega, r, math.inf, a_max, tau, dt, em)


def _servo_axis(theta: float, omega: float, r: float, lim: float, a_max: float, tau: float,
                dt: float, em: float | None) -> tuple[float, float, float]:
    """One axis over ``dt`` [s] (the servo equations, :func:`propagate_axis`'s arguments):
    rate target ``r`` [rad/s] clipped to ±``lim`` [rad/s], the exact propagation (``em`` =
    exp(−dt/τ) − 1 or None), the rate clipped again against rounding; returns (θ [rad],
    ω [rad/s], acceleration [rad/s²]). The Pedestal's step calls it per axis (issue 14: one
    call per axis, the clips and the propagation in one body)."""
    r = lim if r > lim else (-lim if r < -lim else r)
    e = r - omega
    sat = a_max * tau  # |r − ω| above which the acceleration limit is active
    if e > sat or e < -sat:
        s = a_max if e > 0.0 else -a_max
        t1 = (abs(e) - sat) / a_max  # duration of the constant-acceleration phase
        if t1 >= dt:  # the ramp fills the step
            w = omega + s * dt
            return (theta + (omega + 0.5 * s * dt) * dt,
                    lim if w > lim else (-lim if w < -lim else w), s)
        theta += (omega + 0.5 * s * t1) * t1
        e = sat if e > 0.0 else -sat  # ω = r − e exactly at the end of the ramp
        dt -= t1
        em = None
    # exponential phase: ω(t) = r − e·exp(−t/τ), ∫ω = r t − e τ (1 − exp(−t/τ))
    if em is None:
        em = math.expm1(-dt / tau)  # exp(−t/τ) − 1
    theta += r * dt + e * tau * em
    e_new = e * (em + 1.0)
    acc = e_new / tau
    if acc > a_max:  # rounding guard only
        acc = a_max
    elif acc < -a_max:
        acc = -a_max
    omega = r - e_new
    return theta, (lim if omega > lim else (-lim if omega < -lim else omega)), acc


def wrap_2pi(a: float) -> float:
    """Wrap an angle to [0, 2π) [rad], guarding the rounding of tiny negatives to 2π."""
    w = a % TWO_PI
    return 0.0 if w >= TWO_PI else w


def quantize(v: float, lsb: float, n_codes: int) -> float:
    """ADC: round ``v`` [V] to the nearest code, clipped to [0, n_codes − 1]; returns volts.

    # assumption: unipolar ADC spanning exactly one potentiometer turn [0, k·2π)
    """
    code = round(v / lsb)
    if code < 0:
        code = 0
    elif code >= n_codes:
        code = n_codes - 1
    return code * lsb


def decode_pots(v_a: float, v_b: float, pot_gain: float, pot_b_offset: float) -> float:
    """Angle [rad] in [0, 2π) from the two potentiometer voltages [V] (pure function).

    Uses the pot whose reading is farther from its own discontinuity (0 ≡ 2π)  # seed 000
    Figs 6-7 (second pot removes the 360° → 0° discontinuity); pot B reads θ − pot_b_offset.

    Args:
        v_a, v_b: voltages of pots A and B [V].
        pot_gain: potentiometer gain k [V/rad].
        pot_b_offset: angular offset of pot B's zero [rad].
    """
    a = v_a / pot_gain
    b = v_b / pot_gain
    da = a if a < math.pi else TWO_PI - a  # distance of pot A's reading to its jump
    db = b if b < math.pi else TWO_PI - b
    ang = a if da >= db else b + pot_b_offset
    return wrap_2pi(ang)


def unwrap_step(previous: float, wrapped: float) -> float:
    """Continuous angle [rad]: ``previous`` plus the wrapped difference to ``wrapped`` [rad].

    # assumption: the shaft moves less than π between two readings (one per step)
    """
    d = (wrapped - previous + math.pi) % TWO_PI - math.pi
    return previous + d


class Pedestal(Unit):
    """Two-axis (azimuth, elevation) rate-servo pedestal with double potentiometers.

    Inputs (``step``): ``cmd.az``, ``cmd.el`` [V], ``bandwidth`` [Hz]. Outputs: see
    :data:`OUTPUTS` (``az``, ``el`` [rad] decoded from the pots, rates [rad/s], pot voltages
    [V], true angles [rad], invalid-input flag and counter). Model: module docstring.
    """

    INPUTS = INPUTS
    STEP_ARGS = ("cmd.az", "cmd.el", "bandwidth")  # step(dt, None, cmd_az, cmd_el, bandwidth)
    OUTPUTS = OUTPUTS

    PARAMS = (
        Param("rate_per_volt", 0.1, "rad/(s.V)",
              "rate command gain K: commanded rate = K * cmd (assumption; tracker uses the same)",
              low=0.0, high=10.0, low_open=True),
        Param("rate_limit_az", 1.0, "rad/s", "azimuth rate limit (assumption)",
              low=0.0, high=20.0, low_open=True),
        Param("rate_limit_el", 1.0, "rad/s", "elevation rate limit (assumption)",
              low=0.0, high=20.0, low_open=True),
        Param("accel_limit_az", 2.0, "rad/s2", "azimuth acceleration limit (assumption)",
              low=0.0, high=1000.0, low_open=True),
        Param("accel_limit_el", 2.0, "rad/s2", "elevation acceleration limit (assumption)",
              low=0.0, high=1000.0, low_open=True),
        Param("bandwidth", BANDWIDTH0, "Hz",
              "servo bandwidth used until the input provides one; also the accepted range",
              low=BW_MIN, high=BW_MAX, fmi_name="bandwidth0"),  # the input is `bandwidth`
        Param("az0", 0.0, "rad", "initial azimuth", low=0.0, high=TWO_PI, high_open=True),
        Param("el0", 0.0, "rad", "initial elevation", low=-math.pi, high=math.pi),
        Param("pot_gain", 180.0 / math.pi, "V/rad",
              "potentiometer gain k (seed 000: 1 V/deg = 180/pi V/rad)",
              low=0.0, high=1.0e4, low_open=True),
        Param("pot_b_offset", math.pi, "rad",
              "angle at which pot B reads 0 (seed 000 Figs 6-7; 180 deg assumption)",
              low=0.5 * math.pi, high=1.5 * math.pi),
        Param("adc_bits", 16, "1", "ADC resolution over one pot turn (assumption)",
              low=8, high=32),
        Param("pot_noise", 0.005, "V", "additive Gaussian noise sigma per pot (assumption)",
              low=0.0, high=1.0e3),  # above 10·noise < gain·π/4 (≤ 7854 V) anyway
        Param("seed", 0, "1", "seed of the potentiometer noise generator (PCG64)",
              low=0, high=2**31 - 1),  # an FMI Integer is 32-bit
    )

    # declared for type checkers; set by Configurable.configure
    rate_per_volt: float
    rate_limit_az: float
    rate_limit_el: float
    accel_limit_az: float
    accel_limit_el: float
    bandwidth: float
    az0: float
    el0: float
    pot_gain: float
    pot_b_offset: float
    adc_bits: int
    pot_noise: float
    seed: int

    def _check(self) -> None:
        """Cross-parameter check: noise must stay far below the decoder's 45° margin."""
        margin = self.pot_gain * math.pi / 4.0  # [V], 45° of pot travel (see decode_pots)
        if 10.0 * self.pot_noise >= margin:
            raise ValueError(
                f"parameter Pedestal.pot_noise = {self.pot_noise!r} V is out of range for "
                f"pot_gain = {self.pot_gain!r} V/rad: need 10 * pot_noise < pot_gain * pi/4 "
                f"= {margin!r} V (decoder margin)"
            )

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """Rest at (az0, el0); decoder initialised on the known parking angles (assumption)."""
        self._rng = np.random.Generator(np.random.PCG64(self.seed))
        self._noise: list[float] = []  # block of standard normals, consumed 4 per sample
        self._noise_i = _NOISE_BLOCK  # index of the next unused draw (block empty)
        self._n_codes = 1 << self.adc_bits
        self._lsb = self.pot_gain * TWO_PI / self._n_codes  # [V]
        self._bw = float(self.bandwidth)  # last valid bandwidth [Hz]
        self._tau = 1.0 / (TWO_PI * self._bw)  # its time constant [s] (step: assumption)
        self._az = float(self.az0)  # true continuous shaft angles [rad]
        self._el = float(self.el0)
        self._az_rate = 0.0  # [rad/s]
        self._el_rate = 0.0
        self._az_acc = 0.0  # [rad/s²]
        self._el_acc = 0.0
        self._az_dec = float(self.az0)  # continuous decoded angles [rad]
        self._el_dec = float(self.el0)
        self._invalid_count = 0
        self._invalid_noted = False  # set by note_invalid_inputs for the coming step
        self._em_dt = self._em_tau = math.nan  # (dt [s], τ [s]) of the cached _em
        self._em = math.nan  # expm1(−dt/τ) at (_em_dt, _em_tau)
        self._outputs = self._sample(False)

    def outputs(self) -> dict[str, Any]:
        """Outputs of the last step (or of the initial state after ``reset``)."""
        return dict(self._outputs)

    def note_invalid_inputs(self, names: list[str]) -> None:
        """Out-of-domain inputs were replaced by the caller (commands by 0 V, the bandwidth by
        the last valid one): flag ``input.invalid`` in the coming step and count it."""
        self._invalid_noted = True

    # ------------------------------------------------------------------ step
    def step(self, dt: float, inputs: Mapping[str, Any] | None, cmd_az: Any = ...,
             cmd_el: Any = ..., bandwidth: Any = ...) -> dict[str, Any]:
        """Advance ``dt`` [s] with commands held constant; return the outputs at t + dt.

        ``dt == 0`` returns the previous outputs unchanged (no ADC conversion). The returned
        mapping is the unit's record of its outputs: read it, do not modify it. ``inputs``
        None: the inputs are ``cmd_az``, ``cmd_el`` [V] and ``bandwidth`` [Hz] (the run loop's
        positional call, :data:`STEP_ARGS`; the same as the mapping of the three; a value
        not given: TypeError).
        """
        if not dt > 0.0 or dt == math.inf:
            if dt == 0.0:
                return dict(self._outputs)
            raise ValueError(f"Pedestal.step: dt = {dt!r} s must be finite and >= 0")
        invalid = self._invalid_noted  # see note_invalid_inputs
        if invalid:
            self._invalid_noted = False
        try:  # common path: a dict of three finite numbers (issue 14, round 9: subscripts, no
            # get calls; another Mapping or a missing key: _screen's get path, the same values)
            if inputs is not None:  # a mapping: its values, read as the positional call has
                if type(inputs) is not dict:  # them (round 11: shared conversions below)
                    raise KeyError
                cmd_az = inputs["cmd.az"]
                cmd_el = inputs["cmd.el"]
                bandwidth = inputs["bandwidth"]
            u_az = float(cmd_az)
            u_el = float(cmd_el)
            bw = float(bandwidth)
            # one isfinite for the three (inf/NaN propagate; a finite sum that overflows only
            # takes the item-by-item path, which finds nothing invalid)
            ok = isfinite(u_az + u_el + bw) and bw > 0.0
        except (TypeError, ValueError, KeyError):
            ok = False
        if not ok:
            if inputs is None:  # the positional call: the mapping it stands for
                if cmd_az is ... or cmd_el is ... or bandwidth is ...:
                    raise TypeError("Pedestal.step: inputs None takes the values of STEP_ARGS")
                inputs = {"cmd.az": cmd_az, "cmd.el": cmd_el, "bandwidth": bandwidth}
            u_az, u_el, bw, bad = self._screen(inputs)
            invalid = invalid or bad
        bw = BW_MIN if bw < BW_MIN else (BW_MAX if bw > BW_MAX else bw)
        if bw != self._bw:
            self._bw = bw
            self._tau = 1.0 / (TWO_PI * bw)  # first-order lag, −3 dB at B (assumption)
        if invalid:
            self._invalid_count += 1
        tau = self._tau
        # exp(−dt/τ) − 1 of the exponential phase (propagate_axis), the same for both axes and
        # for every step of the same (dt, τ): computed once per (dt, τ) (issue 14, round 5)
        if dt != self._em_dt or tau != self._em_tau:
            self._em_dt, self._em_tau = dt, tau
            self._em = math.expm1(-dt / tau)
        em = self._em

        # per axis: commanded rate K·u clipped to ±rate_limit, then propagate_axis; the rate
        # is clipped again against rounding only (module docstring). _servo_axis per axis, its
        # usual case (no acceleration limit: the exponential phase alone, em given) written
        # out here (issue 14, round 7: no call, no tuple), the same operations; a ramp calls it
        k = self.rate_per_volt
        em1 = em + 1.0  # exp(−dt/τ)
        lim = self.rate_limit_az
        a_max = self.accel_limit_az
        r = k * u_az
        r = lim if r > lim else (-lim if r < -lim else r)
        omega = self._az_rate
        e = r - omega
        sat = a_max * tau  # |r − ω| above which the acceleration limit is active
        if e > sat or e < -sat:
            self._az, self._az_rate, self._az_acc = az, az_rate, az_acc = _servo_axis(
                self._az, omega, r, lim, a_max, tau, dt, em)
        else:  # exponential phase: θ += r t − e τ (1 − exp(−t/τ)), ω = r − e·exp(−t/τ)
            self._az = az = self._az + (r * dt + e * tau * em)
            e = e * em1
            acc = e / tau
            self._az_acc = az_acc = a_max if acc > a_max else (-a_max if acc < -a_max else acc)
            omega = r - e
            self._az_rate = az_rate = lim if omega > lim else (-lim if omega < -lim else omega)
        lim = self.rate_limit_el
        a_max = self.accel_limit_el
        r = k * u_el
        r = lim if r > lim else (-lim if r < -lim else r)
        omega = self._el_rate
        e = r - omega
        sat = a_max * tau
        if e > sat or e < -sat:
            self._el, self._el_rate, self._el_acc = el, el_rate, el_acc = _servo_axis(
                self._el, omega, r, lim, a_max, tau, dt, em)
        else:
            self._el = el = self._el + (r * dt + e * tau * em)
            e = e * em1
            acc = e / tau
            self._el_acc = el_acc = a_max if acc > a_max else (-a_max if acc < -a_max else acc)
            omega = r - e
            self._el_rate = el_rate = lim if omega > lim else (-lim if omega < -lim else omega)

        # _sample(invalid) written out (issue 14, round 9: no call; the angles, rates and
        # accelerations from the locals above; az mod 2π computed once for the pot and the
        # truth), the same operations in the same order: read the four pots (noise + ADC),
        # decode, unwrap. seed 000 "Pedestal": one reading per step
        g = self.pot_gain
        off = self.pot_b_offset
        lsb = self._lsb
        n = self._n_codes
        t = az % TWO_PI  # wrap_2pi(az), before its ≥ 2π check below
        # seed 000: V = k·(angle mod 360°), pot B zeroed at pot_b_offset
        v0 = g * t  # (one assignment a value: no 4-tuple, issue 14, round 10)
        v1 = g * ((az - off) % TWO_PI)
        v2 = g * (el % TWO_PI)
        v3 = g * ((el - off) % TWO_PI)
        s = self.pot_noise
        if s > 0.0:
            i = self._noise_i
            if i + 4 > _NOISE_BLOCK:  # refill: standard normals drawn in blocks (speed)
                self._noise = self._rng.standard_normal(_NOISE_BLOCK).tolist()
                i = 0
            nz = self._noise
            v0 = v0 + s * nz[i]
            v1 = v1 + s * nz[i + 1]
            v2 = v2 + s * nz[i + 2]
            v3 = v3 + s * nz[i + 3]
            self._noise_i = i + 4
        top = n - 1
        pi = math.pi
        c = round(v0 / lsb)  # quantize(v0, lsb, n)
        pa_a = (0 if c < 0 else (top if c >= n else c)) * lsb
        c = round(v1 / lsb)
        pa_b = (0 if c < 0 else (top if c >= n else c)) * lsb
        c = round(v2 / lsb)
        pe_a = (0 if c < 0 else (top if c >= n else c)) * lsb
        c = round(v3 / lsb)
        pe_b = (0 if c < 0 else (top if c >= n else c)) * lsb
        a = pa_a / g  # decode_pots(pa_a, pa_b, g, off)
        b = pa_b / g
        ang = a if (a if a < pi else TWO_PI - a) >= (b if b < pi else TWO_PI - b) else b + off
        w = ang % TWO_PI  # wrap_2pi
        if w >= TWO_PI:
            w = 0.0
        prev = self._az_dec  # unwrap_step(prev, w)
        self._az_dec = az_dec = prev + ((w - prev + pi) % TWO_PI - pi)
        a = pe_a / g  # decode_pots(pe_a, pe_b, g, off)
        b = pe_b / g
        ang = a if (a if a < pi else TWO_PI - a) >= (b if b < pi else TWO_PI - b) else b + off
        w = ang % TWO_PI
        if w >= TWO_PI:
            w = 0.0
        prev = self._el_dec
        self._el_dec = el_dec = prev + ((w - prev + pi) % TWO_PI - pi)
        w = az_dec % TWO_PI  # wrap_2pi(az_dec)
        self._outputs = out = {
            "az": 0.0 if w >= TWO_PI else w,
            "el": el_dec,
            "az.rate": az_rate,
            "el.rate": el_rate,
            "az.acc": az_acc,
            "el.acc": el_acc,
            "pot.az.a": pa_a,
            "pot.az.b": pa_b,
            "pot.el.a": pe_a,
            "pot.el.b": pe_b,
            "az.unwrapped": az_dec,
            "az.true": 0.0 if t >= TWO_PI else t,
            "el.true": el,
            "input.invalid": invalid,
            "input.invalid.count": self._invalid_count,
        }
        return out

    def _screen(self, inputs: Mapping[str, Any]) -> tuple[float, float, float, bool]:
        """(cmd.az [V], cmd.el [V], bandwidth [Hz], invalid) with the documented replacements:
        a missing command is 0 V, an invalid one 0 V; a missing bandwidth is the last valid
        one, an invalid one too (module docstring)."""
        invalid = False
        u_az = inputs.get("cmd.az", 0.0)
        u_el = inputs.get("cmd.el", 0.0)
        bw = inputs.get("bandwidth", self._bw)
        try:
            u_az = float(u_az)
            if not math.isfinite(u_az):
                raise ValueError
        except (TypeError, ValueError):
            u_az, invalid = 0.0, True  # documented: invalid command -> 0 V
        try:
            u_el = float(u_el)
            if not math.isfinite(u_el):
                raise ValueError
        except (TypeError, ValueError):
            u_el, invalid = 0.0, True
        try:
            bw = float(bw)
            if not (math.isfinite(bw) and bw > 0.0):
                raise ValueError
        except (TypeError, ValueError):
            bw, invalid = self._bw, True  # documented: keep the last valid bandwidth
        return u_az, u_el, bw, invalid

    def _sample(self, invalid: bool) -> dict[str, Any]:
        """Read the four pots (noise + ADC), decode, update the continuous trackers.

        # seed 000 "Pedestal": angles are available at each PRI, i.e. one reading per step.
        """
        g = self.pot_gain
        off = self.pot_b_offset
        lsb = self._lsb
        n = self._n_codes
        az, el = self._az, self._el
        # seed 000: V = k·(angle mod 360°), pot B zeroed at pot_b_offset
        v0, v1, v2, v3 = g * (az % TWO_PI), g * ((az - off) % TWO_PI), \
            g * (el % TWO_PI), g * ((el - off) % TWO_PI)
        s = self.pot_noise
        if s > 0.0:
            i = self._noise_i
            if i + 4 > _NOISE_BLOCK:  # refill: standard normals drawn in blocks (speed)
                self._noise = self._rng.standard_normal(_NOISE_BLOCK).tolist()
                i = 0
            nz = self._noise
            v0, v1, v2, v3 = v0 + s * nz[i], v1 + s * nz[i + 1], v2 + s * nz[i + 2], \
                v3 + s * nz[i + 3]
            self._noise_i = i + 4
        # quantize (ADC), decode_pots and unwrap_step of each axis, written out: the same
        # operations in the same order, without 10 calls per sample (issue 14, round 3;
        # tests/test_pedestal.py checks them against the helpers)
        top = n - 1
        c = round(v0 / lsb)  # quantize(v0, lsb, n)
        pa_a = (0 if c < 0 else (top if c >= n else c)) * lsb
        c = round(v1 / lsb)
        pa_b = (0 if c < 0 else (top if c >= n else c)) * lsb
        c = round(v2 / lsb)
        pe_a = (0 if c < 0 else (top if c >= n else c)) * lsb
        c = round(v3 / lsb)
        pe_b = (0 if c < 0 else (top if c >= n else c)) * lsb
        pi = math.pi
        a = pa_a / g  # decode_pots(pa_a, pa_b, g, off)
        b = pa_b / g
        ang = a if (a if a < pi else TWO_PI - a) >= (b if b < pi else TWO_PI - b) else b + off
        w = ang % TWO_PI  # wrap_2pi
        if w >= TWO_PI:
            w = 0.0
        prev = self._az_dec  # unwrap_step(prev, w)
        self._az_dec = az_dec = prev + ((w - prev + pi) % TWO_PI - pi)
        a = pe_a / g  # decode_pots(pe_a, pe_b, g, off)
        b = pe_b / g
        ang = a if (a if a < pi else TWO_PI - a) >= (b if b < pi else TWO_PI - b) else b + off
        w = ang % TWO_PI
        if w >= TWO_PI:
            w = 0.0
        prev = self._el_dec
        self._el_dec = el_dec = prev + ((w - prev + pi) % TWO_PI - pi)
        w = az_dec % TWO_PI  # wrap_2pi(az_dec)
        t = az % TWO_PI  # wrap_2pi(az)
        return {
            "az": 0.0 if w >= TWO_PI else w,
            "el": el_dec,
            "az.rate": self._az_rate,
            "el.rate": self._el_rate,
            "az.acc": self._az_acc,
            "el.acc": self._el_acc,
            "pot.az.a": pa_a,
            "pot.az.b": pa_b,
            "pot.el.a": pe_a,
            "pot.el.b": pe_b,
            "az.unwrapped": az_dec,
            "az.true": 0.0 if t >= TWO_PI else t,
            "el.true": el,
            "input.invalid": invalid,
            "input.invalid.count": self._invalid_count,
        }
