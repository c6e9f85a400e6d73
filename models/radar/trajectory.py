"""Analytic target trajectories in the local ENU frame (X East, Y North, Z Up; m, s).

Every trajectory returns truth position, velocity and acceleration at any time ``t``
analytically (closed forms, no numerical integration, hence no drift), for a scalar ``t``
(arrays of shape (3,)) or a 1-D array of times (arrays of shape (n, 3)):

- :class:`ConstantVelocity` (CV):  p(t) = p0 + v0 τ,  τ = t − t0.
- :class:`ConstantAcceleration` (CA):  p(t) = p0 + v0 τ + a τ²/2,  v(t) = v0 + a τ.
- :class:`CoordinatedTurn`: horizontal turn at constant turn rate ω (> 0: counter-clockwise seen
  from above, i.e. a left turn), keeping the speed: the horizontal velocity rotates at ω, the
  vertical velocity is constant (a level turn when vz = 0, a helix otherwise). Centripetal
  acceleration |a| = ω·v_h = v_h²/r. Built from ω or from a load ``g`` in units of
  g0 = 9.80665 m/s²: ω = g·g0 / v_h.
  # assumption: "an n-g turn" means a horizontal centripetal acceleration of n·g0
  # (v²/r = n·g0), as the brief states; the aerodynamic load factor of a level coordinated turn
  # would be √(1 + n²).
- :class:`Piecewise`: a chain of CV/CA/turn segments with onset/offset times, each segment
  starting from the end state of the previous one (continuous position and velocity); gaps
  between an offset and the next onset, and the time after the last offset, are flown at
  constant velocity.
- :class:`Waypoints`: piecewise constant velocity through given points at given times (or at a
  given constant speed); the velocity jumps at the waypoints (documented: no turn modelling).

:func:`trajectory_from_spec` builds any of them from a plain dict or JSON string (a scenario
file or an FMU String parameter) and raises ``ValueError`` naming the offending key.
:data:`DEFAULT_TRAJECTORY_SPEC` is the closed-loop default scenario (SYSTEM.md "closed-loop
default"); its values are assumptions, documented next to it.
"""

from __future__ import annotations

import bisect
import json
import math
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

G0 = 9.80665  # standard gravity [m/s²] (assumption: the "g" of load factors)

StateArrays = tuple[np.ndarray, np.ndarray, np.ndarray]


def _as_vec3(value: Any, name: str) -> np.ndarray:
    """A finite 3-vector [m, m/s or m/s²] or ``ValueError`` naming ``name``."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(
            f"trajectory spec: key '{name}' must be a list of 3 finite numbers, got {value!r}"
        ) from None
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(
            f"trajectory spec: key '{name}' must be a list of 3 finite numbers, got {value!r}"
        )
    return arr


def _as_float(value: Any, name: str, positive: bool = False, nonneg: bool = False) -> float:
    """A finite float or ``ValueError`` naming ``name``."""
    if isinstance(value, bool):
        raise ValueError(f"trajectory spec: key '{name}' must be a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"trajectory spec: key '{name}' must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"trajectory spec: key '{name}' must be finite, got {value!r}")
    if positive and x <= 0.0:
        raise ValueError(f"trajectory spec: key '{name}' must be > 0, got {value!r}")
    if nonneg and x < 0.0:
        raise ValueError(f"trajectory spec: key '{name}' must be >= 0, got {value!r}")
    return x


class Trajectory(ABC):
    """Truth motion of one point target; evaluated analytically at any time [s]."""

    def state(self, t: float | np.ndarray) -> StateArrays:
        """Position [m], velocity [m/s], acceleration [m/s²] at time(s) ``t`` [s].

        Scalar ``t`` gives three arrays of shape (3,); a 1-D array of n times gives (n, 3).
        """
        tt = np.asarray(t, dtype=float)
        scalar = tt.ndim == 0
        p, v, a = self._eval(np.atleast_1d(tt))
        if scalar:
            return p[0], v[0], a[0]
        return p, v, a

    def state_tuple(self, t: float) -> tuple[tuple[float, float, float], ...]:
        """(p, v, a) at one time ``t`` [s] as tuples of floats (fast path, same formulas)."""
        p, v, a = self._eval(np.array([float(t)]))
        return tuple(p[0].tolist()), tuple(v[0].tolist()), tuple(a[0].tolist())

    def segment(self, t: float) -> tuple[float, float, Trajectory]:
        """(lo, hi, piece): ``piece.state_tuple(u)`` is ``self.state_tuple(u)`` for every time
        lo ≤ u < hi [s], ``t`` among them unless it is NaN (here: the whole time line, the
        trajectory itself). The TargetGenerator calls the piece directly while its times stay
        in the interval (issue 14, round 9: one call per pulse instead of two)."""
        return -math.inf, math.inf, self

    def position(self, t: float | np.ndarray) -> np.ndarray:
        """Position [m] at ``t`` [s]."""
        return self.state(t)[0]

    def velocity(self, t: float | np.ndarray) -> np.ndarray:
        """Velocity [m/s] at ``t`` [s]."""
        return self.state(t)[1]

    def acceleration(self, t: float | np.ndarray) -> np.ndarray:
        """Acceleration [m/s²] at ``t`` [s]."""
        return self.state(t)[2]

    @abstractmethod
    def _eval(self, t: np.ndarray) -> StateArrays:
        """(p, v, a), each (n, 3), for a 1-D array of times ``t`` [s]."""


class ConstantVelocity(Trajectory):
    """p(t) = p0 + v0 (t − t0)  [m]; p0 [m], v0 [m/s], t0 [s]."""

    def __init__(self, p0: Sequence[float], v0: Sequence[float], t0: float = 0.0) -> None:
        self.p0 = np.asarray(p0, dtype=float).reshape(3)
        self.v0 = np.asarray(v0, dtype=float).reshape(3)
        self.t0 = float(t0)
        self._p0v0 = (tuple(self.p0.tolist()), tuple(self.v0.tolist()))  # for state_tuple

    def state_tuple(self, t: float) -> tuple[tuple[float, float, float], ...]:
        tau = t - self.t0
        (x, y, z), (vx, vy, vz) = self._p0v0
        return (x + vx * tau, y + vy * tau, z + vz * tau), (vx, vy, vz), (0.0, 0.0, 0.0)

    def _eval(self, t: np.ndarray) -> StateArrays:
        tau = (t - self.t0)[:, None]
        p = self.p0 + self.v0 * tau
        v = np.empty(p.shape)
        v[:] = self.v0
        return p, v, np.zeros(p.shape)


class ConstantAcceleration(Trajectory):
    """p(t) = p0 + v0 τ + a τ²/2, v(t) = v0 + a τ, τ = t − t0; a [m/s²]."""

    def __init__(
        self, p0: Sequence[float], v0: Sequence[float], a: Sequence[float], t0: float = 0.0
    ) -> None:
        self.p0 = np.asarray(p0, dtype=float).reshape(3)
        self.v0 = np.asarray(v0, dtype=float).reshape(3)
        self.a = np.asarray(a, dtype=float).reshape(3)
        self.t0 = float(t0)

    def state_tuple(self, t: float) -> tuple[tuple[float, float, float], ...]:
        tau = t - self.t0
        p0, v0, a = self.p0.tolist(), self.v0.tolist(), self.a.tolist()
        return (
            tuple(p0[i] + v0[i] * tau + 0.5 * a[i] * tau * tau for i in range(3)),
            tuple(v0[i] + a[i] * tau for i in range(3)),
            tuple(a),
        )

    def _eval(self, t: np.ndarray) -> StateArrays:
        tau = (t - self.t0)[:, None]
        p = self.p0 + self.v0 * tau + 0.5 * self.a * tau * tau
        v = self.v0 + self.a * tau
        return p, v, np.broadcast_to(self.a, p.shape).copy()


class CoordinatedTurn(Trajectory):
    """Horizontal turn at constant rate ω [rad/s] (> 0 counter-clockwise/left), speed kept.

    With the horizontal velocity (vx, vy) rotated by φ = ω τ:
        vx(t) = vx cos φ − vy sin φ,  vy(t) = vx sin φ + vy cos φ,  vz(t) = vz
        x(t) = x0 + (vx sin φ − vy (1 − cos φ))/ω,  y(t) = y0 + (vx (1 − cos φ) + vy sin φ)/ω
        z(t) = z0 + vz τ,   a(t) = ω (−vy(t), vx(t), 0)
    (closed form of the integral; (1 − cos φ)/ω is computed as 2 sin²(φ/2)/ω, free of
    cancellation for small ω; ω = 0 is exact CV).
    """

    def __init__(
        self, p0: Sequence[float], v0: Sequence[float], turn_rate: float, t0: float = 0.0
    ) -> None:
        self.p0 = np.asarray(p0, dtype=float).reshape(3)
        self.v0 = np.asarray(v0, dtype=float).reshape(3)
        self.turn_rate = float(turn_rate)
        self.t0 = float(t0)
        self._p0 = tuple(float(x) for x in self.p0)
        self._v0 = tuple(float(x) for x in self.v0)

    @classmethod
    def from_load(
        cls,
        p0: Sequence[float],
        v0: Sequence[float],
        g: float,
        direction: str = "left",
        t0: float = 0.0,
    ) -> CoordinatedTurn:
        """Turn with centripetal acceleration g·G0 [m/s²]: ω = g·G0 / v_h (v_h > 0 required)."""
        vh = math.hypot(float(v0[0]), float(v0[1]))
        if vh <= 0.0:
            raise ValueError("trajectory spec: a turn given by 'g' needs a horizontal velocity")
        sign = 1.0 if direction == "left" else -1.0
        return cls(p0, v0, sign * g * G0 / vh, t0)

    def state_tuple(self, t: float) -> tuple[tuple[float, float, float], ...]:
        w = self.turn_rate
        vx0, vy0, vz0 = self._v0
        x0, y0, z0 = self._p0
        tau = t - self.t0
        if w == 0.0:
            return (x0 + vx0 * tau, y0 + vy0 * tau, z0 + vz0 * tau), self._v0, (0.0, 0.0, 0.0)
        ph = w * tau
        s, c = math.sin(ph), math.cos(ph)
        sw, cw = s / w, 2.0 * math.sin(0.5 * ph) ** 2 / w  # same formulas as _eval
        vx, vy = vx0 * c - vy0 * s, vx0 * s + vy0 * c
        return (
            (x0 + vx0 * sw - vy0 * cw, y0 + vx0 * cw + vy0 * sw, z0 + vz0 * tau),
            (vx, vy, vz0),
            (-w * vy, w * vx, 0.0),
        )

    def _eval(self, t: np.ndarray) -> StateArrays:
        w = self.turn_rate
        vx0, vy0, vz0 = self._v0
        tau = t - self.t0
        n = t.shape[0]
        p = np.empty((n, 3))
        v = np.empty((n, 3))
        a = np.zeros((n, 3))
        if w == 0.0:  # straight flight
            s_over_w = tau
            one_minus_c_over_w = np.zeros(n)
            c, s = 1.0, 0.0
        else:
            phi = w * tau
            s, c = np.sin(phi), np.cos(phi)
            s_over_w = s / w  # sin(ωτ)/ω
            one_minus_c_over_w = 2.0 * np.sin(0.5 * phi) ** 2 / w  # (1 − cos ωτ)/ω, no cancel.
        p[:, 0] = self.p0[0] + vx0 * s_over_w - vy0 * one_minus_c_over_w
        p[:, 1] = self.p0[1] + vx0 * one_minus_c_over_w + vy0 * s_over_w
        p[:, 2] = self.p0[2] + vz0 * tau
        v[:, 0] = vx0 * c - vy0 * s
        v[:, 1] = vx0 * s + vy0 * c
        v[:, 2] = vz0
        a[:, 0] = -w * v[:, 1]
        a[:, 1] = w * v[:, 0]
        return p, v, a


class Piecewise(Trajectory):
    """Chain of trajectories, segment i valid on [start_i, start_{i+1}).

    Before the first start the first segment is extrapolated analytically. Built by
    :func:`trajectory_from_spec` so that every segment starts at the end state of the previous
    one (continuous position and velocity).
    """

    def __init__(self, starts: Sequence[float], pieces: Sequence[Trajectory]) -> None:
        if len(starts) != len(pieces) or not pieces:
            raise ValueError("Piecewise needs one start time per piece")
        self.starts = np.asarray(starts, dtype=float)
        if np.any(np.diff(self.starts) < 0.0):
            raise ValueError("Piecewise start times must be non-decreasing")
        self.pieces = list(pieces)
        self._starts_list = [float(x) for x in self.starts]

    def _index(self, t: float) -> int:
        i = bisect.bisect_right(self._starts_list, t) - 1
        return min(max(i, 0), len(self.pieces) - 1)

    def state_tuple(self, t: float) -> tuple[tuple[float, float, float], ...]:
        # _index inlined (per-pulse path, issue 14): bisect_right ≤ len, so i ≤ len − 1
        i = bisect.bisect_right(self._starts_list, t) - 1
        return self.pieces[i if i > 0 else 0].state_tuple(t)

    def segment(self, t: float) -> tuple[float, float, Trajectory]:
        """:meth:`Trajectory.segment`: the interval where :meth:`state_tuple` takes the piece it
        takes at ``t`` ([start_i, start_(i+1)); the first piece below start_1, the last one
        from its start on), within that piece's own segment."""
        starts = self._starts_list
        i = bisect.bisect_right(starts, t) - 1
        i = i if i > 0 else 0
        lo = starts[i] if i > 0 else -math.inf
        hi = starts[i + 1] if i + 1 < len(starts) else math.inf
        p_lo, p_hi, piece = self.pieces[i].segment(t)
        return (lo if lo > p_lo else p_lo), (hi if hi < p_hi else p_hi), piece

    def _eval(self, t: np.ndarray) -> StateArrays:
        last = len(self.pieces) - 1
        if t.shape[0] == 1:  # fast path
            return self.pieces[self._index(float(t[0]))]._eval(t)
        idx = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, last)
        if idx[0] == idx[-1] and np.all(np.diff(t) >= 0.0):  # sorted times in one segment
            return self.pieces[int(idx[0])]._eval(t)
        n = t.shape[0]
        p, v, a = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
        for i in np.unique(idx):
            m = idx == i
            p[m], v[m], a[m] = self.pieces[int(i)]._eval(t[m])
        return p, v, a


class Waypoints(Piecewise):
    """Constant-velocity legs through ``points`` [m] reached at ``times`` [s].

    Before the first time the first leg is extrapolated; after the last point the target keeps
    the last leg's velocity. Acceleration is zero (velocity jumps at the waypoints).
    """

    def __init__(self, points: Sequence[Sequence[float]], times: Sequence[float]) -> None:
        pts = np.asarray(points, dtype=float)
        ts = np.asarray(times, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] < 2:
            raise ValueError("trajectory spec: key 'points' needs at least 2 points of 3 numbers")
        if ts.shape != (pts.shape[0],) or np.any(np.diff(ts) <= 0.0):
            raise ValueError("trajectory spec: key 'times' must increase strictly, one per point")
        self.points, self.times = pts, ts
        legs = [
            ConstantVelocity(pts[i], (pts[i + 1] - pts[i]) / (ts[i + 1] - ts[i]), ts[i])
            for i in range(len(ts) - 1)
        ]
        super().__init__(ts[:-1], legs)


# ---------------------------------------------------------------------------------------------
# Building from a plain spec (dict or JSON)
# ---------------------------------------------------------------------------------------------

_TYPE_ALIASES = {
    "cv": "cv", "constant_velocity": "cv",
    "ca": "ca", "constant_acceleration": "ca",
    "turn": "turn", "coordinated_turn": "turn",
    "piecewise": "piecewise", "segments": "piecewise",
    "waypoints": "waypoints",
}
_MOTION_KEYS = {"cv": set(), "ca": {"acceleration"}, "turn": {"g", "turn_rate", "direction"}}


def _check_keys(spec: Mapping[str, Any], allowed: set[str], where: str) -> None:
    unknown = sorted(set(spec) - allowed)
    if unknown:
        raise ValueError(
            f"trajectory spec: unknown key(s) {', '.join(repr(where + k) for k in unknown)}; "
            f"allowed: {', '.join(sorted(allowed))}"
        )


def _kind(spec: Mapping[str, Any], where: str) -> str:
    if "type" not in spec:
        raise ValueError(f"trajectory spec: key '{where}type' is missing")
    kind = _TYPE_ALIASES.get(str(spec["type"]).lower())
    if kind is None:
        raise ValueError(
            f"trajectory spec: key '{where}type' = {spec['type']!r} is invalid; valid: "
            + ", ".join(sorted(_TYPE_ALIASES))
        )
    return kind


def _motion(
    kind: str, spec: Mapping[str, Any], p0: np.ndarray, v0: np.ndarray, t0: float, where: str
) -> Trajectory:
    """A CV/CA/turn trajectory starting at (p0, v0) at t0, parameters from ``spec``."""
    if kind == "cv":
        return ConstantVelocity(p0, v0, t0)
    if kind == "ca":
        if "acceleration" not in spec:
            raise ValueError(f"trajectory spec: key '{where}acceleration' is missing")
        return ConstantAcceleration(p0, v0, _as_vec3(spec["acceleration"], where + "acceleration"),
                                    t0)
    # turn
    has_g, has_w = "g" in spec, "turn_rate" in spec
    if has_g == has_w:
        raise ValueError(
            f"trajectory spec: a turn needs exactly one of keys '{where}g' and '{where}turn_rate'"
        )
    if has_w:
        if "direction" in spec:
            raise ValueError(
                f"trajectory spec: key '{where}direction' goes with 'g' only "
                "(the sign of 'turn_rate' gives the direction)"
            )
        return CoordinatedTurn(p0, v0, _as_float(spec["turn_rate"], where + "turn_rate"), t0)
    g = _as_float(spec["g"], where + "g", nonneg=True)
    direction = spec.get("direction", "left")
    if direction not in ("left", "right"):
        raise ValueError(
            f"trajectory spec: key '{where}direction' = {direction!r} is invalid; "
            "valid: 'left', 'right'"
        )
    if math.hypot(v0[0], v0[1]) <= 0.0:
        raise ValueError(
            f"trajectory spec: key '{where}g' needs a non-zero horizontal velocity at the onset"
        )
    return CoordinatedTurn.from_load(p0, v0, g, direction, t0)


def _piecewise(spec: Mapping[str, Any]) -> Piecewise:
    p = _as_vec3(spec.get("position"), "position")
    v = _as_vec3(spec.get("velocity"), "velocity")
    t = _as_float(spec.get("t0", 0.0), "t0")
    segs = spec.get("segments")
    if not isinstance(segs, Sequence) or isinstance(segs, str) or not segs:
        raise ValueError("trajectory spec: key 'segments' must be a non-empty list of segments")
    starts: list[float] = []
    pieces: list[Trajectory] = []
    end: float | None = t  # end of the previous segment (None: open-ended)
    for i, seg in enumerate(segs):
        where = f"segments[{i}]."
        if not isinstance(seg, Mapping):
            raise ValueError(f"trajectory spec: key 'segments[{i}]' must be an object")
        kind = _kind(seg, where)
        if kind not in _MOTION_KEYS:
            raise ValueError(f"trajectory spec: key '{where}type' must be cv, ca or turn")
        _check_keys(seg, {"type", "onset", "offset", "duration"} | _MOTION_KEYS[kind], where)
        if "onset" in seg:
            onset = _as_float(seg["onset"], where + "onset")
        elif end is not None:
            onset = end
        else:
            raise ValueError(
                f"trajectory spec: key '{where}onset' is missing (the previous segment has "
                "no offset/duration)"
            )
        if onset < t:
            raise ValueError(
                f"trajectory spec: key '{where}onset' = {onset} is before the previous "
                f"segment's start/end {t}"
            )
        if end is not None and onset < end:
            raise ValueError(
                f"trajectory spec: key '{where}onset' = {onset} is before the end of the "
                f"previous segment ({end})"
            )
        if pieces and onset > t:  # advance the state to the onset (gap flown at CV)
            prev = pieces[-1]
            if end is not None and onset > end:
                pe, ve, _ = prev.state(end)
                starts.append(end)
                pieces.append(ConstantVelocity(pe, ve, end))
            p, v, _ = pieces[-1].state(onset)
        elif not pieces and onset > t:  # CV from t0 up to the first onset
            starts.append(t)
            pieces.append(ConstantVelocity(p, v, t))
            p, v, _ = pieces[-1].state(onset)
        if "offset" in seg and "duration" in seg:
            raise ValueError(f"trajectory spec: give only one of '{where}offset', "
                             f"'{where}duration'")
        if "duration" in seg:
            end = onset + _as_float(seg["duration"], where + "duration", nonneg=True)
        elif "offset" in seg:
            end = _as_float(seg["offset"], where + "offset")
            if end < onset:
                raise ValueError(f"trajectory spec: key '{where}offset' = {end} is before the "
                                 f"onset {onset}")
        else:
            end = None
        starts.append(onset)
        pieces.append(_motion(kind, seg, p, v, onset, where))
        t = onset
    if end is not None:  # after the last offset: constant velocity
        pe, ve, _ = pieces[-1].state(end)
        starts.append(end)
        pieces.append(ConstantVelocity(pe, ve, end))
    return Piecewise(starts, pieces)


def _waypoints(spec: Mapping[str, Any]) -> Waypoints:
    pts_raw = spec.get("points")
    if not isinstance(pts_raw, Sequence) or isinstance(pts_raw, str) or len(pts_raw) < 2:
        raise ValueError("trajectory spec: key 'points' must be a list of at least 2 points")
    pts = np.array([_as_vec3(q, f"points[{i}]") for i, q in enumerate(pts_raw)])
    if ("times" in spec) == ("speed" in spec):
        raise ValueError("trajectory spec: waypoints need exactly one of keys 'times', 'speed'")
    if "times" in spec:
        raw = spec["times"]
        if not isinstance(raw, Sequence) or isinstance(raw, str) or len(raw) != len(pts):
            raise ValueError("trajectory spec: key 'times' must be a list with one time per point")
        times = np.array([_as_float(x, f"times[{i}]") for i, x in enumerate(raw)])
        if np.any(np.diff(times) <= 0.0):
            raise ValueError("trajectory spec: key 'times' must increase strictly")
    else:
        speed = _as_float(spec["speed"], "speed", positive=True)
        t0 = _as_float(spec.get("t0", 0.0), "t0")
        seg_len = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if np.any(seg_len <= 0.0):
            raise ValueError("trajectory spec: key 'points' has two equal consecutive points")
        times = t0 + np.concatenate(([0.0], np.cumsum(seg_len) / speed))
    return Waypoints(pts, times)


def trajectory_from_spec(spec: Mapping[str, Any] | str) -> Trajectory:
    """Build a trajectory from a dict or a JSON string.

    Forms (lengths in m, times in s, ENU):

    - ``{"type": "cv", "position": [x, y, z], "velocity": [vx, vy, vz], "t0": 0}``
    - ``{"type": "ca", ..., "acceleration": [ax, ay, az]}``
    - ``{"type": "turn", ..., "g": 3, "direction": "left"|"right"}`` or ``"turn_rate": ω``
      [rad/s, > 0 left]
    - ``{"type": "piecewise", "position", "velocity", "t0", "segments": [seg, ...]}`` where each
      seg is ``{"type": "cv"|"ca"|"turn", <its keys>, "onset": t, "offset": t | "duration": d}``;
      onset defaults to the previous segment's end; gaps and the time after the last offset are
      flown at constant velocity; position and velocity are continuous at every onset.
    - ``{"type": "waypoints", "points": [[x, y, z], ...], "times": [...]}`` or ``"speed": v``
      (with optional ``"t0"``).

    Raises ``ValueError`` naming the bad key.
    """
    if isinstance(spec, str):
        try:
            spec = json.loads(spec)
        except json.JSONDecodeError as exc:
            raise ValueError(f"trajectory spec: invalid JSON ({exc})") from None
    if not isinstance(spec, Mapping):
        raise ValueError("trajectory spec: must be an object (dict / JSON object)")
    kind = _kind(spec, "")
    if kind == "waypoints":
        _check_keys(spec, {"type", "points", "times", "speed", "t0"}, "")
        return _waypoints(spec)
    if kind == "piecewise":
        _check_keys(spec, {"type", "position", "velocity", "t0", "segments"}, "")
        return _piecewise(spec)
    _check_keys(spec, {"type", "position", "velocity", "t0"} | _MOTION_KEYS[kind], "")
    if "position" not in spec:
        raise ValueError("trajectory spec: key 'position' is missing")
    if "velocity" not in spec:
        raise ValueError("trajectory spec: key 'velocity' is missing")
    p0 = _as_vec3(spec["position"], "position")
    v0 = _as_vec3(spec["velocity"], "velocity")
    t0 = _as_float(spec.get("t0", 0.0), "t0")
    return _motion(kind, spec, p0, v0, t0, "")


# Closed-loop default scenario (SYSTEM.md "closed-loop default": a 3-D aircraft passing the
# radar with a maneuver). All values are assumptions:
# - start 6 km west, 12 km north, 1.5 km up (range 13.5 km, elevation 6.4°), flying east at
#   200 m/s and climbing at 10 m/s (speed 200.2 m/s);
# - a 3 g level-rate left turn (ω = 3·9.80665/200 = 0.147 rad/s, radius 1.36 km) from t = 16 s
#   to t = 24 s (heading change 67°), then straight flight;
# - over a 40 s run the range stays within ≈ 12.2–15.8 km and the altitude within 1.5–1.9 km.
DEFAULT_TRAJECTORY_SPEC: dict[str, Any] = {
    "type": "piecewise",
    "position": [-6000.0, 12000.0, 1500.0],
    "velocity": [200.0, 0.0, 10.0],
    "t0": 0.0,
    "segments": [
        {"type": "cv", "onset": 0.0},
        {"type": "turn", "g": 3.0, "direction": "left", "onset": 16.0, "duration": 8.0},
    ],
}
DEFAULT_TRAJECTORY_JSON = json.dumps(DEFAULT_TRAJECTORY_SPEC)
