"""Analytic trajectories: closed forms, turn kinematics, continuity, waypoints, spec errors."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from axir.models.radar.trajectory import (
    DEFAULT_TRAJECTORY_JSON,
    DEFAULT_TRAJECTORY_SPEC,
    G0,
    ConstantAcceleration,
    ConstantVelocity,
    CoordinatedTurn,
    Piecewise,
    Waypoints,
    trajectory_from_spec,
)


def _fd_velocity(traj, t: np.ndarray, h: float = 1e-3) -> np.ndarray:
    """Central finite difference of position [m/s]."""
    return (traj.position(t + h) - traj.position(t - h)) / (2 * h)


def _fd_accel(traj, t: np.ndarray, h: float = 1e-3) -> np.ndarray:
    return (traj.velocity(t + h) - traj.velocity(t - h)) / (2 * h)


def test_cv_closed_form():
    tr = trajectory_from_spec(
        {"type": "cv", "position": [1, 2, 3], "velocity": [10, -20, 5], "t0": 2.0}
    )
    p, v, a = tr.state(7.0)  # τ = 5 s
    np.testing.assert_allclose(p, [51.0, -98.0, 28.0])
    np.testing.assert_allclose(v, [10.0, -20.0, 5.0])
    np.testing.assert_allclose(a, 0.0)


def test_ca_closed_form():
    tr = trajectory_from_spec({"type": "ca", "position": [0, 0, 100], "velocity": [100, 0, 0],
                               "acceleration": [0, 2, -1]})
    p, v, a = tr.state(10.0)
    np.testing.assert_allclose(p, [1000.0, 100.0, 50.0])  # p0 + v0 t + a t²/2
    np.testing.assert_allclose(v, [100.0, 20.0, -10.0])
    np.testing.assert_allclose(a, [0.0, 2.0, -1.0])


def test_vector_and_scalar_time_agree():
    tr = trajectory_from_spec(DEFAULT_TRAJECTORY_SPEC)
    ts = np.array([0.0, 3.3, 16.0, 19.7, 24.0, 35.1])
    p, v, a = tr.state(ts)
    assert p.shape == v.shape == a.shape == (6, 3)
    for i, t in enumerate(ts):
        ps, vs, as_ = tr.state(float(t))
        np.testing.assert_allclose(p[i], ps, rtol=0, atol=1e-9)
        np.testing.assert_allclose(v[i], vs, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a[i], as_, rtol=0, atol=1e-12)
        pt, vt, at = tr.state_tuple(float(t))
        np.testing.assert_allclose(pt, ps, rtol=0, atol=1e-9)
        np.testing.assert_allclose(vt, vs, rtol=0, atol=1e-12)
        np.testing.assert_allclose(at, as_, rtol=0, atol=1e-12)


@pytest.mark.parametrize("g,direction", [(3.0, "left"), (5.0, "right")])
def test_coordinated_turn_keeps_speed_and_has_ng_centripetal(g, direction):
    v0 = np.array([150.0, 200.0, 0.0])  # 250 m/s level
    tr = trajectory_from_spec({"type": "turn", "position": [0, 0, 1000], "velocity": v0.tolist(),
                               "g": g, "direction": direction})
    t = np.linspace(0.0, 30.0, 61)
    p, v, a = tr.state(t)
    speed = np.linalg.norm(v, axis=1)
    np.testing.assert_allclose(speed, 250.0, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(a, axis=1), g * G0, rtol=1e-12)  # v²/r = n g
    np.testing.assert_allclose(np.einsum("ij,ij->i", a, v), 0.0, atol=1e-8)  # ⟂ velocity
    # the path is a circle of radius v²/(n g) around a fixed centre
    r_turn = 250.0**2 / (g * G0)
    centre = p + a / np.linalg.norm(a, axis=1)[:, None] * r_turn
    np.testing.assert_allclose(centre, np.broadcast_to(centre[0], centre.shape), atol=1e-6)
    # left = counter-clockwise seen from above: positive z of v × a
    cross_z = v[:, 0] * a[:, 1] - v[:, 1] * a[:, 0]
    assert np.all(np.sign(cross_z) == (1.0 if direction == "left" else -1.0))
    # analytic velocity/acceleration match finite differences of the analytic position
    np.testing.assert_allclose(_fd_velocity(tr, t), v, atol=1e-4)
    np.testing.assert_allclose(_fd_accel(tr, t), a, atol=1e-4)


def test_turn_rate_small_and_zero_is_cv():
    p0, v0 = [10.0, 20.0, 30.0], [100.0, -50.0, 3.0]
    cv = ConstantVelocity(p0, v0)
    for w in (0.0, 1e-12):
        tr = CoordinatedTurn(p0, v0, w)
        np.testing.assert_allclose(tr.position(np.array([0.0, 50.0])), cv.position(
            np.array([0.0, 50.0])), atol=1e-6)
        np.testing.assert_allclose(tr.state_tuple(50.0)[0], cv.position(50.0), atol=1e-6)


def test_helical_turn_keeps_vertical_rate():
    tr = trajectory_from_spec({"type": "turn", "position": [0, 0, 0], "velocity": [200, 0, 10],
                               "turn_rate": -0.1})
    p, v, _ = tr.state(np.array([0.0, 7.0]))
    assert p[1, 2] == pytest.approx(70.0)
    assert v[1, 2] == pytest.approx(10.0)
    assert np.linalg.norm(v[1]) == pytest.approx(math.hypot(200, 10))


def test_piecewise_continuity_and_segment_kinematics():
    spec = {
        "type": "piecewise", "position": [0, 10000, 2000], "velocity": [-250, 0, 0], "t0": 0,
        "segments": [
            {"type": "cv"},
            {"type": "ca", "acceleration": [0, 0, 5], "onset": 5, "offset": 9},
            {"type": "turn", "g": 4, "onset": 12, "duration": 6},
            {"type": "turn", "turn_rate": 0.05, "onset": 18},
        ],
    }
    tr = trajectory_from_spec(spec)
    assert isinstance(tr, Piecewise)
    eps = 1e-7
    for t_on in (5.0, 9.0, 12.0, 18.0):
        p_minus, v_minus, _ = tr.state(t_on - eps)
        p_plus, v_plus, _ = tr.state(t_on + eps)
        np.testing.assert_allclose(p_plus, p_minus, atol=1e-3)
        np.testing.assert_allclose(v_plus, v_minus, atol=1e-3)
    # within segments: the right model
    np.testing.assert_allclose(tr.acceleration(7.0), [0, 0, 5])
    np.testing.assert_allclose(tr.acceleration(10.5), 0.0)  # gap after the CA offset: CV
    np.testing.assert_allclose(np.linalg.norm(tr.acceleration(15.0)), 4 * G0, rtol=1e-12)
    # position before the first onset is the initial CV, computed by hand
    np.testing.assert_allclose(tr.position(4.0), [-1000.0, 10000.0, 2000.0])
    # after the CA segment: vz = 5·4 = 20 m/s, climb 5·4²/2 = 40 m then 20 m/s
    np.testing.assert_allclose(tr.velocity(10.0), [-250.0, 0.0, 20.0])
    np.testing.assert_allclose(tr.position(10.0)[2], 2000.0 + 40.0 + 20.0)
    # velocity equals the finite difference of position everywhere away from onsets
    t = np.array([1.0, 6.0, 11.0, 14.5, 25.0])
    np.testing.assert_allclose(_fd_velocity(tr, t), tr.velocity(t), atol=1e-4)


def test_piecewise_offset_then_cv_forever():
    tr = trajectory_from_spec({
        "type": "piecewise", "position": [0, 0, 0], "velocity": [100, 0, 0],
        "segments": [{"type": "ca", "acceleration": [10, 0, 0], "onset": 0, "duration": 2}],
    })
    np.testing.assert_allclose(tr.velocity(100.0), [120.0, 0, 0])
    np.testing.assert_allclose(tr.position(3.0), [220.0 + 120.0, 0, 0])


def test_waypoints_pass_through_points():
    pts = [[0, 0, 1000], [1000, 0, 1000], [1000, 2000, 1500], [0, 3000, 1500]]
    tr = trajectory_from_spec({"type": "waypoints", "points": pts, "speed": 100.0, "t0": 5.0})
    assert isinstance(tr, Waypoints)
    lengths = np.linalg.norm(np.diff(np.array(pts, float), axis=0), axis=1)
    times = 5.0 + np.concatenate(([0.0], np.cumsum(lengths) / 100.0))
    np.testing.assert_allclose(tr.position(times), pts, atol=1e-9)
    mid = 0.5 * (times[:-1] + times[1:])
    np.testing.assert_allclose(np.linalg.norm(tr.velocity(mid), axis=1), 100.0)
    np.testing.assert_allclose(_fd_velocity(tr, mid), tr.velocity(mid), atol=1e-6)
    # after the last point: keeps the last leg's velocity
    last_v = (np.array(pts[3], float) - pts[2]) / (times[3] - times[2])
    np.testing.assert_allclose(tr.position(times[3] + 10.0), np.array(pts[3]) + 10.0 * last_v)


def test_waypoints_with_times():
    tr = trajectory_from_spec({"type": "waypoints", "points": [[0, 0, 0], [100, 0, 0],
                                                               [100, 100, 0]],
                               "times": [0, 10, 30]})
    np.testing.assert_allclose(tr.velocity(5.0), [10.0, 0, 0])
    np.testing.assert_allclose(tr.velocity(20.0), [0, 5.0, 0])
    np.testing.assert_allclose(tr.position(20.0), [100.0, 50.0, 0])


def test_default_scenario_assumptions():
    tr = trajectory_from_spec(DEFAULT_TRAJECTORY_JSON)
    t = np.linspace(0.0, 40.0, 801)
    p, v, a = tr.state(t)
    r = np.linalg.norm(p, axis=1)
    assert r.min() >= 8000.0 and r.max() <= 25000.0
    assert p[:, 2].min() >= 1000.0 and p[:, 2].max() <= 3000.0
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 200.0, rtol=0.01)
    acc_g = np.linalg.norm(a, axis=1) / G0
    turning = (t > 16.0) & (t < 24.0)
    np.testing.assert_allclose(acc_g[turning], 3.0, rtol=1e-9)
    assert np.all(acc_g[~turning & (np.abs(t - 16) > 1e-9) & (np.abs(t - 24) > 1e-9)] == 0.0)
    assert json.loads(DEFAULT_TRAJECTORY_JSON) == DEFAULT_TRAJECTORY_SPEC


def test_classes_direct():
    ca = ConstantAcceleration([0, 0, 0], [1, 0, 0], [0, 1, 0], t0=1.0)
    np.testing.assert_allclose(ca.position(3.0), [2.0, 2.0, 0.0])
    with pytest.raises(ValueError):
        Piecewise([0.0, -1.0], [ca, ca])


@pytest.mark.parametrize(
    "spec,key",
    [
        ("{not json", "JSON"),
        ([1, 2], "object"),
        ({"position": [0, 0, 0], "velocity": [1, 0, 0]}, "'type'"),
        ({"type": "spiral", "position": [0, 0, 0], "velocity": [1, 0, 0]}, "'type'"),
        ({"type": "cv", "velocity": [1, 0, 0]}, "'position'"),
        ({"type": "cv", "position": [0, 0, 0]}, "'velocity'"),
        ({"type": "cv", "position": [0, 0], "velocity": [1, 0, 0]}, "'position'"),
        ({"type": "cv", "position": [0, 0, "x"], "velocity": [1, 0, 0]}, "'position'"),
        ({"type": "cv", "position": [0, 0, 0], "velocity": [1, 0, float("nan")]}, "'velocity'"),
        ({"type": "cv", "position": [0, 0, 0], "velocity": [1, 0, 0], "t0": "a"}, "'t0'"),
        ({"type": "cv", "position": [0, 0, 0], "velocity": [1, 0, 0], "speed": 3}, "'speed'"),
        ({"type": "ca", "position": [0, 0, 0], "velocity": [1, 0, 0]}, "'acceleration'"),
        ({"type": "turn", "position": [0, 0, 0], "velocity": [1, 0, 0]}, "'turn_rate'"),
        ({"type": "turn", "position": [0, 0, 0], "velocity": [1, 0, 0], "g": 1,
          "turn_rate": 0.1}, "'g'"),
        ({"type": "turn", "position": [0, 0, 0], "velocity": [1, 0, 0], "g": -1}, "'g'"),
        ({"type": "turn", "position": [0, 0, 0], "velocity": [0, 0, 5], "g": 1}, "'g'"),
        ({"type": "turn", "position": [0, 0, 0], "velocity": [1, 0, 0], "g": 1,
          "direction": "up"}, "'direction'"),
        ({"type": "turn", "position": [0, 0, 0], "velocity": [1, 0, 0], "turn_rate": 0.1,
          "direction": "left"}, "'direction'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0]}, "'segments'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0],
          "segments": [{"type": "waypoints"}]}, "'segments[0].type'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0],
          "segments": [{"type": "cv"}, {"type": "ca", "acceleration": [0, 0, 1]}]},
         "'segments[1].onset'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0],
          "segments": [{"type": "cv", "duration": 5}, {"type": "cv", "onset": 3}]},
         "'segments[1].onset'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0],
          "segments": [{"type": "cv", "onset": 2, "offset": 1}]}, "'segments[0].offset'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0],
          "segments": [{"type": "cv", "onset": 2, "duration": -1}]}, "'segments[0].duration'"),
        ({"type": "piecewise", "position": [0, 0, 0], "velocity": [1, 0, 0],
          "segments": [{"type": "cv", "bogus": 1}]}, "'segments[0].bogus'"),
        ({"type": "waypoints", "points": [[0, 0, 0]], "speed": 1}, "'points'"),
        ({"type": "waypoints", "points": [[0, 0, 0], [1, 0]], "speed": 1}, "'points[1]'"),
        ({"type": "waypoints", "points": [[0, 0, 0], [1, 0, 0]]}, "'times'"),
        ({"type": "waypoints", "points": [[0, 0, 0], [1, 0, 0]], "speed": 0}, "'speed'"),
        ({"type": "waypoints", "points": [[0, 0, 0], [1, 0, 0]], "times": [1, 1]}, "'times'"),
        ({"type": "waypoints", "points": [[0, 0, 0], [0, 0, 0]], "speed": 1}, "'points'"),
    ],
)
def test_spec_errors_name_the_key(spec, key):
    with pytest.raises(ValueError, match=re.escape(key)):
        trajectory_from_spec(spec)
