"""Issue 14, round 9 (branch spd16): the per-PRI paths written out further, each bit for bit
the code it replaces (kept as the reference: main's step of the unit, verbatim, here or in the
round-8 tests), on random and edge states.

- Tracker: ``innovation_factor(α, β, False)`` (= 1 + ``prediction_vrr``) written out in
  ``BeamTracker.step`` (the NIS test of the mixed and steady phases).
- Pedestal: ``_sample`` written out in ``step`` (main's step kept below as the reference).
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
from test_tracker_round8 import _bits, _FormerBeamTracker, _inputs, _state

from axir.models.filters.gains import innovation_factor
from axir.models.pedestal import (
    BW_MAX,
    BW_MIN,
    TWO_PI,
    Pedestal,
    _servo_axis,
)
from axir.models.radar.conventions import CONFIRMED
from axir.models.tracker import Tracker

_EDGE = [0.0, -0.0, 5e-324, 1e-300, 1e-3, 0.1, 0.5, 0.99, 1.0, 1.5, 1.99, 2.0, 2.5, 4.0, -1.0,
         1e300, math.inf, -math.inf, math.nan]


def _vrr_factor(a: float, bb: float) -> float:
    """The lines of ``BeamTracker.step`` that replace ``innovation_factor(a, bb, False)``."""
    den = a * (4.0 - 2.0 * a - bb)
    if a <= 0.0 or bb <= 0.0 or den <= 0.0:
        return math.inf
    return 1.0 + (2.0 * a * a + 2.0 * bb + a * bb) / den


def test_vrr_factor_written_out_equals_innovation_factor() -> None:
    """The written-out factor is innovation_factor's (non-evolutive) on every pair of edge
    values and 200 000 random pairs in and around the stability triangle, by its bits."""
    pairs = [(a, b) for a in _EDGE for b in _EDGE]
    rng = np.random.default_rng(9)
    pairs += list(zip(rng.uniform(-0.5, 2.5, 200_000).tolist(),
                      rng.uniform(-0.5, 4.5, 200_000).tolist(), strict=True))
    for a, b in pairs:
        assert struct.pack("<d", _vrr_factor(a, b)) == struct.pack(
            "<d", innovation_factor(a, b, False)), (a, b)


def test_tracker_step_nis_factor_mixed_phase_equals_the_former_step() -> None:
    """Twin trackers (round 8's reference step, which calls innovation_factor), fed steady
    gains from the manager that are stable, unstable (the infinite factor), zero, negative or
    NaN, switching mid-track: every output and the state equal after every step; the
    non-evolutive NIS path was taken (its factor is finite there: the step uses the steady
    gains only inside the stability triangle; the infinite branch is the test above)."""
    rng = np.random.default_rng(90)
    gains = [(0.3, 0.05), (0.05, 0.001), (0.9, 0.6), (1.9, 0.5), (0.5, 0.0), (0.0, 0.2),
             (-0.1, 0.1), (math.nan, 0.1), (0.2, math.nan), (1e-3, 1e-6)]
    new, old = Tracker(track_init_n=2), Tracker(track_init_n=2)
    old.core.__class__ = _FormerBeamTracker
    taken = 0
    a_ss, b_ss = gains[0]
    for k in range(4000):
        if rng.random() < 0.01:
            a_ss, b_ss = gains[rng.integers(len(gains))]
        mode = 1 if k % 1000 < 30 else CONFIRMED
        inp: dict[str, Any] = _inputs(rng, k, mode, 7000.0 + 0.02 * k, 0.0, 0.4, 0.15,
                                      strong=rng.random() < 0.95)
        inp["alpha"], inp["beta"] = a_ss, b_ss
        o_old, o_new = old.core.step(1e-4, inp), new.core.step(1e-4, inp)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _state(new.core) == _state(old.core), k
        fx = new.core.axes[0]
        if fx.n >= 3 and not fx.evolutive and not o_new["coasting"]:
            taken += 1
    assert taken > 500, taken


# ----------------------------------------------------------------------------------- Pedestal
class _FormerPedestal(Pedestal):
    """The Pedestal with main 5d4d36e's ``step`` (it calls ``_sample``, unchanged)."""

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """``Pedestal.step`` of main 5d4d36e, verbatim below this docstring (the reference).

        Advance ``dt`` [s] with commands held constant; return the outputs at t + dt.

        ``dt == 0`` returns the previous outputs unchanged (no ADC conversion). The returned
        mapping is the unit's record of its outputs: read it, do not modify it.
        """
        if not dt > 0.0 or dt == math.inf:
            if dt == 0.0:
                return dict(self._outputs)
            raise ValueError(f"Pedestal.step: dt = {dt!r} s must be finite and >= 0")
        invalid = self._invalid_noted  # see note_invalid_inputs
        if invalid:
            self._invalid_noted = False
        get = inputs.get
        try:  # common path: three finite numbers
            u_az = float(get("cmd.az", 0.0))
            u_el = float(get("cmd.el", 0.0))
            bw = float(get("bandwidth", self._bw))
            # one isfinite for the three (inf/NaN propagate; a finite sum that overflows only
            # takes the item-by-item path, which finds nothing invalid)
            ok = isfinite(u_az + u_el + bw) and bw > 0.0
        except (TypeError, ValueError):
            ok = False
        if not ok:
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
            self._az, self._az_rate, self._az_acc = _servo_axis(
                self._az, omega, r, lim, a_max, tau, dt, em)
        else:  # exponential phase: θ += r t − e τ (1 − exp(−t/τ)), ω = r − e·exp(−t/τ)
            self._az += r * dt + e * tau * em
            e = e * em1
            acc = e / tau
            self._az_acc = a_max if acc > a_max else (-a_max if acc < -a_max else acc)
            omega = r - e
            self._az_rate = lim if omega > lim else (-lim if omega < -lim else omega)
        lim = self.rate_limit_el
        a_max = self.accel_limit_el
        r = k * u_el
        r = lim if r > lim else (-lim if r < -lim else r)
        omega = self._el_rate
        e = r - omega
        sat = a_max * tau
        if e > sat or e < -sat:
            self._el, self._el_rate, self._el_acc = _servo_axis(
                self._el, omega, r, lim, a_max, tau, dt, em)
        else:
            self._el += r * dt + e * tau * em
            e = e * em1
            acc = e / tau
            self._el_acc = a_max if acc > a_max else (-a_max if acc < -a_max else acc)
            omega = r - e
            self._el_rate = lim if omega > lim else (-lim if omega < -lim else omega)

        self._outputs = out = self._sample(invalid)
        return out


def _ped_state(p: Pedestal) -> bytes:
    """The Pedestal's whole state as pickle bytes (floats by their 8 bytes), the generator by
    its bit-generator state."""
    d = dict(p.__dict__)
    d["_rng"] = d["_rng"].bit_generator.state
    return pickle.dumps(d, protocol=4)


_PED_CASES = [
    {},  # the default
    {"pot_noise": 0.0},
    {"pot_noise": 0.0, "adc_bits": 8, "pot_b_offset": 0.5 * math.pi},
    {"accel_limit_az": 0.05, "accel_limit_el": 0.02, "rate_limit_az": 3.0},  # ramps
    {"adc_bits": 32, "pot_noise": 0.2, "az0": 6.283185307179586 - 1e-12, "el0": -3.0},
    {"pot_gain": 1e4, "pot_noise": 50.0, "pot_b_offset": 1.5 * math.pi, "seed": 11},
]


@pytest.mark.parametrize("params", _PED_CASES)
def test_pedestal_step_with_sample_written_out_equals_the_former_step(params: dict) -> None:
    """Twin pedestals (main's step, which calls ``_sample``) fed the same commands: random,
    saturating (±1e3 V: rate limits, ramps with the acceleration limit), NaN/±inf, missing,
    non-numeric and overflowing (1e308) commands and bandwidths, steps of 0 (the previous
    outputs), 1e-4 and up to 2 s, angles across 0/2π and ±π (the pots' jumps, codes clipped
    at 0 and at the top): every output by its bits, the state and the generator after every
    step; both servo phases taken on both axes."""
    rng = np.random.default_rng(sum(map(ord, repr(params))))
    new, old = Pedestal(**params), Pedestal(**params)
    old.__class__ = _FormerPedestal
    phases = set()
    odd = [math.nan, math.inf, -math.inf, 1e308, -1e308, "x", None]
    for k in range(3000):
        inp: dict[str, Any] = {"cmd.az": float(rng.normal(0.0, 3.0)),
                               "cmd.el": float(rng.normal(0.0, 3.0)),
                               "bandwidth": float(rng.choice([0.5, 2.0, 5.0, 50.0, 1e-3, 1e4]))}
        u = rng.random()
        if u < 0.05:
            inp[str(rng.choice(list(inp)))] = odd[rng.integers(len(odd))]
        elif u < 0.08:
            del inp[str(rng.choice(list(inp)))]
        elif u < 0.15:
            inp["cmd.az"], inp["cmd.el"] = float(rng.choice([-1e3, 1e3])), float(
                rng.choice([-1e3, 1e3]))
        if rng.random() < 0.01:
            new.note_invalid_inputs(["cmd.az"]), old.note_invalid_inputs(["cmd.az"])
        dt = float(rng.choice([1e-4, 1e-4, 1e-4, 0.0, 3e-3, 0.25, 2.0]))
        omega = (new._az_rate, new._el_rate)
        o_old, o_new = old.step(dt, inp), new.step(dt, inp)
        assert list(o_new) == list(o_old)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _ped_state(new) == _ped_state(old), k
        assert new.outputs() == old.outputs()
        if dt > 0.0:
            for ax, w0 in zip(("az", "el"), omega, strict=True):
                phases.add((ax, abs(new._outputs[ax + ".acc"]) < getattr(
                    new, "accel_limit_" + ax) or w0 == new._outputs[ax + ".rate"]))
    assert len(phases) == 4, phases


@pytest.mark.parametrize("params", _PED_CASES[:3])
def test_pedestal_step_equals_the_former_step_at_edge_angles(params: dict) -> None:
    """Angles and decoder states set at the wrap edges (a tiny negative angle whose mod 2π
    rounds to 2π, 0, ±π, 2π − ulp, the pots' jumps at the offset, codes at 0 and at the top)
    with zero and full commands: outputs and state as the former step's."""
    edge = [-1e-17, -0.0, 0.0, 5e-324, math.pi, -math.pi, TWO_PI - 4e-16, TWO_PI, 1e-9,
            params.get("pot_b_offset", math.pi), -1e-300, 3.0 * TWO_PI + 1e-3]
    rng = np.random.default_rng(4)
    for az in edge:
        for el in edge[::3]:
            new, old = Pedestal(**params), Pedestal(**params)
            old.__class__ = _FormerPedestal
            for p in (new, old):
                p._az, p._el, p._az_dec, p._el_dec = az, el, el, az
            for cmd in (0.0, 0.0, 1e3, -1e3, float(rng.normal())):
                inp = {"cmd.az": cmd, "cmd.el": -cmd, "bandwidth": float(rng.choice([BW_MIN,
                                                                                     BW_MAX]))}
                o_old, o_new = old.step(1e-4, inp), new.step(1e-4, inp)
                assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in
                                                              o_old.values()], (az, el)
                assert _ped_state(new) == _ped_state(old)


def test_servo_axis_ramp_branch_is_taken_by_the_written_out_step() -> None:
    """The ramp (acceleration-limited) branch of the written-out step: the same values as
    ``_servo_axis`` itself for a large command (the twin tests above compare the whole
    step)."""
    p = Pedestal(pot_noise=0.0, accel_limit_az=0.05)
    tau, dt = p._tau, 1e-4
    em = math.expm1(-dt / tau)
    exp = _servo_axis(p._az, p._az_rate, p.rate_limit_az, p.rate_limit_az, 0.05, tau, dt, em)
    o = p.step(dt, {"cmd.az": 1e3, "cmd.el": 0.0, "bandwidth": p._bw})
    assert (p._az, o["az.rate"], o["az.acc"]) == exp
