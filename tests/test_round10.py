"""Issue 14, round 10 (branch spd17): more of the per-PRI path without calls, each bit for bit
the code it replaces (the general form kept as the reference: main's step of the unit in the
round-8/9 tests, or the function itself), on random and edge cases.

- TargetGenerator: a :class:`ConstantVelocity` trajectory piece's ``state_tuple`` written out
  in ``step``; the straddle weights 1 − |q − k|, 1 − |q − k − 1| without ``abs``; ``dt``
  converted once (no ``float`` call for a float).
- Tracker: the run loop calls the input mode's step (``Tracker.run_step``: no unit frame);
  the outputs of the α-β axes without DDRE from a template holding their ``track.acc.*`` and
  ``ddre.*`` values; the gate cells read by one slice.
- ``radar.mti.mti_power_gain`` on a Python float: no 0-d array (``mti_power_gain_array``, the
  general form, is the reference).
"""

from __future__ import annotations

import copy
import math
import pickle
import struct
from typing import Any

import numpy as np
import pytest
from test_round9 import _FormerTGStep
from test_tg_round8 import two_adjacent_bins
from test_tracker_round8 import _bits, _FormerBeamTracker, _inputs, _state, _tracker

from axir.models.loop import DirectLoop
from axir.models.radar.conventions import BIN_M, CONFIRMED, N_BINS, C
from axir.models.radar.mti import mti_power_gain, mti_power_gain_array
from axir.models.target_generator import TargetGenerator
from axir.models.tracker import Tracker
from axir.models.tracker.outputs import NO_DDRE


def _f(x: float) -> bytes:
    return struct.pack("<d", x)


# ------------------------------------------------ TargetGenerator: the CV piece and the weights
_CV_TRAJ = [
    '{"type": "cv", "position": [-5000, 9000, 1200], "velocity": [150, -120, 30]}',
    '{"type": "cv", "position": [4000, -11000, 700], "velocity": [-133.3, 87.7, -2.25], '
    '"t0": 0.0137}',
    # CV pieces with their own t0 (tau = t − t0 of each), a turn between: the written-out
    # piece and the called one alternate at the segment bounds
    '{"type": "piecewise", "position": [-6000, 12000, 1500], "velocity": [200, 3, 10], '
    '"t0": 0, "segments": [{"type": "cv", "onset": 0}, {"type": "turn", "g": 3, '
    '"direction": "left", "onset": 0.01, "duration": 0.012}, {"type": "cv", "onset": 0.022}, '
    '{"type": "ca", "onset": 0.031, "acceleration": [1, 2, -3]}, {"type": "cv", '
    '"onset": 0.036}]}',
    '{"type": "waypoints", "points": [[3000, 8000, 500], [3010, 7990, 505], '
    '[2990, 8005, 499], [3000, 8000, 510]], "times": [0.0, 0.011, 0.019, 0.03]}',
]


@pytest.mark.parametrize("traj", _CV_TRAJ)
def test_tg_cv_piece_written_out_equals_the_former_step(traj: str) -> None:
    """Twin generators (main's step before round 9, ``_FormerTGStep``: the trajectory's
    ``state_tuple`` called, ``float(dt)`` and the straddle weights by ``abs``) on CV targets,
    CV pieces of piecewise and waypoint trajectories (own t0, segment bounds crossed), steps of
    one PRI as floats, numpy floats and ints (0), of 0 and of 3 PRIs, restored states: outputs
    by their bits, the truth, the filter state, t and its type."""
    rng = np.random.default_rng(sum(map(ord, traj)))
    new, old = TargetGenerator(trajectory=traj), TargetGenerator(trajectory=traj)
    old.__class__ = _FormerTGStep
    o = new.outputs()
    cv_steps = 0
    for k in range(450):
        pri = 1e-4 if rng.random() < 0.97 else 1.25e-4
        inp = {"antenna.az": o["truth.az"] + rng.normal(0.0, 0.01),
               "antenna.el": o["truth.el"] + rng.normal(0.0, 0.01),
               "gate.start": o["truth.range"] - rng.uniform(-1.0, 17.0) * BIN_M,
               "doppler.centre": float(rng.uniform(-2e3, 2e3)), "pri": pri}
        u = rng.random()
        dt: Any = pri if u < 0.9 else [np.float64(pri), 0, 0.0, 3 * pri, np.float64(0.0),
                                       True][k % 6]
        if k % 150 == 149:
            new.set_state(new.get_state())
            old.set_state(old.get_state())
        if type(new._seg[3]).__name__ == "ConstantVelocity":
            cv_steps += 1
        o_old, o = old.step(dt, inp), new.step(dt, inp)
        assert list(o) == list(o_old)
        assert [_bits(v) for v in o.values()] == [_bits(v) for v in o_old.values()], k
        assert new._y.tobytes() == old._y.tobytes(), k
        assert repr(new._truth[2:]) == repr(old._truth[2:]) and _f(new._truth[0]) == _f(
            old._truth[0]), k
        assert type(new.t) is type(old.t) is float and _f(new.t) == _f(old.t), k
        assert new._pulse == old._pulse
    assert cv_steps > 100, cv_steps


def test_tg_bad_dt_still_raises_and_leaves_the_state() -> None:
    """dt negative, NaN, ±inf, a string or an int too large for a float: the same exception
    (type and message) and the state unchanged, before and after."""
    for dt in (-1e-4, math.nan, math.inf, -math.inf, "1e-4", 10**400, np.float64(-1.0)):
        new, old = TargetGenerator(), TargetGenerator()
        old.__class__ = _FormerTGStep
        errs = []
        for g in (new, old):
            before = pickle.dumps(g.get_state())
            try:
                g.step(dt, {"pri": 1e-4})
                errs.append(None)
            except (ValueError, TypeError, OverflowError) as e:
                errs.append((type(e), str(e)))
            assert pickle.dumps(g.get_state()) == before
        assert errs[0] == errs[1] and errs[0] is not None, (dt, errs)


@pytest.mark.parametrize("mti", [1, 2])
def test_tg_mti_switch_off_stays_off_equals_the_former_step(mti: int) -> None:
    """The canceller's switch tested as ``on and el > max_el + hysteresis`` (off stays off
    without the comparison): twin generators (main's former step) with the antenna elevation
    swept down through max_el, inside the hysteresis band and up again, with NaN elevations
    now and then: outputs, the switch state and the canceller memory equal after every step;
    the switch went on and off."""
    rng = np.random.default_rng(12 + mti)
    params = {"mti": mti, "mti_max_el": 0.08, "mti_hysteresis": 0.01}
    new, old = TargetGenerator(**params), TargetGenerator(**params)
    old.__class__ = _FormerTGStep
    o = new.outputs()
    flips = 0
    for k in range(900):
        el = 0.08 + 0.03 * math.sin(k / 40.0) + rng.normal(0.0, 0.002)
        if k % 113 == 0:
            el = math.nan
        inp = {"antenna.az": o["truth.az"] + rng.normal(0.0, 0.01), "antenna.el": el,
               "gate.start": o["truth.range"] - 6.0 * BIN_M, "doppler.centre": 250.0,
               "pri": 1e-4}
        was = new._mti_on
        o_old, o = old.step(1e-4, inp), new.step(1e-4, inp)
        flips += was != new._mti_on
        assert [_bits(v) for v in o.values()] == [_bits(v) for v in o_old.values()], k
        assert new._mti_on is old._mti_on and new._xh.tobytes() == old._xh.tobytes(), k
    assert flips >= 6, flips


def _weights_new(r: float, gate: float, ru: float) -> tuple[int, float, float] | None:
    """The lines of ``TargetGenerator.step`` that replace ``two_adjacent_bins``."""
    d1 = (r - gate) % ru
    if not d1 > ru - BIN_M:
        q = d1 / BIN_M
        k = math.floor(q)
        if k < N_BINS - 1:
            return k, 1.0 - (q - k), 1.0 + (q - (k + 1))
    return None


def test_straddle_weights_without_abs_equal_two_adjacent_bins() -> None:
    """The weights as 1 − (q − k) and 1 + (q − (k + 1)) equal two_adjacent_bins' (the
    round-8 reference, with abs) by their bits: 300 000 random delays, every bin's edges
    (q = k, the ulp below k + 1, the ulp above k) and the aliased edges."""
    rng = np.random.default_rng(10)
    ru = 0.5 * C * 1e-4
    g = rng.uniform(-2e3, 2e4, 300_000)  # delays in and around the window, ± folds of Ru
    r = g + rng.uniform(-150.0, N_BINS * BIN_M + 150.0, 300_000) + ru * rng.integers(-1, 2,
                                                                                       300_000)
    cases = list(zip(r.tolist(), g.tolist(), strict=True))
    for k in range(N_BINS + 1):
        for x in (k * BIN_M, float(np.nextafter(k * BIN_M, 0.0)),
                  float(np.nextafter(k * BIN_M, math.inf)), ru - BIN_M, ru, 0.0, -0.0):
            cases += [(x, 0.0), (x + 1e4, 1e4), (1e4, 1e4 - x)]
    n = 0
    for r, g in cases:
        a, b = _weights_new(r, g, ru), two_adjacent_bins(r, g, ru)
        if b is None:
            assert a is None, (r, g)
            continue
        n += 1
        assert a is not None and a[0] == b[0] and _f(a[1]) == _f(b[1]) and _f(a[2]) == _f(
            b[2]), (r, g, a, b)
    assert n > 100_000


# --------------------------------------------------------------- radar.mti: the scalar case
def test_mti_power_gain_scalar_equals_the_array_form() -> None:
    """``mti_power_gain`` of a Python float (no 0-d array) equals ``mti_power_gain_array``
    (the general form) by bits and type (numpy float64) for orders 1-3 on 100 000 random ν and
    the edges; order 0, numpy scalars and arrays take the general form (the same objects)."""
    rng = np.random.default_rng(11)
    nus = [*rng.uniform(-2.0, 2.0, 100_000).tolist(), 0.0, -0.0, 0.25, 0.5, 1.0,
           float(np.nextafter(1.0, 0.0)), 5e-324, 1e-300, 1e300, -1e300, math.inf, -math.inf,
           math.nan, 0.06931]
    with np.errstate(all="ignore"):
        for order in (1, 2, 3):
            for nu in nus:
                a, b = mti_power_gain(nu, order), mti_power_gain_array(nu, order)
                assert type(a) is type(b) is np.float64, (nu, order)
                assert a.tobytes() == b.tobytes(), (nu, order)
        for nu in (0.3, np.float64(0.3), np.array([0.1, 0.3])):
            for order in (0, 1, 2):
                a, b = mti_power_gain(nu, order), mti_power_gain_array(nu, order)
                assert type(a) is type(b) and np.asarray(a).tobytes() == np.asarray(b).tobytes()
                assert np.shape(a) == np.shape(b)


# ------------------------------------------------------ Tracker: the outputs' ddre/acc template
@pytest.mark.parametrize("params", [{"track_init_n": 2}, {"track_init_n": 2, "ddre_window": 3},
                                    {"track_init_n": 2, "filter_x": "kalman",
                                     "filter_y": "kalman", "filter_z": "kalman"}])
def test_tracker_outputs_template_equals_the_former_step(params: dict[str, Any]) -> None:
    """Twin trackers (round 8's reference step, every output stored): with the α-β axes and no
    DDRE (the template holding track.acc.* = 0.0 and ddre.* = NO_DDRE), with DDRE (ddre_out
    changing: the stores) and with Kalman axes (not legacy: the stores); restored by
    get_state/set_state (ddre_out still NO_DDRE itself: the template) and by pickle (an equal
    tuple, not NO_DDRE: the stores): outputs by their bits and the state after every step;
    both output forms taken where they apply."""
    rng = np.random.default_rng(sum(map(ord, repr(params))))
    new, old = _tracker(**params), _tracker(**params)
    old.core.__class__ = _FormerBeamTracker
    seen = {"template": 0, "stores": 0}
    for k in range(1500):
        mode = 1 if k % 500 < 20 else CONFIRMED
        inp: dict[str, Any] = _inputs(rng, k, mode, 7000.0 + 0.02 * k, 0.0, 0.4, 0.15,
                                      strong=rng.random() < 0.9)
        if k % 300 == 299:
            new.set_state(new.get_state())
            old.set_state(old.get_state())
        elif k == 1049:  # from here on ddre_out is an equal tuple, not NO_DDRE itself
            new.core = pickle.loads(pickle.dumps(new.core))
            old.core = pickle.loads(pickle.dumps(old.core))
        core = new.core
        if core.legacy_detector and core.ddre_out is NO_DDRE:
            seen["template"] += 1
        else:
            seen["stores"] += 1
        o_old, o_new = old.core.step(1e-4, inp), new.core.step(1e-4, inp)
        assert list(o_new) == list(o_old)
        assert [_bits(v) for v in o_new.values()] == [_bits(v) for v in o_old.values()], k
        assert _state(new.core) == _state(old.core), k
    if "ddre_window" in params or "filter_x" in params:
        assert seen["stores"] > 1000 and (seen["template"] == 0 or "ddre_window" in params)
    else:
        assert seen["template"] > 1000 and seen["stores"] > 300, seen


def test_no_ddre_survives_deepcopy_as_itself() -> None:
    """The template's test is ``ddre_out is NO_DDRE``: a deep copy (get_state) keeps the
    object, a pickled copy does not (then the stores, the same values)."""
    assert copy.deepcopy(NO_DDRE) is NO_DDRE
    assert pickle.loads(pickle.dumps(NO_DDRE)) == NO_DDRE


# ------------------------------------------------------- the run loop: Tracker.run_step
def test_tracker_run_step_is_the_core_step_unless_step_was_replaced() -> None:
    trk = Tracker()
    assert trk.run_step() == trk.core.step
    trk.step = lambda dt, inputs: {}  # wrapped on the instance (benchmarks): that one
    assert trk.run_step() is trk.step

    class _Sub(Tracker):
        def step(self, dt: float, inputs: Any) -> dict[str, Any]:
            return super().step(dt, inputs)

    sub = _Sub()
    assert sub.run_step() == sub.step


def _loop_bits(loop: DirectLoop) -> list[Any]:
    return [(u, k, _bits(v)) for u, d in loop.out.items() for k, v in d.items()]


def _unit_states(loop: DirectLoop) -> list[bytes]:
    out = []
    for u in (loop.gen, loop.trk, loop.ped, loop.mgr):
        st = u.get_state()
        st.pop("core", None)
        st.pop("step", None)  # a wrapper set on the instance (the test below)
        out.append(pickle.dumps(st, protocol=4))
    out.append(_state(loop.trk.core))
    return out


def test_run_loop_with_run_step_equals_the_step_loop() -> None:
    """``DirectLoop.run`` (the Tracker's input-mode step called directly) and ``step`` repeated
    (each unit's ``step``, the Tracker's through its unit) over 0.15 s of the default
    scenario, in three runs: the outputs by their bits, t, the steps and every unit's state
    equal; a Tracker step wrapped on the instance before a run is the one the run calls."""
    a, b = DirectLoop.from_params(), DirectLoop.from_params()
    calls: list[float] = []
    steps_wrapped = 0
    for end in (0.05, 0.1, 0.15):
        s0 = a.steps
        a.run(end)
        if end > 0.05:
            steps_wrapped += a.steps - s0
        while b.t < end:
            b.step()
        assert (a.t, a.steps) == (b.t, b.steps)
        assert _loop_bits(a) == _loop_bits(b)
        assert _unit_states(a) == _unit_states(b)
        if end == 0.05:
            orig = a.trk.step
            a.trk.step = lambda h, inputs, orig=orig: calls.append(h) or orig(h, inputs)
    assert len(calls) == steps_wrapped > 0
    assert all(type(h) is float for h in calls)
