"""Readable results: the printed summary in engineering units (summary.json stays SI) and
the plot helpers (angle wrapping, the moving RMS drawn as a ±1σ band)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.orchestrator.plots import _moving_rms, _wrap_deg
from axir.orchestrator.report import format_summary, format_value


def test_values_in_engineering_units() -> None:
    assert format_value("max_pointing_error_rad", math.pi / 360) == "0.5 deg"
    assert format_value("rms_angle_error_rad", math.radians(0.0072)) == "0.0072 deg"
    assert format_value("rms_range_error_m", 4.04) == "4.04 m"
    assert format_value("lock_time", 0.037) == "0.037 s"
    assert format_value("snr_db", 13.0) == "13 dB"
    assert format_value("doppler_error_hz", 170.0) == "170 Hz"
    assert format_value("rms_range_error_m", None) == "n/a"
    assert format_value("final_mode", "confirmed") == "confirmed"


def test_summary_lines_no_radians() -> None:
    summary = {"scenario": "closed-loop", "seed": 1, "duration": 40.0, "complete": True,
               "status": "complete", "end_time": 40.0,
               "time_in_mode": {"acquisition": 0.02, "tentative": 0.017, "confirmed": 39.96},
               "lock_time": 0.037, "final_mode": "confirmed", "rms_range_error_m": 4.0,
               "rms_angle_error_rad": 1.2566e-4, "max_pointing_error_rad": 0.0099484,
               "steps": 358514, "wall_time_s": 107.0, "us_per_step": 298.5,
               "versions": {"python": "3.11"}, "fmus": {}}
    text = format_summary(summary)
    lines = text.splitlines()
    assert lines[0] == "closed-loop: seed 1, 40 s simulated, complete"
    assert "rad" not in text and "versions" not in text
    line = {ln.split("  ")[1].strip(): ln for ln in lines[1:]}
    assert line["max pointing error"].endswith(" 0.57 deg")  # 0.0099484 rad = 0.570°
    assert line["rms angle error"].endswith(" 0.0072 deg")
    assert line["time in mode"].endswith("confirmed 39.96 s")
    assert line["steps"].endswith("358514 in 107 s wall (298.5 µs per step)")


def test_interrupted_summary_says_how_far() -> None:
    text = format_summary({"scenario": "x", "seed": 2, "duration": 20.0, "complete": False,
                           "status": "interrupted", "signal": "SIGTERM", "end_time": 3.25})
    assert text.splitlines()[0] == "x: seed 2, 3.25 of 20 s simulated, interrupted (SIGTERM)"


def test_wrap_deg() -> None:
    np.testing.assert_allclose(_wrap_deg(np.array([0.0, 179.0, 181.0, -181.0, 360.0, 540.0])),
                               [0.0, 179.0, -179.0, 179.0, 0.0, 180.0])


def test_moving_rms_equals_direct_window() -> None:
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.01, 0.03, 400))
    x = rng.normal(0.0, 2.0, t.size)
    x[50:60] = np.nan  # not confirmed: left out
    got = _moving_rms(t, x, 0.5)
    for i in (5, 55, 70, 399):
        w = x[(t >= t[i] - 0.5) & (t <= t[i])]
        w = w[np.isfinite(w)]
        want = math.sqrt(np.mean(w ** 2)) if w.size > 1 else math.nan
        assert got[i] == pytest.approx(want, nan_ok=True)


def test_stepping_loop_printed_apart_from_start_up() -> None:
    summary = {"scenario": "closed-loop", "seed": 3, "duration": 3.0, "complete": True,
               "status": "complete", "steps": 26904, "wall_time_s": 5.0,
               "us_per_step": 185.8, "loop_us_per_step": 140.25, "startup_s": 1.227,
               "realtime_factor": 0.795}
    line = {ln.split("  ")[1].strip(): ln for ln in format_summary(summary).splitlines()[1:]}
    assert line["steps"].endswith("26904 in 5 s wall (185.8 µs per step)")
    assert "140.2 µs per step" in line["stepping loop"] and "1.227 s" in line["stepping loop"]
    assert "loop_us" not in format_summary(summary) and "startup" not in format_summary(summary)
