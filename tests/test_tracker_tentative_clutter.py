"""Issue 11 (session 24): ``Tracker.tentative_clutter_ratio`` — a side Doppler filter that holds
clutter is left out of the tentative angle readings' Σ over the filters
(models/tracker/tentative_cells.py ``clutter_free_filters``; docs/filters.md "The tentative Σ
without a clutter filter; tentative readings at the beam's edge"). The range reading keeps the
Σ over the 3 filters (SYSTEM.md).

Found on the envelope design's one false confirmation (42 km, −857.14 m/s, 5°, seed 1): in that
PRI schedule the third filter sits on the clutter line and held the down beam's clutter at
2.2 × the background, so every tentative elevation reading was −0.5° to −0.7° with the target
0.34° above the boresight, and the confirming PRI's tentative report was 1.35° off it.

The expected readings below are the linear law's ratio (u − d)/(u + d)/k_m of the beams as the
test builds them (the antenna's gains times an amplitude, plus the floors per filter), summed
over the filters that should be in the Σ: computed here, not by the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.loop import DirectLoop
from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import GATE_BIN, N_BEAMS, N_BINS, N_DOPPLER
from axir.models.tracker import Tracker
from axir.orchestrator.envelope import Cell, cell_parameters, seeded
from axir.orchestrator.metrics import ANGLE_GATE_RAD, angle_between

DEG = math.pi / 180.0
ANT = MonopulseAntenna()
AZ0, EL0 = 0.5, 0.1
AMP = 50.0  # peak amplitude of the target in the centre filter [1]
#: clutter per beam (u, r, d, l) in every bin of a side filter: the down beam holds twice the
#: others' (the ground below the beam), the pattern that biases the elevation reading
CLUTTER = (4.0, 4.0, 8.0, 4.0)


def _beams(theta_el: float, theta_lat: float, floor: float, clutter_filter: int | None,
           scale: float = 1.0) -> np.ndarray:
    """(4, 16, 3) beams: ``floor`` in every cell, the target (AMP × gains at (θ_el, θ_lat)
    [rad]) in bin 7 of the centre filter, and ``scale`` × CLUTTER added to every bin of
    ``clutter_filter``."""
    beams = np.full((N_BEAMS, N_BINS, N_DOPPLER), floor)
    beams[:, GATE_BIN - 1, 1] += AMP * ANT.gains(theta_lat, theta_el)
    if clutter_filter is not None:
        beams[:, :, clutter_filter] += scale * np.asarray(CLUTTER)[:, None]
    return beams


def tentative_outputs(beams: np.ndarray, n_pri: int = 20, **params) -> dict:
    """The outputs of a tentative tracker (boresight (AZ0, EL0), 3 readings to a track) after
    ``n_pri`` identical PRIs of ``beams``; a reading entered at the last one."""
    trk = Tracker(designation_az=AZ0, designation_el=EL0, track_init_n=3, **params)
    step = {"beam": beams, "ped.az": AZ0, "ped.el": EL0, "range.offset": 0.0,
            "gate.command": 20_000.0, "mode": 1, "alpha": 0.0, "beta": 0.0}
    for _ in range(n_pri):
        out = trk.step(1e-4, step)
    assert out["dev.el"] != 0.0  # a reading at this PRI
    return out


def _reading(beams: np.ndarray, **params) -> tuple[float, dict]:
    """dev.el [rad] after 20 identical tentative PRIs, and the last outputs."""
    out = tentative_outputs(beams, **params)
    return out["dev.el"], out


def _expected(beams: np.ndarray, filters: list[int]) -> float:
    """The linear law's elevation reading of bin 7 summed over ``filters``."""
    u, _, d, _ = beams[:, GATE_BIN - 1, filters].sum(axis=1)
    return (u - d) / (u + d) / ANT.slope


@pytest.mark.parametrize("clutter_filter", [0, 2])
@pytest.mark.parametrize("theta_el", [0.34 * DEG, -1.0 * DEG])
def test_a_side_filter_in_clutter_is_left_out(clutter_filter: int, theta_el: float) -> None:
    beams = _beams(theta_el, 0.2 * DEG, 1.0, clutter_filter)
    beams[:, GATE_BIN, 1] += 0.3 * AMP * ANT.gains(0.2 * DEG, theta_el)  # (range: off centre)
    kept = [f for f in range(N_DOPPLER) if f != clutter_filter]
    on, out_on = _reading(beams)
    off, out_off = _reading(beams, tentative_clutter_ratio=0.0)
    assert on == pytest.approx(_expected(beams, kept), rel=1e-9)
    assert off == pytest.approx(_expected(beams, [0, 1, 2]), rel=1e-9)  # SYSTEM.md's Σ
    # the range reading keeps the Σ over the 3 filters (SYSTEM.md), clutter included
    assert out_on["dev.range"] == out_off["dev.range"] > 0.0
    assert abs(off - on) > 0.02 * DEG  # the down beam's clutter moves the Σ's reading


def test_clutter_below_the_ratio_and_in_the_centre_filter_stays() -> None:
    weak = _beams(0.34 * DEG, 0.0, 1.0, 0, scale=0.1)  # background 1.5 × the others'
    assert _reading(weak)[0] == pytest.approx(_expected(weak, [0, 1, 2]), rel=1e-9)
    centre = _beams(0.34 * DEG, 0.0, 1.0, 1)  # a blind PRI: the target's filter holds it
    assert _reading(centre)[0] == pytest.approx(_expected(centre, [0, 1, 2]), rel=1e-9)
    both = _beams(0.34 * DEG, 0.0, 1.0, 0)
    both[:, :, 2] += np.asarray(CLUTTER)[:, None]
    assert _reading(both)[0] == pytest.approx(_expected(both, [1]), rel=1e-9)


def test_a_nan_background_keeps_the_sum() -> None:
    beams = _beams(0.34 * DEG, 0.0, 1.0, 2)
    beams[:, 0, 0] = np.nan  # one non-finite background cell: no filter is judged
    trk = Tracker(designation_az=AZ0, designation_el=EL0, track_init_n=3)
    out = trk.step(1e-4, {"beam": beams, "ped.az": AZ0, "ped.el": EL0, "range.offset": 0.0,
                          "gate.command": 20_000.0, "mode": 1, "alpha": 0.0, "beta": 0.0})
    assert all(math.isfinite(out[k]) for k in ("track.az", "track.el", "cmd.az", "cmd.el"))


@pytest.mark.parametrize("theta_el, theta_lat", [(0.8, 0.0), (-0.5, 1.2)])
def test_the_tentative_report_removes_the_noise_of_the_kept_filters(theta_el, theta_lat):
    """The known tentative direction (``tentative_dilution``) with a clutter filter left out:
    the pair's noise removed is that of the one kept side filter (floor 1 per beam: the mean
    background SUM of the two kept filters is 8, the pair's noise in the other one 2), so the
    report is where the same target over the same floor without the clutter puts it (the
    three filters, the noise of two removed); with the rule off the clutter moves it."""
    reports = []
    for clutter, ratio in ((None, 2.0), (2, 2.0), (2, 0.0)):
        _, out = _reading(_beams(theta_el * DEG, theta_lat * DEG, 1.0, clutter),
                          tentative_clutter_ratio=ratio)
        lat = ((out["track.az"] - AZ0 + math.pi) % (2 * math.pi) - math.pi) * math.cos(EL0)
        reports.append(np.array([out["track.el"] - EL0, lat]))
    quiet, cluttered, off = reports
    assert cluttered == pytest.approx(quiet, abs=3e-5)
    assert np.abs(off - quiet).max() > 0.05 * DEG


@pytest.mark.parametrize("ratio, on_target", [(2.0, True), (0.0, False)])
def test_the_design_cell_confirms_on_the_target(ratio: float, on_target: bool) -> None:
    """The traced design cell (10 m², seed 1), in the direct loop up to its confirmation: the
    first confirmed PRI's report is within the summary's angle gate of the truth with the rule,
    and 1.35° off without it."""
    cell = Cell(range_m=42000.0, speed=-857.14, el_deg=5.0, rcs=10.0, seed=1, duration=3.0)
    prm = cell_parameters(cell)
    prm.setdefault("Tracker", {})["tentative_clutter_ratio"] = ratio
    loop = DirectLoop.from_params(seeded(prm, cell.seed))
    while loop.t < 0.3:
        loop.step()
        if loop.out["RadarManager"]["mode"] == 2:
            break
    assert loop.out["RadarManager"]["mode"] == 2
    trk, tg = loop.out["Tracker"], loop.out["TargetGenerator"]
    err = float(angle_between(np.array(trk["track.az"]), np.array(trk["track.el"]),
                              np.array(tg["truth.az"]), np.array(tg["truth.el"])))
    assert (err <= ANGLE_GATE_RAD) is on_target
    assert on_target or err > 1.0 * DEG
