"""The printed summary of a run: the figures of ``summary.json`` (SI) in engineering units
(m, deg, s, dB, Hz), one figure per line, for a person reading a terminal.

Units follow the key's suffix (``_rad`` → deg, ``_m`` → m, ``_s`` / ``time`` → s, ``_db`` → dB,
``_hz`` → Hz), so figures added to :func:`~.metrics.summarize` later print sensibly too.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

#: keys of summary.json that are not figures of the run (bookkeeping; not printed)
_SKIP = {"scenario", "source", "seed", "duration", "complete", "status", "error", "signal",
         "algorithm", "versions", "fmus", "plots", "samples", "end_time", "steps",
         "wall_time_s", "us_per_step", "realtime_factor", "loop_us_per_step", "startup_s"}
#: key suffix → (printed unit, factor from SI, name suffix to drop)
_UNITS = (("_rad", "deg", 180.0 / math.pi), ("_deg", "deg", 1.0), ("_m", "m", 1.0),
          ("_db", "dB", 1.0), ("_hz", "Hz", 1.0), ("_s", "s", 1.0))


def _num(x: float) -> str:
    """4 significant digits, no exponent for everyday magnitudes."""
    if x == 0 or 1e-3 <= abs(x) < 1e6:
        return f"{x:.4g}" if abs(x) < 1e4 else f"{x:.0f}"
    return f"{x:.3e}"


def _label(key: str) -> tuple[str, str, float]:
    if key.startswith("time_"):  # time_in_mode: seconds per mode; time_on_target_s
        return key.removesuffix("_s").replace("_", " "), "s", 1.0
    if key.endswith("_time"):  # lock_time: the name stays whole
        return key.replace("_", " "), "s", 1.0
    for suffix, unit, factor in _UNITS:
        if key.endswith(suffix):
            return key[: -len(suffix)].replace("_", " "), unit, factor
    return key.replace("_", " "), "", 1.0


def format_value(key: str, value: Any) -> str:
    """``value`` of summary key ``key`` in engineering units (e.g. 0.0087 rad → '0.4956 deg')."""
    _, unit, factor = _label(key)
    if value is None:
        return "n/a"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    return f"{_num(value * factor)} {unit}".rstrip()


def format_summary(summary: Mapping[str, Any]) -> str:
    """The summary as aligned lines: a header line (scenario, seed, duration, outcome), the
    run's figures in engineering units, then steps and wall time."""
    outcome = summary.get("status") or ("complete" if summary.get("complete") else "partial")
    if summary.get("signal"):
        outcome += f" ({summary['signal']})"
    duration = float(summary.get("duration") or 0.0)
    end = summary.get("end_time")
    simulated = f"{_num(duration)} s" if end is None or summary.get("complete") else \
        f"{_num(float(end))} of {_num(duration)} s"
    lines = [f"{summary.get('scenario')}: seed {summary.get('seed')}, {simulated} simulated, "
             f"{outcome}"]
    rows: list[tuple[str, str]] = []
    for key, value in summary.items():
        if key in _SKIP:
            continue
        if isinstance(value, Mapping):
            parts = [f"{k} {format_value(key, v)}" for k, v in value.items()]
            rows.append((_label(key)[0], ", ".join(parts)))
        elif isinstance(value, (list, tuple)):
            rows.append((_label(key)[0], ", ".join(str(v) for v in value) or "none"))
        else:
            rows.append((_label(key)[0], format_value(key, value)))
    steps = summary.get("steps")
    if steps is not None:
        rows.append(("steps", f"{steps} in {_num(float(summary.get('wall_time_s') or 0))} s wall "
                              f"({_num(float(summary.get('us_per_step') or 0))} µs per step)"))
        if summary.get("loop_us_per_step"):
            rows.append(("stepping loop", f"{_num(float(summary['loop_us_per_step']))} µs per "
                         f"step (the rest: {_num(float(summary.get('startup_s') or 0))} s "
                         "loading, initializing and freeing the FMUs)"))
    if summary.get("realtime_factor"):
        rows.append(("real-time factor", f"{_num(float(summary['realtime_factor']))} "
                     "(simulated s per wall s of the stepping loop; ≥ 1: faster than the radar)"))
    width = max((len(k) for k, _ in rows), default=0)
    lines += [f"  {k:<{width}}  {v}" for k, v in rows]
    return "\n".join(lines)
