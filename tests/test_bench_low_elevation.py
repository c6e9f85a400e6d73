"""The low-elevation benchmark (benchmarks/bench_low_elevation.py, issue 11 point 2, session 20):
its sets are the documented grids, and an unknown set is refused with exit status 2."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import bench_low_elevation as bench


def test_the_sets_are_the_documented_grids():
    lowel, lowel2, stress = (bench.cells(n) for n in bench.SETS)
    assert len(lowel) == 144 and len(lowel2) == 192 and len(stress) == 36
    assert {c.el_deg for c in lowel2} == {0.5, 1.5, 2.5, 4.0}
    assert {c.range_m for c in lowel} == {6000.0, 10000.0, 14000.0}
    assert all(c.rcs == 1.0 and c.clutter for c in lowel + lowel2 + stress)
    # the turning targets: 24 of seed 3, and seeds 1-6 of the two closing 2.5° cells
    assert sum(c.seed == 3 for c in stress) == 24 + 2
    assert {c.g for c in stress} == {5.0, 7.0}
    assert len({c.key() for c in lowel + lowel2 + stress}) == 144 + 192 + 36 - 2  # 2 repeats


def test_an_unknown_set_is_refused(capsys):
    with pytest.raises(SystemExit) as e:
        bench.main(["--sets", "lowel,nope"])
    assert e.value.code == 2
    assert "unknown set 'nope'" in capsys.readouterr().err


def test_the_crossing_set_flies_through_the_notch():
    cells = bench.cells("crossing")
    assert "crossing" in bench.ALL_SETS and "crossing" not in bench.SETS  # not by default
    assert len(cells) == 4 * 5 * 3 * 2 and all(c.duration == 4.0 for c in cells)
    through = 0
    for c in cells:
        assert c.speed < -5.0  # outside the manager's clutter notch at the start
        # straight flight: the closest point (radial speed 0) at r0·|ṙ0|/|v|², and the
        # radial speed at t is (ṙ0·r0 + |v|²·t)/r(t)
        v2 = c.tangential ** 2 + c.speed ** 2
        t0 = c.range_m * -c.speed / v2
        through += t0 < c.duration
        r1 = (c.range_m ** 2 + 2.0 * c.range_m * c.speed * 1.0 + v2) ** 0.5
        assert -6.5 < (c.range_m * c.speed + v2 * 1.0) / r1 < -4.8  # the notch's edge, 1 s in
    assert through == 90


def test_the_long_crossing_set_crosses_the_notch_in_5_and_10_s():
    cells = bench.cells("longcross")
    assert "longcross" in bench.ALL_SETS and "longcross" not in bench.SETS  # not by default
    assert len(cells) == 3 * 2 * 3 * 2

    def rate(c, t: float) -> float:  # straight flight: (ṙ0·r0 + |v|²·t)/r(t)
        v2 = c.tangential ** 2 + c.speed ** 2
        return (c.range_m * c.speed + v2 * t) / (
            c.range_m ** 2 + 2.0 * c.range_m * c.speed * t + v2 * t * t) ** 0.5

    bands = set()
    for c in cells:
        assert -6.5 < rate(c, 1.0) < -4.8  # the notch's edge 1 s in
        assert rate(c, c.duration) > 7.5  # out of the band's exit (1.5 × 5 m/s) at the end
        # the time from −5 to +5 m/s (bisection on the monotonic radial speed)
        ts = []
        for target in (-5.0, 5.0):
            lo, hi = 0.0, c.duration
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if rate(c, mid) < target else (lo, mid)
            ts.append(lo)
        bands.add(round(ts[1] - ts[0]))
    assert bands == {5, 10}
