"""Weak angle readings (issue 11, session 9): a reading's monopulse accuracy from its gate-cell
SNR (models/tracker/initiation.py ``reading_angle_variance``), and the track initiation
weighed by it (Tracker ``init_angle_sigma``, ``reading_pole``): a confirmed track is reported
once its readings make its direction known, also after the hand-over's re-centre.

Before (main at b25f57c) the 42 km, −142.86 m/s, 5°, 10 m², seed 1 plane cell was re-centred
at its first confirmed PRI on one weak reading (gate cell ≈ 2.5× the background) 1.29° off the
target: a false confirmation; and three 60 km cells (below the detectability criterion)
reported young tracks steered 1.26-1.55° off by weak readings."""

from __future__ import annotations

import math

import numpy as np
import pytest
from designation import MANAGER_S20

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import GATE_BIN, N_BEAMS, N_BINS, N_DOPPLER
from axir.models.tracker import Tracker
from axir.models.tracker.initiation import reading_angle_variance
from axir.orchestrator.envelope import Cell, run_cell

K_M = MonopulseAntenna().slope  # [1/rad]


@pytest.mark.parametrize(("snr", "rel"), [(10.0, 0.10), (30.0, 0.05), (100.0, 0.05)])
def test_angle_variance_matches_a_monte_carlo_monopulse_pair(snr, rel):
    # four beams of a boresight target (amplitude A each) in unit complex Gaussian noise,
    # magnitudes as the generator's; the angle ε/k_m of the up/down pair, and the ratio the
    # tracker forms: mean 4-beam SUM of the gate cell over that of noise-only cells
    rng = np.random.default_rng(7)
    m = 100_000
    a = math.sqrt(snr)

    def noise(shape):
        return (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)) / math.sqrt(2.0)

    u, r, d, lf = np.abs(a + noise((4, m)))
    var_emp = float(np.var((u - d) / (u + d) / K_M))
    ratio = float(np.mean(u + r + d + lf) / np.mean(np.abs(noise((4, m))).sum(axis=0)))
    assert reading_angle_variance(ratio, 1.0 / K_M) == pytest.approx(var_emp, rel=rel)


def test_angle_variance_errs_large_at_low_snr_and_is_zero_without_noise():
    # at SNR 2-4 per beam the first-order law overstates the spread (a weak reading is
    # trusted less, not more); no noise (ratio inf): no angle noise
    rng = np.random.default_rng(3)
    n = rng.standard_normal((4, 50_000)) + 1j * rng.standard_normal((4, 50_000))
    u, _, d, _ = np.abs(math.sqrt(3.0) + n / math.sqrt(2.0))
    var_emp = float(np.var((u - d) / (u + d) / K_M))
    ratio = 2.2  # ≈ the mean SUM ratio of SNR 3 per beam (measured as above: 2.1-2.3)
    assert reading_angle_variance(ratio, 1.0 / K_M) > var_emp
    assert reading_angle_variance(math.inf, 1.0 / K_M) == 0.0


_STEP = {"ped.az": 0.5, "ped.el": 0.1, "range.offset": 0.0, "gate.command": 20_000.0}


def _beams(up: float, down: float, side: float, background: float = 1.0) -> np.ndarray:
    b = np.full((N_BEAMS, N_BINS, N_DOPPLER), background)
    b[1, GATE_BIN - 1, :] = b[3, GATE_BIN - 1, :] = side  # right, left
    b[0, GATE_BIN - 1, :], b[2, GATE_BIN - 1, :] = up, down
    return b


def _el_reading(up: float, down: float) -> float:
    return (up - down) / (up + down) / K_M  # [rad] the linear law of the tracker


def _handover(scale: float, **kw) -> dict:
    """A tentative track on strong readings at boresight, then a first confirmed reading
    0.8° above with a gate SUM 2.5 × ``scale`` × the background: far outside the tentative
    track's gate (1 mrad readings), so the track is re-centred on it (fc11's rule)."""
    trk = Tracker(designation_az=0.5, designation_el=0.1, track_init_n=1, **kw)
    for _ in range(20):
        trk.step(1e-4, {**_STEP, "mode": 1, "beam": _beams(100.0, 100.0, 100.0)})
    return trk.step(1e-4, {**_STEP, "mode": 2,
                           "beam": _beams(3.6 * scale, 1.4 * scale, 2.5 * scale)})


@pytest.mark.parametrize(("scale", "keep"), [(1.0, 4.0), (0.9, 8.0)])
def test_a_track_re_centred_on_a_weak_reading_is_not_reported_on_it(scale, keep):
    # per-beam SNR ≈ 4 (σθ ≈ 0.45°): re-centred 0.8° above, but its direction now rests on
    # one weak reading: the report stays where the radar looks (the boresight) until the
    # confirmed readings have made it known (main: reported at once, 0.8° off the boresight).
    # The tentative track's direction was known: what decides is recentre_keep_factor k
    # (session 22) — this reading holds 1.6 % of J_req (< 1/4² of session 13), at 0.9 × the
    # SUM 1.2 % (< 1/8², the default since session 22)
    assert _beams(3.6, 1.4, 2.5)[:, GATE_BIN - 1, 1].sum() / 4.0 == pytest.approx(2.5)
    dev = _el_reading(3.6, 1.4)
    assert math.degrees(dev) == pytest.approx(0.8, abs=0.05)
    out = _handover(scale, recentre_keep_factor=keep)
    assert out["track.z"] > 20_000.0 * math.sin(0.1 + 0.9 * dev)  # re-centred on it
    assert not out["track.valid"]
    assert out["track.el"] == pytest.approx(0.1)


def test_a_known_direction_re_centred_on_a_reading_within_the_factor_is_reported():
    # session 22 (recentre_keep_factor 8 by default): the 1.6 % reading above is ≥ 1/64 of
    # J_req; the tentative track's direction was known, so the re-centred track reports its
    # (inverted) direction at once
    assert Tracker.defaults()["recentre_keep_factor"] == 8.0
    out = _handover(1.0, beam_background=0.0)  # the raw ratio (session 29's rule takes 30 %
    assert out["track.valid"]  # of the synthetic background off each elevation beam)
    eps = (3.6 - 1.4) / (3.6 + 1.4)  # the reading's ratio: reported atanh(ε)/k_m, 0.86°
    assert out["track.el"] - 0.1 == pytest.approx(math.atanh(eps) / K_M, rel=0.02)


def test_a_track_re_centred_on_a_strong_reading_is_reported_on_it():
    # the same 0.8° deviation with a gate SUM 100 × the background: accurate to ≈ 0.01°
    out = _handover(40.0)
    assert out["track.valid"]
    # reported with the pattern inverted on it (session 14, report_inverts_pattern):
    # atanh(ε)/k_m of the reading's ratio ε, 0.86°
    eps = (3.6 - 1.4) / (3.6 + 1.4)
    assert out["track.el"] - 0.1 == pytest.approx(math.atanh(eps) / K_M, rel=0.02)


def _pris_to_report(beam: np.ndarray, **kw) -> int:
    trk = Tracker(designation_az=0.5, designation_el=0.1, track_init_n=10, **kw)
    for k in range(1, 2000):
        if trk.step(1e-4, {**_STEP, "mode": 2, "beam": beam})["track.valid"]:
            return k
    return 10**9


def test_a_track_of_weak_readings_is_reported_once_its_direction_is_known():
    # strong readings: reported at track_init_n (10); weak ones (per-beam SNR ≈ 4, σθ ≈ 0.45°,
    # each PRI ≈ (1 − 0.9)/(1 + 0.9) of an independent reading): the track's direction is
    # known to 0.25° only after ≈ (0.45/0.25)²/0.053 ≈ 60 PRIs; before, the boresight
    assert _pris_to_report(_beams(100.0, 100.0, 100.0)) == 10
    weak = _pris_to_report(_beams(2.5, 2.5, 2.5))
    assert 40 <= weak <= 120
    assert _pris_to_report(_beams(2.5, 2.5, 2.5), init_angle_sigma=0.0) == 10
    # independent readings (pole 0) need 19× fewer
    assert _pris_to_report(_beams(2.5, 2.5, 2.5), reading_pole=0.0) == 10


@pytest.mark.slow
@pytest.mark.parametrize(("range_m", "speed", "seed"), [
    (42_000.0, -142.86, 1),  # b25f57c: 1 false confirmation (re-centred 1.29° off)
    (60_000.0, -428.57, 1),  # b25f57c: 1 (a young track walked 1.3-1.5° off)
    (60_000.0, 571.43, 1),  # b25f57c: 2
])
def test_plane_cells_that_confirmed_off_target_no_longer_do(range_m, speed, seed):
    cell = Cell(range_m=range_m, speed=speed, el_deg=5.0, rcs=10.0, seed=seed)
    assert run_cell(cell)["false_confirmations"] == 0  # the defaults
    # as traced, with session 20's manager (tests/designation.py MANAGER_S20); with session
    # 21's the first two cells are not confirmed at all in 3 s (docs/envelope.md)
    out = run_cell(cell, overrides={"RadarManager": MANAGER_S20})
    assert out["false_confirmations"] == 0
    assert out["lock_time"] is not None  # still confirmed on the target


def test_while_its_direction_is_unknown_a_track_reports_its_range_and_the_boresight():
    # weak readings 0.3° above the boresight: after 20 confirmed PRIs the track holds
    # track_init_n measurements but not the angle information: range and range rate are
    # the filter's (they do not depend on the direction's accuracy; a report frozen at the
    # hypothesis would fall behind a fast target), the angles the boresight's
    trk = Tracker(designation_az=0.5, designation_el=0.1, track_init_n=10)
    for _ in range(20):
        out = trk.step(1e-4, {**_STEP, "mode": 2, "beam": _beams(2.8, 2.2, 2.5)})
    assert out["track.n"] == 20 and not out["track.valid"]
    assert out["track.el"] == pytest.approx(0.1) and out["track.az"] == pytest.approx(0.5)
    assert out["track.range"] == pytest.approx(math.sqrt(
        out["track.x"] ** 2 + out["track.y"] ** 2 + out["track.z"] ** 2))
    assert math.atan2(out["track.z"], math.hypot(out["track.x"], out["track.y"])) > 0.1
