"""Truthful summaries (issue 11 point 6): orchestrator/metrics.py ``summarize`` on synthetic
records — a false track confirmed off the target, a drop, an on-target lock. The expected
values follow from the synthetic scene (times, gates), not from the code under test."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.orchestrator.metrics import ANGLE_GATE_RAD, RANGE_GATE_M, ArrayRecord, summarize

DT = 0.01  # [s] sample spacing of the synthetic records
R_TRUE, AZ_TRUE, EL_TRUE = 20_000.0, 1.0, 0.1


def scene(n: int, mode: np.ndarray, track_range: np.ndarray,
          track_az: np.ndarray | None = None) -> ArrayRecord:
    """A record of ``n`` samples: a fixed target, the given mode and track range/azimuth, the
    track elevation and the pedestal on the truth."""
    t = np.arange(n) * DT
    full = np.full(n, 1.0)
    return ArrayRecord(t, {
        "RadarManager.mode": mode,
        "Tracker.track.range": track_range,
        "Tracker.track.az": AZ_TRUE * full if track_az is None else track_az,
        "Tracker.track.el": EL_TRUE * full,
        "TargetGenerator.truth.range": R_TRUE * full,
        "TargetGenerator.truth.az": AZ_TRUE * full,
        "TargetGenerator.truth.el": EL_TRUE * full,
        "Pedestal.az": AZ_TRUE * full,
        "Pedestal.el": EL_TRUE * full,
    })


def test_default_gates_are_two_bins_and_half_the_beamwidth():
    assert pytest.approx(150.0) == RANGE_GATE_M
    assert pytest.approx(math.radians(1.25)) == ANGLE_GATE_RAD


def test_false_track_then_on_target_lock():
    """Confirmed 40 km away from 0.5 s to 1.0 s (a false track), acquisition, then confirmed
    on the target (range error 5 m) from 2.0 s to the end at 3.99 s."""
    n = 400
    mode = np.zeros(n)
    rng = np.full(n, R_TRUE + 5.0)
    mode[50:100] = 2
    rng[50:100] = R_TRUE + 40_000.0
    mode[200:] = 2
    s = summarize(scene(n, mode, rng))
    assert s["first_confirmed_time"] == pytest.approx(0.5)
    assert s["lock_time"] == pytest.approx(2.0)  # the first ON-TARGET confirmation
    assert s["false_confirmations"] == 1
    assert s["first_false_confirmation_time"] == pytest.approx(0.5)
    assert s["time_false_confirmed_s"] == pytest.approx(0.5)
    assert s["drops"] == 0
    assert s["rms_range_error_m"] == pytest.approx(5.0)  # the false track is not in it
    assert s["held_fraction"] == pytest.approx(1.0)


def test_drop_is_counted_and_held_fraction_falls():
    """On target 1.0-2.0 s, back to acquisition 2.0-2.5 s, on target again 2.5 s to the end."""
    n = 400
    mode = np.zeros(n)
    mode[100:200] = 2
    mode[250:] = 2
    s = summarize(scene(n, mode, np.full(n, R_TRUE)))
    assert s["lock_time"] == pytest.approx(1.0)
    assert s["drops"] == 1
    assert s["false_confirmations"] == 0
    # on target 1.0 s + 1.5 s (last sample has no duration) over 3.0 s since the lock
    assert s["held_fraction"] == pytest.approx((1.0 + 1.49) / 2.99)


def test_track_walking_off_in_angle_is_a_drop_and_a_false_confirmation():
    """Confirmed throughout from 0.1 s; the track azimuth leaves the truth by 3° at 2.0 s
    (beyond half the 2.5° beamwidth at any elevation below 60°): a drop and a false track."""
    n = 300
    mode = np.zeros(n)
    mode[10:] = 2
    az = np.full(n, AZ_TRUE)
    az[200:] += math.radians(3.0)
    s = summarize(scene(n, mode, np.full(n, R_TRUE), az))
    assert s["lock_time"] == pytest.approx(0.1)
    assert s["drops"] == 1
    assert s["false_confirmations"] == 1
    assert s["first_false_confirmation_time"] == pytest.approx(2.0)


def test_range_gate_is_a_parameter():
    """A 200 m track error: off target with the 150 m default gate, on target with 300 m."""
    n = 100
    mode = np.full(n, 2.0)
    rec = scene(n, mode, np.full(n, R_TRUE + 200.0))
    assert summarize(rec)["lock_time"] is None
    assert summarize(rec)["false_confirmations"] == 1
    s = summarize(rec, range_gate_m=300.0)
    assert s["lock_time"] == pytest.approx(0.0)
    assert s["false_confirmations"] == 0


def test_never_confirmed():
    n = 50
    s = summarize(scene(n, np.zeros(n), np.full(n, R_TRUE)))
    assert s["lock_time"] is None and s["first_confirmed_time"] is None
    assert s["drops"] == 0 and s["false_confirmations"] == 0
    assert s["held_fraction"] is None and s["rms_range_error_m"] is None
