"""Issue 11 (session 24): ``Tracker.tentative_edge_fraction`` — a tentative reading beyond the
beam's edge is read on the centre filter's cell across the other pair, as a confirmed one
(models/tracker/tentative_cells.py ``tentative_edge``; docs/filters.md "The tentative Σ without a
clutter filter; tentative readings at the beam's edge").

Found with designation errors of 2.5-3°: the tentative readings are Σ over the three Doppler
filters, so both beams of a pair carry two filters of noise, and a 1 m² target 2.8° off the
boresight at 10 km read +1.0° to +1.4° in every tentative reading; the confirming PRI reported
it 1.33° off (a false confirmation by the summary's angle gate).

The beams below are built from the antenna's gains with the noise entering as its mean power
(E|s + n|² = |s|² + σ²), the law the edge reading removes; the expected readings are the
Gaussian pattern's own (ε = tanh(k_m·θ)) and the linear law of the Σ, computed here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_tracker_tentative_clutter import EL0, tentative_outputs

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import GATE_BIN, N_BEAMS, N_BINS, N_DOPPLER
from axir.models.tracker.cells import _NOISE_POWER_RATIO

DEG = math.pi / 180.0
ANT = MonopulseAntenna()
K = ANT.slope
FLOOR = 0.2  # mean noise magnitude per beam [1] (a mean background SUM of 0.8)
AMP = 8.5  # peak amplitude of the target [1]: its stronger beam ≈ 24-27 dB above the noise


def _beams(theta_el: float, theta_lat: float) -> np.ndarray:
    """(4, 16, 3) beams: ``FLOOR`` everywhere, and in bin 7 of the centre filter the rms of the
    target (AMP × gains at (θ_el, θ_lat) [rad]) and the noise."""
    beams = np.full((N_BEAMS, N_BINS, N_DOPPLER), FLOOR)
    n2 = _NOISE_POWER_RATIO * FLOOR ** 2
    beams[:, GATE_BIN - 1, 1] = np.sqrt((AMP * ANT.gains(theta_lat, theta_el)) ** 2 + n2)
    return beams


def _run(beams: np.ndarray, **params) -> dict:
    """The outputs of a tentative tracker after 30 identical PRIs (its direction known)."""
    return tentative_outputs(beams, 30, **params)


def _sigma_reading(beams: np.ndarray) -> tuple[float, float]:
    """The linear law (el, lat) [rad] of bin 7 summed over the three filters (SYSTEM.md)."""
    u, r, d, lf = beams[:, GATE_BIN - 1, :].sum(axis=1)
    return (u - d) / (u + d) / K, (r - lf) / (r + lf) / K


@pytest.mark.parametrize("theta_el", [2.8 * DEG, -2.5 * DEG, 3.2 * DEG])
def test_an_axis_beyond_the_edge_reads_the_angle(theta_el: float) -> None:
    beams = _beams(theta_el, 0.3 * DEG)
    on = _run(beams)
    off = _run(beams, tentative_edge_fraction=0.0)
    sig_el, sig_lat = _sigma_reading(beams)
    assert off["dev.el"] == pytest.approx(sig_el, rel=1e-9)
    assert abs(math.atanh(K * sig_el) / K) < abs(theta_el) - 0.4 * DEG  # the Σ reads short
    assert on["dev.el"] == pytest.approx(math.tanh(K * theta_el) / K, rel=1e-6)
    # the other axis, inside the edge, keeps the Σ's reading
    assert on["dev.lat"] == pytest.approx(sig_lat, rel=1e-9)


def test_inside_the_edge_nothing_changes() -> None:
    beams = _beams(0.9 * DEG, -0.6 * DEG)
    on, off = _run(beams), _run(beams, tentative_edge_fraction=0.0)
    assert (on["dev.el"], on["dev.lat"]) == (off["dev.el"], off["dev.lat"])
    assert (on["track.az"], on["track.el"]) == (off["track.az"], off["track.el"])


@pytest.mark.parametrize("theta_el", [2.2 * DEG, -2.4 * DEG])
def test_the_report_is_the_target_and_not_scaled_by_the_dilution(theta_el: float) -> None:
    """The known tentative direction: the filter averages edge readings that hold no noise
    of the other filters, so the dilution's scaling (session 15) leaves that axis alone and
    the inverted report is the target's elevation; without the reading it falls short."""
    beams = _beams(theta_el, 0.0)
    on, off = _run(beams), _run(beams, tentative_edge_fraction=0.0)
    assert on["track.el"] - EL0 == pytest.approx(theta_el, abs=0.01 * DEG)
    assert abs(off["track.el"] - EL0) < abs(theta_el) - 0.05 * DEG
