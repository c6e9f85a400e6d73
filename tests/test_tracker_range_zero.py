"""A target at the radar (range 0) must not stop the Tracker (session 11): the maneuver
statistic divided by the angular variance (ρ·σθ)², which is 0 there — a ZeroDivisionError
out of ``step`` (an FMU's fmi2DoStep error) when a target closing at 1500 m/s from 3 km
reached the antenna (found by a hostile-engagement sweep, docs/envelope.md "Session 11")."""

from __future__ import annotations

import math

from axir.models.tracker.maneuver import nis_cs


def test_nis_of_a_measurement_at_range_zero_is_infinite_not_an_exception() -> None:
    assert nis_cs((1.0, 2.0, 3.0), 1.0, 0.0, 1.0, 0.0, 0.0, 5.0, 1e-3, 2.0) == math.inf
    # elsewhere unchanged: the radial term alone at ρ > 0 (q_a = q_e = 0 along u_ρ)
    assert nis_cs((0.0, 3.0, 0.0), 1.0, 0.0, 1.0, 0.0, 10.0, 2.0, 1e-3, 1.5) == 9.0 / 4.0 / 1.5
    assert math.isnan(nis_cs((1.0, 0.0, 0.0), 1.0, 0.0, 1.0, 0.0, math.nan, 2.0, 1e-3, 1.0))


def test_an_engagement_through_the_radar_runs_to_its_end() -> None:
    """3 km closing at 1500 m/s: the target reaches the antenna at 2 s and recedes behind
    it; the closed loop runs its 3 s (the summary's figures are not judged: no radar tracks
    a target through itself)."""
    from axir.orchestrator.envelope import Cell, run_cell

    s = run_cell(Cell(range_m=3000.0, speed=-1500.0, el_deg=5.0, rcs=1.0, seed=1,
                      duration=3.0))
    assert s["steps"] > 25_000
    assert s["lock_time"] is not None and s["lock_time"] < 0.1
