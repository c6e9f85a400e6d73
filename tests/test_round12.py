"""Issue 14, round 12 (branch spd19): ``RadarManager.step`` with numpy's ``add`` / ``ndarray``
and ``math.isfinite`` as module globals, the fast path's inputs stored without None tests
(try/else), the confirmed mode tested first and ``self.mode`` / ``self._track`` read once;
bit for bit main's step (kept below as the reference) on random and odd inputs.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import pytest
from manager_scene import Scene, make
from test_round9 import _mgr_state

from axir.models.filters.gains import kalata_gains
from axir.models.manager import RadarManager
from axir.models.manager.machine import (
    _F64,
    _GATE0_M,
    _SUM_SHAPE,
    ANCHOR_MARGIN_M,
    ANCHOR_PERIOD,
    _scalar_inputs,
)
from axir.models.manager.ports import finite_or_none, read_sum
from axir.models.radar.conventions import (
    ACQUISITION,
    BIN_M,
    CONFIRMED,
    TENTATIVE,
)


class _FormerManager(RadarManager):
    """The RadarManager with main 8e59ae1's ``step``."""

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """``RadarManager.step`` of main 8e59ae1, verbatim below this docstring."""
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
        dt_eff = dtv if dtv is not None and dtv > 0.0 else self._all_pris[self._pri_idx]
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
            # array is taken as it is; session 17 moved its finiteness test to the dwell's end
            # (the inherited _end_dwell, on the accumulated sum; test_manager_machine's
            # test_one_nonfinite_sample_makes_its_dwell_a_miss tests that rule), so this former
            # step accumulates it as the current one does
            if not (type(s) is np.ndarray and s.shape == _SUM_SHAPE and s.dtype == _F64):
                s = read_sum(s)
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

        # servo bandwidth and α-β gain schedule (seed 000: "The bandwidths of the servo-loops
        # are progressively reduced up to a certain limit"; "The Radar Manager is responsible
        # for updating the Alpha-Beta coefficients"; laws in the module docstring, *Confirmed*),
        # then the common case of _step_outputs(), written out here (issue 14, round 9: no call
        # per PRI; hotpath.py documents the outputs)
        confirmed = self.mode == CONFIRMED
        if not confirmed:  # bandwidth: bw_start → bw_floor over bw_decay_time of confirmed
            self._bw = bw = self.bw_start
        else:
            decay = self.bw_decay_time
            conf_time = self._track.conf_time
            if decay <= 0.0 or conf_time >= decay:
                self._bw = bw = self.bw_floor
            else:
                x = conf_time / decay
                self._bw = bw = self.bw_start * (self.bw_floor / self.bw_start) ** x
        # steady gains: Kalata's for the tracking index of σm (opened after a maneuver) and T
        sigma_m = (self.sigma_man_high if self._track.since_maneuver <= self.maneuver_hold
                   else self.sigma_man)
        t = self._all_pris[self._pri_idx]  # the current PRI [s]
        key = (sigma_m, t)
        if key != self._gains_key:
            self._gains_key = key
            self._lambda = sigma_m * t * t / self.sigma_meas
            self._gains = kalata_gains(self._lambda)
        # SYSTEM.md: evolutive gains until the manager's steady gains take over. The Tracker
        # (filters.gains.scheduled_gains) uses max(evolutive(n), steady) per gain, so the steady
        # gains are sent throughout confirmed tracking; 0 in acquisition / tentative
        # (evolutive only, seed 000: "Alpha-Beta filters with a short time constant").
        if not confirmed:
            self._alpha = self._beta = 0.0
            return self._step_outputs()
        self._alpha, self._beta = self._gains
        tmpl = self._out_tmpl
        if tmpl is not None and not self._dwell_done and self._gains_key is self._tmpl_gains_key:
            out = tmpl.copy()  # a confirmed PRI without a dwell end (StepOutputsMixin)
            out["gate.command"] = self._gate - _GATE0_M
            out["bandwidth"] = bw
            return out
        return self._step_outputs()


_ODD = [None, "x", "1e3", [1.0], np.float32(2.5), np.int64(3), True, False, 0, -1.0,
        math.nan, math.inf, -math.inf, 1e308]


def _oddify(inp: dict, rng: np.random.Generator) -> None:
    """Replace, drop or distort some inputs (odd types, NaN/±inf, missing keys, odd SUMs)."""
    u = rng.random()
    if u < 0.10:
        key = str(rng.choice(["track.range", "track.range_rate", "maneuver", "gate.start"]))
        if rng.random() < 0.3:
            inp.pop(key, None)
        else:
            inp[key] = _ODD[int(rng.integers(len(_ODD)))]
    elif u < 0.13:
        s = inp["sum"]
        inp["sum"] = [s.astype(np.float32), s[:8], s.copy().T, s * math.nan, None, s.tolist(),
                      np.where(s > 3.0, math.inf, s)][int(rng.integers(7))]
    elif u < 0.15:
        inp["maneuver"] = bool(rng.random() < 0.5) if rng.random() < 0.5 else 1.0


def _outcome(m: RadarManager, dt: Any, inp: dict) -> tuple:
    try:
        return ("ok", repr(m.step(dt, inp)))
    except Exception as e:  # the same exception expected of both
        return ("raised", type(e).__name__, str(e))


@pytest.mark.parametrize(("seed", "params"), [
    (11, {}), (12, {"bw_decay_time": 0.05, "maneuver_hold": 0.02}),
    (13, {"max_range": 60_000.0, "max_speed": 400.0}), (14, {"bw_decay_time": 0.0}),
    (15, {"dwell_acq": 12, "dwell_tent": 20, "dwell_conf": 8}),
])
def test_round12_step_equals_the_former_step(seed: int, params: dict) -> None:
    """Twin managers fed the same scene through every mode, with odd inputs now and then
    (numpy and integer types, booleans, strings, None, a list, NaN/±inf, missing keys,
    float32 / short / transposed / non-finite / list SUMs) and steps of 0, NaN, −PRI, a
    string and 2·PRI: the outputs by their repr (or the same exception) and the whole state
    after every step."""
    new, old = make(**params), make(**params)
    old.__class__ = _FormerManager
    scene = Scene(37_000.0, seed=seed)
    rng = np.random.default_rng(seed)
    modes = set()
    for k in range(3 * 1000):
        scene.present = k % 1000 < 750
        inp = scene.inputs()
        _oddify(inp, rng)
        pri = scene.prev["pri"] if scene.prev else 1e-4
        dt: Any = pri
        if rng.random() < 0.03:
            dt = [0.0, math.nan, -pri, 2.0 * pri, "x", np.float32(pri)][int(rng.integers(6))]
        r_old, r_new = _outcome(old, dt, dict(inp)), _outcome(new, dt, dict(inp))
        assert r_new == r_old, k
        assert _mgr_state(new) == _mgr_state(old), k
        if r_new[0] == "ok":
            scene.prev = new.outputs() | {"pri": new._all_pris[new._pri_idx]}
            modes.add(new.mode)
        scene.t += pri
    assert modes == {ACQUISITION, TENTATIVE, CONFIRMED}
