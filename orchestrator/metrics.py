"""Summary figures of a recorded run (pure numpy over a :class:`~.record.Recorder`'s data, or
any record with the same ``data``/``column`` interface, e.g. :class:`ArrayRecord`).

Truthful confirmation (issue 11, point 6). A recorded sample is *confirmed on target* when the
manager is in confirmed mode AND the track is within the gates of the truth:

- range gate: |track.range − truth.range| ≤ ``range_gate_m``, default 2 bins = 150 m. The
  target's matched-filter response spans ±1 bin (±75 m, the 0.5 µs pulse, models/radar/
  conventions.py); a track more than one further bin away no longer has the target in its
  tracking cell. # assumption: 2 bins (a parameter of the metric)
- angle gate: great-circle angle between the track direction and the truth ≤
  ``angle_gate_rad``, default half the 3 dB beamwidth (2.5°/2 = 1.25°): beyond it the target is
  outside the main lobe's 3 dB contour around the track. # assumption (a parameter)

A confirmed sample outside either gate is *confirmed off target*. Keys (all times in s):

- ``lock_time``: first confirmed-ON-TARGET sample (None: never). Before issue 11 this was the
  first confirmed sample of any kind; that is now ``first_confirmed_time``.
- ``time_on_target_s``; ``held_fraction``: time on target / (end_time − lock_time).
- ``drops``: on-target confirmed episodes that end before the end of the record (the manager
  leaves confirmed mode, or the confirmed track leaves the gates).
- ``false_confirmations``: confirmed-off-target episodes (maximal runs of confirmed samples
  outside the gates: a track confirmed on clutter, on a wrong range hypothesis, or walked off
  the target); ``time_false_confirmed_s``, ``first_false_confirmation_time``.
- ``rms_range_error_m``, ``rms_angle_error_rad``, ``rms_pointing_error_rad``,
  ``max_pointing_error_rad``: over the confirmed-on-target samples (before issue 11: over all
  confirmed samples).

Episodes are counted on the recorded samples: with a record decimation of d steps an episode
shorter than d PRIs may be missed (record every step when counting matters).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Protocol

import numpy as np

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import BIN_M

MODE_NAMES = ("acquisition", "tentative", "confirmed")
#: default range gate of the on-target test [m]: 2 range bins (see the module docstring)
RANGE_GATE_M = 2.0 * BIN_M
#: default angle gate of the on-target test [rad]: half the 3 dB beamwidth
ANGLE_GATE_RAD = 0.5 * float(MonopulseAntenna.param_map()["beamwidth"].default)

TRUTH = ("TargetGenerator.truth.range", "TargetGenerator.truth.az", "TargetGenerator.truth.el")
TRACK = ("Tracker.track.range", "Tracker.track.az", "Tracker.track.el")
MODE = "RadarManager.mode"
POINTING = ("Pedestal.az", "Pedestal.el")
#: the variables :func:`summarize` needs for every key (record at least these)
SUMMARY_VARIABLES = (MODE, *TRACK, *TRUTH, *POINTING)


class Record(Protocol):
    """What :func:`summarize` reads: rows ``data`` (column 0 time [s]) and ``column(ref)``."""

    @property
    def data(self) -> np.ndarray: ...

    def column(self, ref: str) -> np.ndarray | None: ...


class ArrayRecord:
    """A record built from arrays (the direct loop's recording): ``data`` and ``column`` as
    :class:`~.record.Recorder`."""

    def __init__(self, t: Sequence[float] | np.ndarray,
                 columns: Mapping[str, Sequence[float] | np.ndarray]) -> None:
        self.variables = list(columns)
        cols = [np.asarray(t, dtype=float)] + [np.asarray(columns[k], dtype=float)
                                               for k in self.variables]
        self._data = np.column_stack(cols) if cols[0].size else np.empty((0, len(cols)))
        self.n = len(self._data)

    @property
    def data(self) -> np.ndarray:
        return self._data

    def column(self, ref: str) -> np.ndarray | None:
        try:
            return self._data[:, 1 + self.variables.index(ref)]
        except ValueError:
            return None


def _los(az: np.ndarray, el: np.ndarray) -> np.ndarray:
    ce = np.cos(el)
    return np.stack([ce * np.sin(az), ce * np.cos(az), np.sin(el)], axis=-1)


def angle_between(az1, el1, az2, el2) -> np.ndarray:
    """Great-circle angle between two directions [rad] (robust for small angles)."""
    a, b = _los(np.asarray(az1), np.asarray(el1)), _los(np.asarray(az2), np.asarray(el2))
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))


def _rms(x: np.ndarray) -> float | None:
    return float(np.sqrt(np.mean(np.square(x)))) if x.size else None


def _runs(flag: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start and end (exclusive) sample indices of the maximal runs of True in ``flag``."""
    f = np.concatenate(([False], flag.astype(bool), [False])).astype(np.int8)
    d = np.diff(f)
    return np.flatnonzero(d == 1), np.flatnonzero(d == -1)


def on_target(rec: Record, range_gate_m: float = RANGE_GATE_M,
              angle_gate_rad: float = ANGLE_GATE_RAD) -> np.ndarray | None:
    """Per sample: the track within the range and angle gates of the truth (None when the
    record lacks a track or truth variable)."""
    cols = [rec.column(n) for n in (*TRACK, *TRUTH)]
    if any(c is None for c in cols):
        return None
    tr, taz, tel, gr, gaz, gel = cols
    ang = angle_between(taz, tel, gaz, gel)
    return (np.abs(tr - gr) <= range_gate_m) & (ang <= angle_gate_rad)


def summarize(rec: Record, range_gate_m: float = RANGE_GATE_M,
              angle_gate_rad: float = ANGLE_GATE_RAD) -> dict[str, Any]:
    """Time in each mode, on-target lock time, time held, drops, false confirmations, RMS
    errors on target and final mode (keys in the module docstring; gates [m], [rad])."""
    t = rec.data[:, 0]
    out: dict[str, Any] = {"samples": int(t.size), "end_time": float(t[-1]) if t.size else 0.0}
    mode = rec.column(MODE)
    if mode is None or not t.size:
        return out
    dt = np.diff(t, append=t[-1])
    out["time_in_mode"] = {n: float(dt[mode == i].sum()) for i, n in enumerate(MODE_NAMES)}
    conf = mode == 2
    out["first_confirmed_time"] = float(t[np.argmax(conf)]) if conf.any() else None
    out["final_mode"] = MODE_NAMES[int(mode[-1])] if 0 <= mode[-1] < 3 else int(mode[-1])
    inside = on_target(rec, range_gate_m, angle_gate_rad)
    out["range_gate_m"] = float(range_gate_m)
    out["angle_gate_rad"] = float(angle_gate_rad)
    if inside is not None:
        on, off = conf & inside, conf & ~inside
        out["lock_time"] = float(t[np.argmax(on)]) if on.any() else None
        out["time_on_target_s"] = float(dt[on].sum())
        span = out["end_time"] - out["lock_time"] if on.any() else 0.0
        out["held_fraction"] = out["time_on_target_s"] / span if span > 0.0 else None
        _, ends = _runs(on)
        out["drops"] = int(np.sum(ends < t.size))
        starts, _ = _runs(off)
        out["false_confirmations"] = int(starts.size)
        out["time_false_confirmed_s"] = float(dt[off].sum())
        out["first_false_confirmation_time"] = float(t[starts[0]]) if starts.size else None
    else:  # no truth recorded: the on-target figures cannot be computed
        on = conf
        out["lock_time"] = None
    col = rec.column
    tr, tt = col(TRACK[0]), col(TRUTH[0])
    if tr is not None and tt is not None:
        out["rms_range_error_m"] = _rms((tr - tt)[on])
    if all(col(n) is not None for n in (*TRACK[1:], *TRUTH[1:])):
        ang = angle_between(*(col(n)[on] for n in (*TRACK[1:], *TRUTH[1:])))
        out["rms_angle_error_rad"] = _rms(ang)
    if all(col(n) is not None for n in (*POINTING, *TRUTH[1:])):
        ang = angle_between(*(col(n)[on] for n in (*POINTING, *TRUTH[1:])))
        out["rms_pointing_error_rad"] = _rms(ang)
        out["max_pointing_error_rad"] = float(ang.max()) if ang.size else None
    for k, v in list(out.items()):
        if isinstance(v, float) and not math.isfinite(v):
            out[k] = None
    return out
