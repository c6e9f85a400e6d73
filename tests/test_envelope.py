"""The envelope benchmark's quick subset (issue 11 point 5; orchestrator/envelope.py,
orchestrator/envelope_run.py): three short cells in the direct loop — a filter-centred
detectable target, an undetectable one (60 km, 0.1 m²) and target-free clutter at 0.5° — the
per-cell CSV cache, the cell geometry and the detectability criterion."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.radar.trajectory import trajectory_from_spec
from axir.models.target_generator import TargetGenerator
from axir.orchestrator.envelope import (
    Cell,
    _filter_output_powers,
    albersheim_snr_db,
    clutter_loss_db,
    detectable,
    detection_snr_db,
    required_snr_db,
    trajectory_spec,
)
from axir.orchestrator.envelope_run import design, read_rows, run_design


def test_cell_geometry_is_range_speed_elevation():
    c = Cell(range_m=42_000.0, speed=-700.0, el_deg=3.0, rcs=1.0)
    tr = trajectory_from_spec(trajectory_spec(c))
    p, v, _ = tr.state(0.0)
    r = float(np.linalg.norm(p))
    assert r == pytest.approx(42_000.0)
    assert math.degrees(math.asin(p[2] / r)) == pytest.approx(3.0)
    assert math.degrees(math.atan2(p[0], p[1])) == pytest.approx(30.0)
    assert float(p @ v) / r == pytest.approx(-700.0)  # range rate
    p2, _, _ = tr.state(2.0)
    assert float(np.linalg.norm(p2)) == pytest.approx(42_000.0 - 1400.0)  # purely radial


def test_maneuver_cell_turns_at_the_load_factor():
    c = Cell(range_m=10_000.0, speed=-50.0, el_deg=5.0, rcs=1.0, g=7.0, tangential=250.0,
             maneuver_onset=1.0)
    tr = trajectory_from_spec(trajectory_spec(c))
    _, _, a0 = tr.state(0.5)
    _, _, a1 = tr.state(2.0)
    assert float(np.linalg.norm(a0)) == pytest.approx(0.0, abs=1e-9)
    assert float(np.linalg.norm(a1)) == pytest.approx(7.0 * 9.80665, rel=1e-6)


def test_albersheim_single_look():
    # Albersheim (1981) single look, Pd 0.9, Pfa 1e-6: 13.1 dB (Richards, Fundamentals of
    # Radar Signal Processing, table of Albersheim's equation)
    assert albersheim_snr_db(1e-6, 0.9) == pytest.approx(13.1, abs=0.15)


def test_detectability_follows_the_radar_equation():
    """20 dB at 10 km for 1 m² (TargetGenerator defaults) + 12.8 dB filter gain: 1 m² is
    detectable at 30 km (13.7 dB ≥ 12.5 dB) and not at 34 km (−40·log10(3.4) = −21.3 dB)."""
    assert detection_snr_db(Cell(10_000.0, 0.0, 5.0, 1.0)) == pytest.approx(
        20.0 + 10 * math.log10(1.9 / 0.1), abs=1e-9)
    # at a radial speed folded mid-band on every PRI (clutter loss < 0.5 dB at 5°)
    v = -53.15
    assert detectable(Cell(30_000.0, v, 5.0, 1.0))
    assert not detectable(Cell(34_000.0, v, 5.0, 1.0))
    assert not detectable(Cell(10_000.0, v, 5.0, 0.0))  # no target
    # a receding target is judged at its range after 1 s (1 m² limit: 32.2 km)
    assert detectable(Cell(31_500.0, v, 5.0, 1.0))
    assert not detectable(Cell(31_500.0, 1000.0, 5.0, 1.0))


def test_filter_output_powers_are_the_analytic_ones():
    """One-pole filter |H|² = (1 − ρ)²/|1 − ρe^{j2π(ν_t − ν)}|²: white-noise power gain
    (1 − ρ)/(1 + ρ), lag-1 autocorrelation ρ·cos 2πν_t of it; behind the two-pulse canceller
    (power gain 1 − cos 2πν) the noise is (1 − ρ)/(1 + ρ)·(1 − ρ cos 2πν_t) and a target at
    ν_t gains 1 − cos 2πν_t."""
    rho = TargetGenerator.defaults()["pole"]
    pri = 1e-4
    s, n, c = _filter_output_powers(0.3, pri, 0.0, 0)
    assert (s, c) == (1.0, 0.0)
    assert n == pytest.approx((1 - rho) / (1 + rho), rel=1e-6)
    for nu in (0.5, 0.3, 0.1):
        s, n, c = _filter_output_powers(nu, pri, 0.0, 1)
        assert s == pytest.approx(1 - math.cos(2 * math.pi * nu), rel=1e-9)
        assert n == pytest.approx((1 - rho) / (1 + rho) * (1 - rho * math.cos(2 * math.pi * nu)),
                                  rel=1e-6)
    # AR(1) clutter of power P, no canceller, filter at 0 Hz: P·Σ_k r_f[k]·ρc^|k| with the
    # filter's autocorrelation r_f[k] = (1 − ρ)/(1 + ρ)·ρ^|k|: P·(1 − ρ)/(1 + ρ)·(1 + ρρc)/(1 − ρρc)
    rho_c = math.exp(-2 * math.pi * TargetGenerator.defaults()["clutter_spread"] * pri)
    _, _, c = _filter_output_powers(0.0, pri, 2.0, 0)
    assert c == pytest.approx(2.0 * (1 - rho) / (1 + rho) * (1 + rho * rho_c) / (1 - rho * rho_c),
                              rel=1e-3)


def test_clutter_floor_enters_detectability_in_main_beam_clutter():
    # 0 Hz on every PRI at 5°: the sidelobe clutter (0 dB per pulse) fills the filter
    assert clutter_loss_db(Cell(10_000.0, 0.0, 5.0, 10.0)) > 10.0
    # inside the manager's clutter notch: blind by design, whatever the SNR
    assert not detectable(Cell(2_000.0, 0.0, 5.0, 10.0))
    assert not detectable(Cell(2_000.0, 4.0, 40.0, 10.0))
    assert detectable(Cell(2_000.0, 20.0, 40.0, 10.0))
    # mid-band at 80°: the clutter enters only through the −30 dB sidelobes (< 0.5 dB)
    assert clutter_loss_db(Cell(10_000.0, -53.15, 80.0, 10.0)) < 0.5
    # in main-beam clutter (1°) the canceller's residue costs several dB at every speed
    assert all(clutter_loss_db(Cell(20_000.0, v, 1.0, 10.0)) > 3.0
               for v in (-700.0, -300.0, -53.15, 400.0))
    # the 42 km / 1° / −200 m/s, 10 m² target: above the thermal criterion, below
    # the clutter-plus-noise one; at 10 km it is detectable
    far = Cell(42_000.0, -200.0, 1.0, 10.0)
    assert detection_snr_db(far) >= required_snr_db()
    assert not detectable(far)
    assert detectable(Cell(10_000.0, -200.0, 1.0, 10.0))


def test_quick_envelope_cells_and_cache(tmp_path):
    csv_path = tmp_path / "env.csv"
    rows = run_design(design(quick=True), csv_path, workers=1)
    assert len(rows) == 3
    near, far, free = rows
    # a filter-centred target at 10 km, 10 m²: on target within 1 s, held, RMS ≤ 10 m
    assert near["detectable"] == "True"
    assert near["lock_time"] != "" and float(near["lock_time"]) < 1.0
    assert int(near["drops"]) == 0 and int(near["false_confirmations"]) == 0
    assert float(near["held_fraction"]) >= 0.99
    assert float(near["rms_range_error_m"]) <= 10.0
    # 60 km, 0.1 m²: not detectable, never confirmed on target
    assert far["detectable"] == "False" and far["lock_time"] == ""
    # no target: no on-target lock can exist
    assert free["detectable"] == "False" and free["lock_time"] == ""
    # the cache: a second run computes nothing and returns the same rows
    calls = []
    again = run_design(design(quick=True), csv_path, workers=1,
                       progress=lambda *a: calls.append(a))
    assert calls == [] and again == rows
    assert len(read_rows(csv_path)) == 3
