"""Zero false confirmations at the first confirmed sample (issue 11, fc11).

On main at a85474c these 42 km plane cells (5°, 10 m², seed 1) made a false confirmation on
their very first confirmed PRI: the Tracker had no track (or a 1-2 measurement one) when the
manager confirmed, and its report was the designation of t = 0 (270 m off the target) or the
single noisy measurement of a young tentative track (1.4° off in elevation). Now a Tracker
without an established track (fewer than ``track_init_n`` measurements) reports where the
radar looks: the gate centre of the manager's hypothesis and the antenna boresight
(docs/filters.md "No-track report and track initiation")."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from axir.models.radar.conventions import BIN_M, GATE_BIN, N_BEAMS, N_BINS, N_DOPPLER
from axir.models.tracker import Tracker
from axir.orchestrator.envelope import run_cell
from axir.orchestrator.envelope_run import ANCHOR


@pytest.mark.parametrize("speed", [
    357.14,  # a85474c: confirmed at 0.0761 s, the report was the designation, +273 m off
    428.57,  # a85474c: confirmed at 0.1013 s, a 2-measurement tentative track, 1.46° off
])
def test_42_km_cell_confirms_on_target_at_its_first_confirmed_sample(speed):
    out = run_cell(replace(ANCHOR, range_m=42_000.0, speed=speed, seed=1, duration=0.3))
    # confirmed within the run (since the Doppler peak search of branch acq11: 0.14-0.15 s)
    assert out["first_confirmed_time"] is not None and out["first_confirmed_time"] < 0.25
    assert out["false_confirmations"] == 0
    # the first confirmed sample is the lock (on target), and the track holds
    assert out["lock_time"] == out["first_confirmed_time"]
    assert out["drops"] == 0


def _tentative_step(trk: Tracker, gate: float, offset: float, az: float, el: float) -> dict:
    beams = np.ones((N_BEAMS, N_BINS, N_DOPPLER))  # flat noise: no usable measurement
    return trk.step(1e-4, {"beam": beams, "ped.az": az, "ped.el": el, "mode": 1,
                           "range.offset": offset, "gate.command": gate})


def test_tentative_without_a_track_reports_the_hypothesis_and_the_boresight():
    trk = Tracker(designation_az=0.5, designation_el=0.1, designation_range=40_000.0)
    gate, offset, az, el = 9_000.0, 30_000.0, 0.52, 0.09
    out = _tentative_step(trk, gate, offset, az, el)
    assert not out["track.valid"]
    # the true range of the gate centre (bin 7: 6 bins beyond the gate start), not 40 km
    assert out["track.range"] == pytest.approx(gate + offset + (GATE_BIN - 1) * BIN_M)
    assert out["track.az"] == pytest.approx(az)
    assert out["track.el"] == pytest.approx(el)
    assert out["track.range_rate"] == 0.0


@pytest.mark.parametrize("n_init", [1, 3, 6, 8])
def test_a_confirmed_track_is_reported_once_it_holds_track_init_n_measurements(n_init):
    # a strong target in gate bin 7, above boresight: every PRI is a measurement
    # (session 9's report; session 13's tentative_known_direction, on by default, reports
    # a tentative track whose direction is known: test_tracker_known_direction.py)
    trk = Tracker(designation_az=0.5, designation_el=0.1, track_init_n=n_init,
                  tentative_known_direction=False)
    beams = np.ones((N_BEAMS, N_BINS, N_DOPPLER))
    beams[:, GATE_BIN - 1, :] = 100.0
    beams[0, GATE_BIN - 1, :] = 110.0  # up beam stronger: target above boresight
    step = {"beam": beams, "ped.az": 0.5, "ped.el": 0.1, "range.offset": 0.0,
            "gate.command": 20_000.0}
    for _ in range(3):  # tentative: a track steers the antenna but is not reported
        out = trk.step(1e-4, {**step, "mode": 1})
        assert out["track.n"] >= 1 and not out["track.valid"]
        assert out["track.el"] == pytest.approx(0.1)  # the boresight
    valid = []
    for _ in range(n_init + 1):
        out = trk.step(1e-4, {**step, "mode": 2})
        valid.append(bool(out["track.valid"]))
        if not out["track.valid"]:
            assert out["track.el"] == pytest.approx(0.1)
    # the tentative track agrees with the confirmed cells (same target): it is kept
    assert out["track.n"] == 3 + n_init + 1
    # reported from the PRI its measurements (tentative ones included) reach track_init_n
    assert valid == [3 + k + 1 >= n_init for k in range(n_init + 1)]
    assert valid[-1]
    assert out["track.el"] > 0.1 and math.isfinite(out["track.range"])


def test_a_tentative_track_the_confirmed_cells_disagree_with_is_re_centred():
    # tentative: the target read ≈ 0.2° below boresight (as a clutter-biased Σ over the
    # filters); confirmed: as far above. The first confirmed measurement is far outside the
    # tentative track's innovation gate: the track is re-centred on it (its measurement count
    # goes on); the same reading in both modes leaves the track where it was
    step = {"ped.az": 0.5, "ped.el": 0.1, "range.offset": 0.0, "gate.command": 20_000.0}

    def beams(up: float, down: float) -> np.ndarray:
        b = np.ones((N_BEAMS, N_BINS, N_DOPPLER))
        b[:, GATE_BIN - 1, :] = 100.0
        b[0, GATE_BIN - 1, :], b[2, GATE_BIN - 1, :] = up, down
        return b

    def track(confirmed_up: float, confirmed_down: float) -> dict:
        trk = Tracker(designation_az=0.5, designation_el=0.1, track_init_n=1)
        for _ in range(20):
            trk.step(1e-4, {**step, "mode": 1, "beam": beams(90.0, 110.0)})
        return trk.step(1e-4, {**step, "mode": 2, "beam": beams(confirmed_up, confirmed_down)})

    moved, kept = track(110.0, 90.0), track(90.0, 110.0)
    assert moved["track.n"] == kept["track.n"] == 21
    assert kept["track.el"] < 0.1  # still below the boresight, as every reading
    assert moved["track.el"] > 0.1  # on the confirmed reading, above
