"""Confirmed tracking at 20-42 km, 5° (issue 11, round 4): the physical bound on a confirmed
track's range rate, the Doppler centre after missed dwells, and whole engagements that
dropped or made a false confirmation on main before round 4 (docs/filters.md)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from axir.models.loop import DirectLoop
from axir.orchestrator.envelope import cell_parameters, seeded
from axir.orchestrator.envelope_run import ANCHOR


def _run(range_km: float, speed: float, seed: int, duration: float
         ) -> dict[str, np.ndarray]:
    """A plane cell at 5° in the direct loop; mode, track range rate and range error per PRI."""
    cell = replace(ANCHOR, range_m=1000.0 * range_km, speed=speed, seed=seed,
                   duration=duration)
    loop = DirectLoop.from_params(seeded(cell_parameters(cell), seed))
    rows = []
    while loop.t < duration:
        loop.step()
        tr, m = loop.out["Tracker"], loop.out["RadarManager"]
        rows.append((m["mode"], tr["track.range_rate"],
                     tr["track.range"] - loop.out["TargetGenerator"]["truth.range"]))
    a = np.array(rows, dtype=float)
    return {"mode": a[:, 0], "rate": a[:, 1], "err": a[:, 2]}


def test_a_confirmed_track_never_moves_faster_than_max_speed():
    # 42 km, receding 1000 m/s, seed 1: the track is confirmed one PRI after a reset (n = 1);
    # on main its range rate read 1.06e6 m/s three PRIs later, the track range jumped 250 m
    # and the manager dropped it as implausible (a false confirmation 246 m off)
    max_speed = cell_parameters(replace(ANCHOR))["Tracker"].get("max_speed", 1500.0)
    r = _run(42.0, 1000.0, 1, 0.12)
    conf = r["mode"] == 2
    assert conf.any()
    assert np.max(np.abs(r["rate"][conf])) <= max_speed + 1e-6
    # and it is not dropped in the 40 ms after the confirmation
    first = int(np.argmax(conf))
    assert conf[first:].all()
    assert np.max(np.abs(r["err"][conf])) < 150.0
