"""Designation errors in the direct loop (issue 11, sessions 12-14): an envelope cell whose
designation (and the pedestal's start) is moved off the target, and the check that two loops
differing only in how the Tracker reports differ only in the reported outputs.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from axir.models.loop import DirectLoop
from axir.models.tracker import Tracker
from axir.orchestrator.envelope import Cell, cell_parameters

DEG = math.pi / 180.0
#: the Tracker of sessions 16-18 (seed 000's evolutive velocity gain, no range rate from the
#: manager's Doppler: ``Tracker.SEED000``): the traced defects of those sessions as traced
SESSION18 = Tracker.SEED000
#: the RadarManager before session 21's clutter rules (the residue share's thresholds, the
#: fast attack of the acquisition level): the cells traced before them, as traced (the rules
#: change a cell's tentative history; the defaults' outcomes are in docs/envelope.md)
MANAGER_S20 = {"residue_share_looks": False, "noise_attack_ratio": 0.0}
#: the Tracker's hand-over before session 22 (``recentre_keep_factor`` 8 since): a known
#: direction kept only on a reading of ≥ 1/16 of J_req — the cells traced before, as traced
TRACKER_S21 = {"recentre_keep_factor": 4.0}
#: the Tracker's tentative cells before session 24: SYSTEM.md's Σ over the 3 filters whatever
#: they hold, and no edge reading in tentative — the cells traced before, as traced
TRACKER_S23 = {"tentative_clutter_ratio": 0.0, "tentative_edge_fraction": 0.0}
#: the confirmed Doppler loop and miss limit before session 25: each dither pair alone and
#: each sign clear, the search after misses away from the centre first, a track dropped after
#: 5 missed dwells —
#: the cells traced before, as traced
MANAGER_S24 = {"doppler_disc_pairs": 1, "doppler_disc_together": False,
               "doppler_search_from_centre": False, "miss_limit": 5}
#: the Tracker's lost track before session 25: its velocity extrapolated however young
TRACKER_S24 = {"reacquire_velocity_check": False}
#: the confirmed readings before session 29: the raw beams' ratios (``beam_background`` 0.3
#: since, which also keeps several of the cells traced before on the target) — the cells
#: traced before, as traced
TRACKER_S28 = {"beam_background": 0.0}


def designation_params(cell: Cell, d_az_deg: float, d_el_deg: float,
                       manager: dict[str, Any] | None = None,
                       **tracker: object) -> dict[str, dict[str, Any]]:
    """``cell``'s unit parameters (unseeded) with the designation and the pedestal's start
    moved by (``d_az_deg``, ``d_el_deg``) [deg] on top of the envelope's default error, the
    RadarManager parameters ``manager`` and the Tracker parameters ``tracker``."""
    p = cell_parameters(cell)
    p["RadarManager"].update(manager or {})
    p["Tracker"]["designation_az"] += d_az_deg * DEG
    p["Tracker"]["designation_el"] += d_el_deg * DEG
    p["Pedestal"]["az0"] = p["Tracker"]["designation_az"]
    p["Pedestal"]["el0"] = p["Tracker"]["designation_el"]
    p["Tracker"].update(tracker)
    return p


def steps_with_different_reports(a: DirectLoop, b: DirectLoop, steps: int,
                                 reports: tuple[str, ...] = ("track.az", "track.el"),
                                 each_step: Callable[[], None] | None = None) -> int:
    """Step both loops ``steps`` times (calling ``each_step`` after each); assert that every
    output of every unit other than the Tracker's ``reports`` is equal (NaN equal to NaN) at
    every step; return the number of (step, report) pairs that differed (two NaN: equal)."""
    changed = 0
    for _ in range(steps):
        a.step()
        b.step()
        if each_step is not None:
            each_step()
        for unit, out in a.out.items():
            for key, v in out.items():
                w = b.out[unit][key]
                if unit == "Tracker" and key in reports:
                    changed += v != w and not (v != v and w != w)
                else:
                    x, y = np.asarray(v), np.asarray(w)
                    assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), (unit, key)
    return changed


def run_on_off(cell: Cell, d_az_deg: float, d_el_deg: float, option: str,
               values: tuple[Any, Any] = (True, False),
               manager: dict[str, Any] | None = None, **tracker: Any
               ) -> tuple[dict[str, Any], dict[str, Any]]:
    """``cell`` run (:func:`~axir.orchestrator.envelope.run_cell`) with the designation moved
    as in :func:`designation_params`, the Tracker's ``option`` at ``values[0]`` (default
    True), then at ``values[1]`` (False), and the Tracker parameters ``tracker``: the two
    summaries."""
    import axir.orchestrator.envelope as env

    orig = env.cell_parameters
    out = []
    try:
        for on in values:
            env.cell_parameters = lambda c, on=on: designation_params(
                c, d_az_deg, d_el_deg, manager, **{**tracker, option: on})
            out.append(env.run_cell(cell))
    finally:
        env.cell_parameters = orig
    return out[0], out[1]


def run_with_params(cell: Cell, unit: str, **params: Any) -> dict[str, Any]:
    """``cell`` run (:func:`~axir.orchestrator.envelope.run_cell`) with the ``unit``'s
    parameters ``params`` over the cell's own: its summary."""
    from axir.orchestrator.envelope import run_cell

    return run_cell(cell, overrides={unit: params})


def run_with_tracker(cell: Cell, manager: dict[str, Any] | None = None,
                     **tracker: Any) -> dict[str, Any]:
    """``cell`` run (:func:`~axir.orchestrator.envelope.run_cell`) with the Tracker
    parameters ``tracker`` and the RadarManager parameters ``manager`` over the cell's own:
    its summary."""
    from axir.orchestrator.envelope import run_cell

    return run_cell(cell, overrides={"Tracker": tracker, "RadarManager": manager or {}})
