"""Summary figures of a recorded run: lock time, time per mode, RMS range/angle errors,
pointing error and final mode (pure numpy over a :class:`~.record.Recorder`'s data)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .record import Recorder

MODE_NAMES = ("acquisition", "tentative", "confirmed")


def _los(az: np.ndarray, el: np.ndarray) -> np.ndarray:
    ce = np.cos(el)
    return np.stack([ce * np.sin(az), ce * np.cos(az), np.sin(el)], axis=-1)


def angle_between(az1, el1, az2, el2) -> np.ndarray:
    """Great-circle angle between two directions [rad] (robust for small angles)."""
    a, b = _los(np.asarray(az1), np.asarray(el1)), _los(np.asarray(az2), np.asarray(el2))
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))


def _rms(x: np.ndarray) -> float | None:
    return float(np.sqrt(np.mean(np.square(x)))) if x.size else None


def summarize(rec: Recorder) -> dict[str, Any]:
    """Lock time, time in each mode, RMS errors in confirmed mode and final mode."""
    t = rec.data[:, 0]
    out: dict[str, Any] = {"samples": int(rec.n), "end_time": float(t[-1]) if t.size else 0.0}
    mode = rec.column("RadarManager.mode")
    if mode is None or not t.size:
        return out
    dt = np.diff(t, append=t[-1])
    out["time_in_mode"] = {n: float(dt[mode == i].sum()) for i, n in enumerate(MODE_NAMES)}
    conf = mode == 2
    out["lock_time"] = float(t[np.argmax(conf)]) if conf.any() else None
    out["final_mode"] = MODE_NAMES[int(mode[-1])] if 0 <= mode[-1] < 3 else int(mode[-1])
    col = rec.column
    tr, tt = col("Tracker.track.range"), col("TargetGenerator.truth.range")
    if tr is not None and tt is not None:
        out["rms_range_error_m"] = _rms((tr - tt)[conf])
    names = ("Tracker.track.az", "Tracker.track.el", "TargetGenerator.truth.az",
             "TargetGenerator.truth.el")
    if all(col(n) is not None for n in names):
        ang = angle_between(*(col(n)[conf] for n in names))
        out["rms_angle_error_rad"] = _rms(ang)
    names = ("Pedestal.az", "Pedestal.el", "TargetGenerator.truth.az", "TargetGenerator.truth.el")
    if all(col(n) is not None for n in names):
        ang = angle_between(*(col(n)[conf] for n in names))
        out["rms_pointing_error_rad"] = _rms(ang)
        out["max_pointing_error_rad"] = float(ang.max()) if ang.size else None
    for k, v in list(out.items()):
        if isinstance(v, float) and not math.isfinite(v):
            out[k] = None
    return out
