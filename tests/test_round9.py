"""Issue 14, round 9 (branch spd16): the per-PRI paths written out further, each bit for bit
the code it replaces (kept as the reference: main's step of the unit, verbatim, here or in the
round-8 tests), on random and edge states.

- Tracker: ``innovation_factor(α, β, False)`` (= 1 + ``prediction_vrr``) written out in
  ``BeamTracker.step`` (the NIS test of the mixed and steady phases).
- Pedestal: ``_sample`` written out in ``step`` (main's step kept below as the reference).
- RadarManager: ``_update_schedule`` and the common case of ``_step_outputs`` written out in
  ``step`` (main's step kept below as the reference).
- The direct loop's run loop: outputs, t and steps in locals, stored when it ends.
- The TargetGenerator's, the Pedestal's and the Tracker's inputs read by subscripts from a
  dict (main's steps, which read them by ``get``, kept here or in the round-8 tests).
- TargetGenerator: ``_pulse1`` and ``radar.tg_outputs.outputs`` written out in ``step``
  (main's step and ``_pulse1``: the round-8 reference, tests/test_tg_round8.py).
- TargetGenerator: the trajectory piece of the pulse's time called directly
  (``Trajectory.segment``) while the times stay in its interval.
- Tracker: ``update_xyz``'s three-axis case written out in ``BeamTracker.step`` (round 8's
  reference step calls ``update_xyz``; its twin tests in tests/test_tracker_round8.py and the
  gain hand-overs at equality below).
"""

from __future__ import annotations

import json
import math
import pickle
import struct
from collections.abc import Mapping
from math import isfinite
from typing import Any

import numpy as np
import pytest
from manager_scene import Scene, make
from test_tg_round8 import _FormerTG
from test_tracker_round8 import (
    _bits,
    _FormerBeamTracker,
    _inputs,
    _state,
    _step_or_error,
    _tracker,
)

from axir.models.filters.gains import innovation_factor, kalata_gains
from axir.models.loop import DirectLoop
from axir.models.manager import RadarManager
from axir.models.manager.machine import (
    _F64,
    _GATE0_M,
    _SUM_SHAPE,
    ANCHOR_MARGIN_M,
    ANCHOR_PERIOD,
    _add_reduce,
    _scalar_inputs,
)
from axir.models.manager.ports import finite_or_none, read_sum
from axir.models.pedestal import (
    BW_MAX,
    BW_MIN,
    TWO_PI,
    Pedestal,
    _servo_axis,
)
from axir.models.radar.conventions import ACQUISITION, BIN_M, CONFIRMED, TENTATIVE
from axir.models.target_generator import TargetGenerator

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
    new, old = _tracker(track_init_n=2), _tracker(track_init_n=2)
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


# ------------------------------------------------------------------------------ RadarManager
class _FormerManager(RadarManager):
    """The RadarManager with main 5d4d36e's ``step``."""

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """``RadarManager.step`` of main 5d4d36e, verbatim below this docstring (the
        reference): it calls ``_update_schedule`` and ``_step_outputs``."""
        try:  # issue 14: the common case, every scalar input a finite number, screened at once
            dtv: float | None = float(dt)
            rng: float | None = float(inputs["track.range"])
            rate: float | None = float(inputs["track.range_rate"])
            mv: float | None = float(inputs["maneuver"])
            # one isfinite for the four (inf/NaN propagate; a finite sum that overflows only
            # takes the one-by-one rule, which gives these same values: issue 14, round 7)
            if not math.isfinite(dtv + rng + rate + mv):
                raise ValueError
        except (TypeError, ValueError, KeyError):
            dtv, rng, rate, mv = _scalar_inputs(dt, inputs)
        dt_eff = dtv if dtv is not None and dtv > 0.0 else self._pris[self._pri_idx]
        self._detection = False
        self._dwell_done = False

        # track inputs (held when non-finite)
        tr = self._track
        if rng is not None:
            tr.last_range = rng
        if rate is not None:
            tr.last_rate = rate
        if mv is not None:
            tr.maneuver = mv != 0.0
        if tr.maneuver:
            tr.since_maneuver = 0.0
        else:
            tr.since_maneuver += dt_eff

        mode = self.mode
        if mode == TENTATIVE:
            self._tent.steps += 1
        elif mode == CONFIRMED:
            tr.conf_time += dt_eff
            # confirmed-track plausibility (issue 11; written out here, issue 14 round 7): the
            # track range stays inside the instrumented range [0, max_range] and moves no
            # faster than max_speed from an anchor (the resolved range at confirmation, then
            # the track range each ANCHOR_PERIOD), within ANCHOR_MARGIN_M; once the track is
            # doppler_track_delay old (its velocity has converged, the Doppler centre follows
            # it) also |track.range_rate| ≤ max_speed. Records the last plausible range; a held
            # (absent or non-finite) range is plausible and moves nothing
            if rng is not None:
                conf = tr.conf_time
                age = conf - tr.anchor_time
                if (not 0.0 <= rng <= self.max_range
                        or abs(rng - tr.anchor_range) > self.max_speed * age + ANCHOR_MARGIN_M
                        or (conf >= self.doppler_track_delay
                            and abs(tr.last_rate) > self.max_speed)):
                    self._drop_track()
                else:
                    if age >= ANCHOR_PERIOD:
                        tr.anchor_range, tr.anchor_time = rng, conf
                    tr.good_range = rng
                    self._gate = rng - self._offset

        # sample
        dw = self._dwell
        if dw.settle > 0:
            dw.settle -= 1
        else:
            s = inputs.get("sum")
            # read_sum(s), its common case written out (issue 14, round 7): a float64 (16, 3)
            # array is taken as it is when its sum is finite
            if not (type(s) is np.ndarray and s.shape == _SUM_SHAPE and s.dtype == _F64):
                s = read_sum(s)
            elif not math.isfinite(_add_reduce(s, None)):
                s = None
            gate_ok = True
            if self.mode != CONFIRMED and "gate.start" in inputs:
                gs = finite_or_none(inputs["gate.start"])
                if gs is None:
                    s = None
                else:
                    ru = self._ks[self._pri_idx] * BIN_M
                    d = (gs - (self._gate - _GATE0_M)) % ru
                    gate_ok = min(d, ru - d) <= 0.5 * BIN_M
            mode = self.mode  # as _dwell_length()
            n_dwell = (self.dwell_acq if mode == ACQUISITION else
                       self.dwell_tent if mode == TENTATIVE else self.dwell_conf)
            if not gate_ok:
                dw.stall += 1
                if dw.stall >= self.stall_pris:
                    dw.n_seen = n_dwell
                    dw.bad = True
            else:
                dw.n_seen += 1
                if s is None:
                    dw.bad = True
                else:
                    np.add(dw.acc, s, dw.acc)  # out positional: no keyword parsing
            if dw.n_seen >= n_dwell:
                self._end_dwell()

        if self.mode == TENTATIVE and self._tent.steps > self.tent_timeout_pris:
            self._enter_acquisition(self._search.centre_true)

        self._update_schedule()
        return self._step_outputs()

    def _update_schedule(self) -> None:
        """main 5d4d36e's ``ScheduleMixin._update_schedule`` (models/manager/schedule.py, removed
        when round 9 wrote it out in the step): the servo bandwidth, then the steady gains."""
        confirmed = self.mode == CONFIRMED
        # bandwidth: bw_start → bw_floor exponentially over bw_decay_time of confirmed tracking
        if not confirmed:
            self._bw = self.bw_start
        else:
            decay = self.bw_decay_time
            conf_time = self._track.conf_time
            if decay <= 0.0 or conf_time >= decay:
                self._bw = self.bw_floor
            else:
                x = conf_time / decay
                self._bw = self.bw_start * (self.bw_floor / self.bw_start) ** x
        # steady gains: Kalata's for the tracking index of σm (opened after a maneuver) and T
        opened = self._track.since_maneuver <= self.maneuver_hold
        sigma_m = self.sigma_man_high if opened else self.sigma_man
        t = self._pris[self._pri_idx]  # the current PRI [s]
        key = (sigma_m, t)
        if key != self._gains_key:
            self._gains_key = key
            self._lambda = sigma_m * t * t / self.sigma_meas
            self._gains = kalata_gains(self._lambda)
        # SYSTEM.md: evolutive gains until the manager's steady gains take over. The Tracker
        # (filters.gains.scheduled_gains) uses max(evolutive(n), steady) per gain, so the steady
        # gains are sent throughout confirmed tracking and the tracker hands over itself when
        # its α(n) falls below them; 0 in acquisition / tentative (evolutive only, seed 000:
        # "Alpha-Beta filters with a short time constant").
        if not confirmed:
            self._alpha = self._beta = 0.0
        else:
            self._alpha, self._beta = self._gains


def _mgr_state(m: RadarManager) -> bytes:
    """The manager's whole state as pickle bytes (arrays by dtype, shape and bytes)."""
    return pickle.dumps(m.__dict__, protocol=4)


@pytest.mark.parametrize(("seed", "params"), [
    (3, {}), (4, {"bw_decay_time": 0.0}), (5, {"bw_decay_time": 0.05, "maneuver_hold": 0.02}),
    (6, {"bw_decay_time": 1e-3, "sigma_man_high": 300.0}),
])
def test_manager_step_schedule_and_outputs_written_out_equal_the_former_step(
        seed: int, params: dict) -> None:
    """Twin managers (main's step, which calls ``_update_schedule`` and ``_step_outputs``)
    fed the same synthetic scene through acquisition, tentative, confirmed, missed dwells,
    drops and re-acquisition, with maneuver flags (the opened gains: a new gains key),
    steps of 0, NaN and 2·PRI, a NaN range and a missing SUM now and then: every output by
    its repr (types, bits, NaN) and the state after every step; the written-out template
    path, the full outputs in confirmed mode and the decaying bandwidth were taken."""
    new, old = make(**params), make(**params)
    old.__class__ = _FormerManager
    scene = Scene(37_000.0, seed=seed)
    rng = np.random.default_rng(seed)
    seen = {"template": 0, "full_confirmed": 0, "decay": 0, "modes": set()}
    for k in range(3 * 1200):
        scene.present = k % 1200 < 900
        inp = scene.inputs()
        u = rng.random()
        if u < 0.02:
            inp["maneuver"] = True
        elif u < 0.025:
            inp["track.range"] = math.nan
        elif u < 0.03:
            del inp["sum"]
        pri = scene.prev["pri"] if scene.prev else 1e-4
        dt = pri if rng.random() < 0.98 else float(rng.choice([0.0, math.nan, 2.0 * pri]))
        had = new._out_tmpl is not None
        o_old, o_new = old.step(dt, inp), new.step(dt, inp)
        assert list(o_new) == list(o_old)
        assert repr(o_new) == repr(o_old), k
        assert _mgr_state(new) == _mgr_state(old), k
        conf = o_new["mode"] == CONFIRMED
        seen["template"] += conf and had and not o_new["dwell.done"] and new._out_tmpl is not None
        seen["full_confirmed"] += conf and (o_new["dwell.done"] or not had)
        seen["decay"] += conf and new.bw_floor < o_new["bandwidth"] < new.bw_start
        seen["modes"].add(o_new["mode"])
        scene.prev = o_new
        scene.t += pri
    assert len(seen.pop("modes")) == 3
    if new.bw_decay_time == 0.0:  # no decay: the floor at once
        assert seen.pop("decay") == 0
    assert min(seen.values()) > 0, seen


# ------------------------------------------------------------------------------- the run loop
class _StopError(Exception):
    pass


def _failing(unit: Any, at: int) -> Any:
    """``unit.step`` that raises at its ``at``-th call (0-based)."""
    orig, calls = unit.step, [0]

    def step(h: float, inputs: Any) -> Any:
        calls[0] += 1
        if calls[0] - 1 == at:
            raise _StopError
        return orig(h, inputs)
    return step


def _out_bits(loop: DirectLoop) -> list:
    return [(n, k, _bits(v)) for n, d in loop.out.items() for k, v in d.items()]


@pytest.mark.parametrize("unit", ["ped", "gen", "trk", "mgr"])
def test_run_loop_stores_outputs_t_and_steps_as_step_does_when_a_unit_raises(unit: str) -> None:
    """The run loop keeps the outputs, t and the step count in locals and stores them when it
    ends: a unit raising in the middle of a pass leaves ``out`` (the new outputs of the units
    stepped before it in that pass, every key and value), ``t`` and ``steps`` as
    :meth:`DirectLoop.step` repeated leaves them (it stores as it goes)."""
    for at in (0, 1, 7):
        a, b = DirectLoop.from_params(), DirectLoop.from_params()
        for loop in (a, b):
            for _ in range(3):
                loop.step()
            u = getattr(loop, unit)
            u.step = _failing(u, at)
        with pytest.raises(_StopError):
            a.run(1.0)
        with pytest.raises(_StopError):
            while b.t < 1.0:
                b.step()
        assert (a.t, a.steps) == (b.t, b.steps)
        assert list(a.out) == list(b.out)
        assert _out_bits(a) == _out_bits(b)


def test_run_loop_without_a_pass_leaves_out_t_and_steps() -> None:
    """No pass (duration ≤ t): ``out`` keeps its keys (the TargetGenerator's outputs, computed
    only by its first step, are not added), t and steps unchanged; then runs equal steps."""
    a, b = DirectLoop.from_params(), DirectLoop.from_params()
    keys = list(a.out)
    a.run(0.0)
    assert list(a.out) == keys and (a.t, a.steps) == (0.0, 0)
    a.run(0.002)
    while b.t < 0.002:
        b.step()
    assert (a.t, a.steps) == (b.t, b.steps) and _out_bits(a) == _out_bits(b)


# ------------------------------------------------------------ the inputs read by subscripts
# main's step (reading the inputs by get) and main's _pulse1: the round-8 reference
_FormerTGStep = _FormerTG


class _Proxy(Mapping):
    """A Mapping that is not a dict (its ``get`` is Mapping's)."""

    def __init__(self, d: dict) -> None:
        self._d = d

    def __getitem__(self, k: str) -> Any:
        return self._d[k]

    def __iter__(self) -> Any:
        return iter(self._d)

    def __len__(self) -> int:
        return len(self._d)


class _Missing(dict):
    """A dict subclass whose missing keys read as 0.5 by subscript (not by ``get``)."""

    def __missing__(self, k: str) -> float:
        return 0.5


def _as_kind(rng: np.random.Generator, inp: dict) -> Any:
    """``inp`` as a dict, a dict subclass with __missing__, a defaultdict, a mapping proxy or
    another Mapping, with a key removed now and then."""
    import collections
    import types

    inp = dict(inp)
    if rng.random() < 0.15:
        del inp[str(rng.choice(sorted(inp)))]
    kind = rng.integers(6)
    if kind == 1:
        return _Missing(inp)
    if kind == 2:
        return collections.defaultdict(lambda: 0.25, inp)
    if kind == 3:
        return types.MappingProxyType(inp)
    if kind == 4:
        return _Proxy(inp)
    return inp


def test_tg_step_inputs_by_subscript_equal_the_former_get_step() -> None:
    """Twin generators (main's step, which reads the inputs by ``get``) fed the same inputs
    as dicts, dict subclasses (with __missing__, defaultdict), mapping proxies and other
    Mappings, keys missing, non-finite, non-numeric and too-short PRIs: outputs and state
    equal after every step."""
    rng = np.random.default_rng(91)
    new, old = TargetGenerator(seed=4), TargetGenerator(seed=4)
    old.__class__ = _FormerTGStep
    odd = [math.nan, math.inf, "x", None, 1e-6]
    for k in range(1500):
        inp: dict[str, Any] = {"antenna.az": 0.5 + 0.001 * k, "antenna.el": 0.1,
                               "gate.start": 9000.0 + k, "doppler.centre": 300.0, "pri": 1e-4}
        if rng.random() < 0.05:
            inp[str(rng.choice(sorted(inp)))] = odd[rng.integers(len(odd))]
        elif rng.random() < 0.01:
            inp["antenna.az"] = 1e308  # a finite sum that overflows: the item-by-item rule
        if k % 97 == 0:
            new.note_invalid_inputs(["pri"]), old.note_invalid_inputs(["pri"])
        m = _as_kind(rng, inp)
        o_old, o_new = old.step(1e-4, m), new.step(1e-4, m)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert repr(new._last_u) == repr(old._last_u)
        assert (new._invalid, new._invalid_count, new.t) == (old._invalid, old._invalid_count,
                                                             old.t)
        assert new._y.tobytes() == old._y.tobytes()
    assert np.isfinite(new._y).all()


def _tracker_step(core: Any, inp: Any) -> Any:
    try:
        return _step_or_error(core, 1e-4, inp)
    except (KeyError, IndexError) as e:  # a missing ped.az / ped.el, or a missing beam read
        return repr(e)  # as 0.5 by __missing__: raised before and after alike


def test_pedestal_and_tracker_inputs_by_subscript_equal_the_former_get_steps() -> None:
    """The Pedestal and the Tracker (main's steps read their inputs by ``get``) fed dicts,
    dict subclasses with __missing__, defaultdicts, mapping proxies and other Mappings, keys
    missing: outputs (or the exception, KeyError for a missing ``ped.az``) and state equal."""
    rng = np.random.default_rng(92)
    pn, po = Pedestal(), Pedestal()
    po.__class__ = _FormerPedestal
    tn, to = _tracker(track_init_n=2), _tracker(track_init_n=2)
    to.core.__class__ = _FormerBeamTracker
    for k in range(1500):
        inp = {"cmd.az": float(rng.normal()), "cmd.el": float(rng.normal()), "bandwidth": 2.0}
        m = _as_kind(rng, inp)
        o_old, o_new = po.step(1e-4, m), pn.step(1e-4, m)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _ped_state(pn) == _ped_state(po), k
        mode = 0 if k < 10 else (1 if k < 40 else CONFIRMED)
        tin = _inputs(rng, k, mode, 7000.0 + 0.02 * k, 0.0, 0.4, 0.15, strong=True)
        m = _as_kind(rng, tin)
        r_old, r_new = _tracker_step(to.core, m), _tracker_step(tn.core, m)
        assert r_new == r_old, k
        assert _state(tn.core) == _state(to.core), k


# ------------------------------------------- TargetGenerator: _pulse1 and the outputs in step
_TRAJ = [
    '{"type": "cv", "position": [-5000, 9000, 1200], "velocity": [150, -120, 30]}',
    '{"type": "ca", "position": [7000, -3000, 800], "velocity": [-90, 160, -12], '
    '"acceleration": [3.5, -7.25, 1.5]}',
    '{"type": "turn", "position": [3000, 14000, 900], "velocity": [-180, 40, 6], "g": 4, '
    '"direction": "right"}',
    '{"type": "piecewise", "position": [-6000, 12000, 1500], "velocity": [200, 3, 10], '
    '"t0": 0, "segments": [{"type": "cv", "onset": 0}, {"type": "turn", "g": 3, '
    '"direction": "left", "onset": 0.01, "duration": 0.015}, {"type": "ca", "onset": 0.025, '
    '"acceleration": [1, 2, -3]}]}',
]


@pytest.mark.parametrize("traj", _TRAJ)
@pytest.mark.parametrize("params", [{}, {"swerling": 1, "dwell_pulses": 4},
                                    {"clutter": True, "mti": 1, "rcs": 0.0}])
def test_tg_step_pulse_and_outputs_written_out_equal_the_former_step(traj: str,
                                                                     params: dict) -> None:
    """Twin generators (main's step calling main's ``_pulse1`` and ``tg_outputs.outputs``) on
    moving, accelerating and turning targets (every velocity and acceleration component
    non-zero: the truth's sums in their order), the antenna following the target, steps of
    one PRI, of 0 (the outputs at the same time) and of 3 PRIs (the N-pulse path) now and then:
    outputs by their bits, the filter state, the last pulse's truth and ``outputs()``."""
    rng = np.random.default_rng(sum(map(ord, traj + repr(params))))
    new = TargetGenerator(trajectory=traj, **params)
    old = TargetGenerator(trajectory=traj, **params)
    old.__class__ = _FormerTGStep
    o = new.outputs()
    for k in range(400):
        pri = 1e-4 if rng.random() < 0.97 else 1.25e-4
        inp = {"antenna.az": o["truth.az"] + rng.normal(0.0, 0.01),
               "antenna.el": o["truth.el"] + rng.normal(0.0, 0.01),
               "gate.start": o["truth.range"] - rng.uniform(3.0, 9.0) * BIN_M,
               "doppler.centre": float(rng.uniform(-2e3, 2e3)), "pri": pri}
        dt = pri if rng.random() < 0.98 else float(rng.choice([0.0, 3 * pri]))
        if k % 150 == 149:  # a restored state: the trajectory piece looked up again
            new.set_state(new.get_state())
            old.set_state(old.get_state())
        o_old, o = old.step(dt, inp), new.step(dt, inp)
        assert list(o) == list(o_old)
        assert [_bits(v) for v in o.values()] == [_bits(v) for v in o_old.values()], k
        assert new._y.tobytes() == old._y.tobytes(), k
        t_new, t_old = new._truth, old._truth
        assert [_bits(v) for v in (t_new[0], *t_new[3:])] == [
            _bits(v) for v in (t_old[0], *t_old[3:])], k
        assert t_new[2] == t_old[2] and t_new[1] is new._traj
        assert repr(new.outputs()) == repr(old.outputs())
        assert (new.t, new._pulse) == (old.t, old._pulse)


# ----------------------------------------------------- Tracker: update_xyz written out in step
def test_tracker_three_axis_update_written_out_at_gain_hand_overs() -> None:
    """Twin trackers (round 8's reference step calls update_xyz): the manager's steady gains
    set exactly to the evolutive α(m), β(m) of the coming update (the ``>=`` hand-overs at
    equality, then the steady-gain tuple held: update_xyz's ``st == (α_ss, β_ss)`` path),
    just above and below them, unstable and NaN; a capped index (n_max: scheduled_gains
    itself), per-axis velocity priors (the written-out path entered by value once every axis
    holds the steady gains, session 28) and a step of 1e-300 s: outputs and state equal after
    every step; the steady-tuple path and both hand-overs at equality were taken."""
    rng = np.random.default_rng(93)
    for params in ({"track_init_n": 2}, {"track_init_n": 2, "n_max": 40},
                   {"track_init_n": 2, "velocity_prior_axes": True}):  # session 28
        new, old = _tracker(**params), _tracker(**params)
        old.core.__class__ = _FormerBeamTracker
        held = equal = by_value = 0
        for k in range(900):
            mode = 1 if k < 15 else CONFIRMED
            inp: dict[str, Any] = _inputs(rng, k, mode, 7000.0 + 0.02 * k, 0.0, 0.4, 0.15,
                                          strong=True)
            m = new.core.axes[0].n + 1
            ev_a, ev_b = 2.0 * (2.0 * m - 1.0) / (m * (m + 1.0)), 6.0 / (m * (m + 1.0))
            u = rng.random()
            if u < 0.4:
                a_ss, b_ss = ev_a, ev_b  # both at equality
            elif u < 0.55:
                a_ss, b_ss = float(np.nextafter(ev_a, 0.0)), ev_b
            elif u < 0.7:
                a_ss, b_ss = ev_a, float(np.nextafter(ev_b, 0.0))
            elif u < 0.85:
                a_ss, b_ss = 0.05, 0.002
            else:
                a_ss, b_ss = [(1.9, 0.5), (math.nan, 0.1), (0.0, 0.0)][k % 3]
            inp["alpha"], inp["beta"] = a_ss, b_ss
            T = 1e-4 if rng.random() < 0.995 else 1e-300
            fx = new.core.axes[0]
            held += fx._steady is not None and fx.n > 0
            equal += fx.n > 0 and (a_ss, b_ss) == (ev_a, ev_b)
            axes = new.core.axes  # per-axis priors: each axis's own tuple, all equal in value
            by_value += (fx.n > 0 and fx._steady == (a_ss, b_ss)
                         and axes[1]._steady == axes[2]._steady == fx._steady
                         and not (axes[1]._steady is fx._steady is axes[2]._steady))
            o_old, o_new = old.core.step(T, inp), new.core.step(T, inp)
            assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
            assert _state(new.core) == _state(old.core), k
        assert held > 20 and equal > 100, (held, equal)
        if params.get("velocity_prior_axes"):  # the written-out path entered by value
            assert by_value > 0, by_value



# ------------------------------------------------------------- Trajectory.segment (the piece)
def _segment_cases() -> list[Any]:
    from axir.models.radar.trajectory import ConstantVelocity, Piecewise, trajectory_from_spec

    cv = [ConstantVelocity([1e3 * k, 2e3, 300.0], [10.0 * k, -5.0, 1.0], t0=0.1 * k)
          for k in range(4)]
    return [
        trajectory_from_spec(json.loads(_TRAJ[3])),
        Piecewise([0.0, 0.5, 0.5, 1.0], cv),  # an empty segment (a repeated start)
        Piecewise([0.2], cv[:1]),  # one piece: the whole time line
        Piecewise([0.0, 0.3], [Piecewise([0.0, 0.1], cv[:2]), Piecewise([0.3, 0.4], cv[2:])]),
        trajectory_from_spec({"type": "waypoints", "points": [[0, 0, 0], [100, 50, 10],
                                                              [200, -50, 30]],
                              "times": [0.0, 1.0, 2.5]}),
        cv[2],
    ]


@pytest.mark.parametrize("case", range(6))
def test_segment_piece_state_equals_the_trajectory_state_over_its_interval(case: int) -> None:
    """``Trajectory.segment(t)`` = (lo, hi, piece): t in [lo, hi) (unless NaN) and
    ``piece.state_tuple(u) == traj.state_tuple(u)`` (bits) at lo, hi − ulp and random u in
    between, for times before the first start, on every start, between, after the last, ±inf
    and NaN; nested piecewise trajectories, a repeated start, one piece, waypoints."""
    traj = _segment_cases()[case]
    rng = np.random.default_rng(case)
    starts = list(getattr(traj, "_starts_list", [0.0]))
    ts = [-5.0, -1e-9, 0.0, 2.9, 1e9, math.inf, -math.inf, math.nan, *starts,
          *(float(np.nextafter(x, -math.inf)) for x in starts), *rng.uniform(-1, 3, 60).tolist()]
    for t in ts:
        lo, hi, piece = traj.segment(t)
        if t == t:
            assert lo <= t < hi or (t == hi == math.inf), (t, lo, hi)
        us = [u for u in (lo, float(np.nextafter(hi, -math.inf)), t,
                          *rng.uniform(max(lo, -10.0), min(hi, 10.0), 8).tolist())
              if lo <= u < hi and math.isfinite(u)]
        for u in us:
            assert [_bits(x) for v in piece.state_tuple(u) for x in v] == [
                _bits(x) for v in traj.state_tuple(u) for x in v], (t, u)
