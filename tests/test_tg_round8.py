"""Issue 14, round 8 (branch spd15): ``TargetGenerator._pulse1`` with
``geometry.boresight_offsets_cart``, ``MonopulseAntenna.gains_tuple`` and
``straddle.two_adjacent_bins`` written out equals, bit for bit, the former one-pulse path (main
684be29, kept below verbatim as the reference): random antenna pointing (on the target, off by
a few beamwidths, behind), gates placing the target in every bin, on the straddle's edges (the
last bin, within a bin of the aliased bin 0) and outside the window, PRIs changing, with
noise, clutter and the cancellers, Swerling 1; every output and the filter state after every
step.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Mapping
from math import asin, atan2, cos, floor, hypot, isfinite, sin, sqrt
from typing import Any

import numpy as np
import pytest

from axir.models.radar.conventions import BIN_M, N_BEAMS, N_BINS, C
from axir.models.radar.geometry import TWO_PI
from axir.models.radar.mti import MTI_TAPS_0D, cancel_pulse_into
from axir.models.radar.pulse1 import FLOOR_EL_MAX, PulseCache, clutter_gains_tuple
from axir.models.radar.straddle import straddle_bins
from axir.models.radar.tg_outputs import MIN_RANGE as _MIN_RANGE
from axir.models.target_generator import (
    _CHUNK,
    _DRAW_BLOCK,
    _IN_DEFAULTS,
    _N_CLUT,
    _PRI_MIN,
    TargetGenerator,
)

_D_AZ, _D_EL, _D_GATE, _D_FC, _D_PRI = (d for _, d in _IN_DEFAULTS)


# The two helpers of main 684be29's _pulse1, kept here as part of the reference (round 9
# wrote them out in the step; the models no longer carry them): verbatim.


def boresight_offsets_cart(
    x: float, y: float, z: float, rho: float, az_a: float, el_a: float
) -> tuple[float, float]:
    """``boresight_offsets`` of the target at (X, Y, Z) [m], range ``rho`` [m] (= |p|),
    from boresight (az_a, el_a) [rad] -> (lateral, elevation) [rad].

    The target unit vector is p/ρ (seed 000 "Spherical to Cartesian": cos φ sin θ = X/ρ,
    cos φ cos θ = Y/ρ, sin φ = Z/ρ) instead of the sines and cosines of atan2 angles (issue
    14: 4 trigonometric calls fewer; equal to ``boresight_offsets`` to rounding, tested).
    ρ = 0 (no direction) gives the direction (az, el) = (0, 0) as cart_to_sph does.
    """
    if rho > 0.0:
        ux, uy, uz = x / rho, y / rho, z / rho
    else:
        ux, uy, uz = 0.0, 1.0, 0.0
    ca, sa, ce, se = cos(az_a), sin(az_a), cos(el_a), sin(el_a)
    b = ux * ce * sa + uy * ce * ca + uz * se  # boresight
    r = ux * ca - uy * sa  # right (east at az = 0)
    u = -ux * se * sa - uy * se * ca + uz * ce  # up
    # max(−1, min(1, u)) as comparisons (NaN → 1 as there; issue 14: no builtin calls)
    u = u if u < 1.0 else 1.0
    return atan2(r, b), asin(u if u > -1.0 else -1.0)


def two_adjacent_bins(r: float, gate_start: float, ru: float) -> tuple[int, float, float] | None:
    """The usual case of ``straddle_bins`` (issue 14, per-pulse path): (k, Λ_k, Λ_k+1) when
    the target falls between bins k and k + 1 of the window (0 ≤ k ≤ 14) and its aliased
    delay d1 − Ru is at least a bin away from bin 0; else None (use ``straddle_bins``).
    The same operations as ``straddle_bins``; Λ_k+1 may be 0 where that one leaves the
    bin out (q on a bin sample: adding 0 leaves the sample unchanged)."""
    d1 = (r - gate_start) % ru
    if d1 > ru - BIN_M:  # d1 − Ru within a bin of bin 0: both candidates count
        return None
    q = d1 / BIN_M
    k = floor(q)
    if k >= N_BINS - 1:
        return None
    return k, 1.0 - abs(q - k), 1.0 - abs(q - (k + 1))

_N_NOISE = 2 * N_BEAMS * 16
_SQRT_HALF = sqrt(0.5)


class _FormerTG(TargetGenerator):
    """The TargetGenerator with main 684be29's ``_pulse1`` (the reference of this module),
    called by main 5d4d36e's ``step`` (issue 14, round 9 wrote ``_pulse1`` and the output
    mapping out in ``step``: the reference keeps the step that calls them)."""

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """``TargetGenerator.step`` of main 5d4d36e, verbatim below this docstring: it calls
        ``_pulse1`` (below) and ``_outputs`` (round 9 wrote both out in the step).

        Advance by ``dt`` [s] (≥ 0) and return the outputs (see class docstring).

        Raises ``ValueError`` naming ``dt`` for a non-finite or negative step (state left
        unchanged). A non-finite input keeps its last valid value (``input.invalid``).
        """
        if (dt.__class__ is not float or not 0.0 <= dt < math.inf) and (  # a float: fine
                not isinstance(dt, (int, float)) or not math.isfinite(dt) or dt < 0.0):
            raise ValueError(f"TargetGenerator step dt = {dt!r} must be a finite number >= 0 [s]")
        # the input rule (_hold_valid, radar/hold.py) in its usual case written out: five
        # finite numbers as floats, pri above its floor, nothing noted (issue 14: no calls)
        get = inputs.get
        try:
            az = float(get("antenna.az", _D_AZ))
            el = float(get("antenna.el", _D_EL))
            gate = float(get("gate.start", _D_GATE))
            fc = float(get("doppler.centre", _D_FC))
            pri = float(get("pri", _D_PRI))
            usual = isfinite(az + el + gate + fc + pri) and pri >= _PRI_MIN  # as hold_inputs
        except (TypeError, ValueError):
            usual = False
        if usual and not self._invalid_noted:
            self._last_u = u = {"antenna.az": az, "antenna.el": el, "gate.start": gate,
                                "doppler.centre": fc, "pri": pri}
            self._invalid = False  # (the count unchanged)
        else:
            u = self._hold_valid(inputs)
            az, el, gate, fc, pri = (u["antenna.az"], u["antenna.el"], u["gate.start"],
                                     u["doppler.centre"], u["pri"])
        t_new = self.t + float(dt)
        if self.fidelity == "measurement":
            self._measure(t_new)
        elif dt > 0.0:
            if dt / pri < 1.5:  # max(1, round(dt/pri)) == 1 (round half to even: 1.5 -> 2)
                self._pulse1(t_new, az, el, gate, fc, pri)
            else:
                n_total = round(dt / pri)
                done = 0
                while done < n_total:  # chunks keep memory bounded for very long steps
                    n = min(_CHUNK, n_total - done)
                    k = np.arange(done, done + n)
                    self._pulses(t_new - (n_total - 1 - k) * pri, u)
                    done += n
        self.t = t_new
        return self._outputs(t_new, pri)

    def _pulse1(self, t: float, az_a: float, el_a: float, gate: float, fc: float, pri: float
                ) -> None:
        """``TargetGenerator._pulse1`` of main 684be29, verbatim below (the reference).

        One pulse at time ``t`` [s] for the inputs antenna.az, antenna.el [rad],
        gate.start [m], doppler.centre [Hz], pri [s]: the scalar fast path of :meth:`_pulses`
        (same draws and equations; issue 14 round 3 reorders floating-point operations, tested
        equal to rounding: s = 1 − ρ folded into the inputs, noise and clutter per block:
        PulseCache)."""
        clutter = self.clutter
        if clutter:  # the clutter gains (4,) as Python floats, written out (issue 14, round 7):
            # the same tuple object while its values do not change (all at the sidelobe floor
            # between _cg_lo and FLOOR_EL_MAX); _cg_moved when they change
            if el_a != self._cg_key:
                g = (self._cg_floor if self._cg_lo < el_a < FLOOR_EL_MAX
                     else clutter_gains_tuple(self._antenna, el_a, self._sidelobe))
                self._cg_moved = g != self._cg_vals
                if self._cg_moved:
                    self._cg_vals = g
                self._cg_key = el_a
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
                np.multiply(pc.correction(g, gp, s), c, out=pc.xc)
                x3 += pc.xc3
        # truth: trajectory, then (range, az, el) as geometry.cart_to_sph (same operations)
        st = self._traj.state_tuple(t)
        px, py, pz = st[0]
        h = hypot(px, py)
        r = sqrt(h * h + pz * pz)
        self._truth = (t, self._traj, st, r, atan2(px, py) % TWO_PI, atan2(pz, h))
        lat, elo = boresight_offsets_cart(px, py, pz, r, az_a, el_a)
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
        g0, g1, g2, g3 = self._antenna.gains_tuple(lat, elo)
        # x[b, j] += c_b · Λ_j in the bins of the straddle (Ru = c·PRI/2, radar.py), with
        # c_b = g_b·coef = s·a·F·g_b·e^(−j4πR/λ)
        sb = two_adjacent_bins(r, gate, 0.5 * C * pri)
        if sb is not None:  # the usual case: bins j, j + 1
            j, w0, w1 = sb
            # c_b·Λ as (re, im): complex × real written out on the parts (the same products
            # for finite values: (g·cr)·w, (g·ci)·w), then two C calls write the target row
            # (zero outside bins j, j + 1; each value once per filter) and one contiguous
            # add puts it into x (x + 0.0 = x elsewhere: the same values, −0.0 aside)
            a0, b0, a1, b1 = g0 * cr, g0 * ci, g1 * cr, g1 * ci
            a2, b2, a3, b3 = g2 * cr, g2 * ci, g3 * cr, g3 * ci
            e0, f0, e1, f1 = a0 * w0, b0 * w0, a0 * w1, b0 * w1
            e2, f2, e3, f3 = a1 * w0, b1 * w0, a1 * w1, b1 * w1
            e4, f4, e5, f5 = a2 * w0, b2 * w0, a2 * w1, b2 * w1
            e6, f6, e7, f7 = a3 * w0, b3 * w0, a3 * w1, b3 * w1
            pc.t3_lo[j](e0, f0, e0, f0, e0, f0, e1, f1, e1, f1, e1, f1,
                        e2, f2, e2, f2, e2, f2, e3, f3, e3, f3, e3, f3)
            pc.t3_hi[j](e4, f4, e4, f4, e4, f4, e5, f5, e5, f5, e5, f5,
                        e6, f6, e6, f6, e6, f6, e7, f7, e7, f7, e7, f7)
            x3 += pc.t3  # x[:, j : j + 2] += c_b·Λ (4, 2), in the 3 copies
        else:
            coef = complex(cr, ci)
            gc = np.array((g0 * coef, g1 * coef, g2 * coef, g3 * coef))  # c_b (4,)
            for j, w in straddle_bins(r, gate, 0.5 * C * pri):
                x3[:, j] += (gc * w)[:, None]
        x = pc.xrows[i]  # this pulse's x (4, 16), target included (filter 1's copy)
        if self.mti:  # MTI canceller Σ_i h_i x[n − i] below mti_max_el (radar/mti.py)
            on = self._mti_on  # mti_switch(on, el_a, max_el, hysteresis), written out
            max_el = self.mti_max_el
            if el_a < max_el:
                on = self._mti_on = True
            elif el_a > max_el + self.mti_hysteresis:
                on = self._mti_on = False
            if self.mti == 1:  # two-pulse: h0·(x − x[n−1]) (h1 = −h0); memory: this row
                if on:
                    np.subtract(x, self._xh[0], out=pc.mo)
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


def _bits(v: Any) -> Any:
    if isinstance(v, np.ndarray):
        return ("nd", v.dtype.str, v.shape, v.tobytes())
    if type(v) is float:
        return ("f", struct.pack("<d", v))
    return (type(v).__name__, v)


CASES = [
    {},
    {"swerling": 1, "dwell_pulses": 3},
    {"clutter": True, "mti": 1},
    {"clutter": True, "mti": 2, "swerling": 1},
    {"noise": False, "clutter": True, "mti": 2},
    # a target at the antenna (ρ = 0: no direction, the boresight-offset fallback)
    {"trajectory": '{"type": "cv", "position": [0, 0, 0], "velocity": [0, 0, 0]}'},
    # a still target whose up-axis offset rounds to 1.0000000000000002 (the clamp before asin)
    {"trajectory": '{"type": "cv", "position": [4000, 4000, 4000], "velocity": [0, 0, 0]}'},
]


@pytest.mark.parametrize("params", CASES)
def test_one_pulse_written_out_equals_the_former_pulse_bit_for_bit(params: dict[str, Any]
                                                                    ) -> None:
    """Twin generators, one with the former one-pulse path, stepped one PRI at a time with the
    same inputs: the same outputs (bits) and Doppler-filter state after every step; the
    straddle's usual case, its last-bin and aliased-edge fallbacks and targets outside the
    window all taken."""
    rng = np.random.default_rng(sum(map(ord, repr(params))))
    new, old = TargetGenerator(**params), TargetGenerator(**params)
    old.__class__ = _FormerTG
    o = new.outputs()
    seen = {"usual": 0, "last_bin": 0, "edge": 0, "outside": 0}
    pri = 1e-4
    for k in range(1500):
        if rng.random() < 0.02:
            pri = float(rng.choice([1e-4, 1.25e-4, 2e-4, 6.4e-5]))
        ru = 0.5 * C * pri
        r = o["truth.range"]
        u = rng.random()
        if u < 0.6:
            gate = r - rng.uniform(-0.5, 15.5) * BIN_M  # in the window, every bin
        elif u < 0.7:
            gate = r - 14.0 * BIN_M - rng.uniform(0.0, 1.0) * BIN_M  # the last bins
        elif u < 0.8:
            gate = r - ru + rng.uniform(0.0, 1.2) * BIN_M  # aliased, near bin 0
        elif u < 0.85:
            gate = r - float(rng.choice([0.0, 14.0, 15.0, 16.0])) * BIN_M  # on bin samples
        else:
            gate = float(rng.uniform(0.0, 6e4))
        v = rng.random()
        if v < 0.7:
            az = o["truth.az"] + rng.normal(0.0, 0.03)
            el = o["truth.el"] + rng.normal(0.0, 0.03)
        elif v < 0.9:
            az, el = rng.uniform(0.0, TWO_PI), rng.uniform(-0.1, 1.5)
        elif v < 0.95:
            az, el = o["truth.az"] + math.pi, float(rng.choice([0.0, math.pi / 2, -0.2]))
        else:  # the target on the antenna's up (down) axis: |up| at 1 ± rounding (the clamp)
            az = o["truth.az"]
            el = o["truth.el"] + float(rng.choice([-1.0, 1.0])) * math.pi / 2
        inp = {"antenna.az": az, "antenna.el": el, "gate.start": gate,
               "doppler.centre": float(rng.uniform(-3e3, 3e3)), "pri": pri}
        d1 = (r - gate) % ru
        if d1 > ru - BIN_M:
            seen["edge"] += 1
        elif d1 / BIN_M >= 15.0:
            seen["outside" if d1 / BIN_M >= 16.0 else "last_bin"] += 1
        else:
            seen["usual"] += 1
        o_old = old.step(pri, inp)
        o = new.step(pri, inp)
        assert list(o) == list(o_old)
        assert [_bits(x) for x in o.values()] == [_bits(x) for x in o_old.values()], k
        assert new._y.tobytes() == old._y.tobytes(), k
        assert new._xh.tobytes() == old._xh.tobytes(), k
    if "trajectory" not in params:  # (at ρ = 0 the gate does not move the target)
        assert min(seen.values()) > 0, seen

