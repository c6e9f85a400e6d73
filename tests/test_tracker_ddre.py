"""DDRE range estimator (seed 001 eqs. 1-11)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.tracker.ddre import DDRE


def _best_window_centroid(p2: np.ndarray, s: int, dr: float, r0: float) -> float:
    """Independent brute force: window of s bins with max energy, |A|²-weighted centroid."""
    best, arg = -1.0, 0
    for r in range(p2.size - s + 1):
        e = p2[r:r + s].sum()
        if e > best:
            best, arg = e, r
    w = p2[arg:arg + s]
    ranges = r0 + dr * np.arange(arg, arg + s)
    return float((w * ranges).sum() / w.sum())


@pytest.mark.parametrize("seed", range(5))
def test_point_and_extended_target_centroid(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n, s, dr, r0 = 200, 8, 3.0, 1234.0
    a = np.zeros(n)
    start = int(rng.integers(10, 180))
    width = int(rng.integers(1, s + 1))  # point (1 bin) up to a target filling the window
    a[start:start + width] = rng.uniform(0.5, 2.0, width)
    d = DDRE(window=s, bin_size=dr, range_start=r0)
    out = d.update(a, 0.0)
    p2 = a**2
    expected = r0 + dr * float((p2 * np.arange(n)).sum() / p2.sum())
    assert out.range == pytest.approx(expected, abs=1e-9)
    assert out.range == pytest.approx(_best_window_centroid(p2, s, dr, r0), abs=1e-9)
    assert out.detected


def test_range_start_override_moves_the_window() -> None:
    a = np.zeros(30)
    a[5] = 1.0
    d = DDRE(window=2, bin_size=10.0, range_start=100.0)
    assert d.measure(a)[0] == pytest.approx(150.0)
    assert d.update(a, 0.0, range_start=1000.0).range == pytest.approx(1050.0)


def test_complex_profile_uses_magnitude_squared() -> None:
    a = np.zeros(50, complex)
    a[20], a[21] = 1 + 1j, 2j
    d = DDRE(window=4, bin_size=1.0)
    assert d.update(a, 0.0).range == pytest.approx((2 * 20 + 4 * 21) / 6)


def test_local_background_removes_constant_background() -> None:
    n, s, dr = 120, 6, 2.0
    a2 = np.zeros(n)
    a2[60:63] = [4.0, 9.0, 1.0]  # target |A|²
    target_centroid = dr * (4 * 60 + 9 * 61 + 1 * 62) / 14.0
    bg = 0.5  # constant background power
    a = np.sqrt(a2 + bg)
    local = DDRE(window=s, bin_size=dr, background="local").update(a, 0.0)
    assert local.range == pytest.approx(target_centroid, abs=1e-9)
    assert local.s0 == pytest.approx(14.0, abs=1e-9)
    # without subtraction the background biases the window centroid toward its centre
    none = DDRE(window=s, bin_size=dr, background="none").update(a, 0.0)
    assert abs(none.range - target_centroid) > 0.05
    glob = DDRE(window=s, bin_size=dr, background="global").update(a, 0.0)
    assert glob.range == pytest.approx(target_centroid, abs=1e-9)


def test_threshold_holds_previous_range() -> None:
    d = DDRE(window=4, bin_size=1.0, threshold=1.0, memory=1.0)
    a = np.zeros(40)
    a[10] = 2.0
    first = d.update(a, 0.0)
    assert first.detected and first.range == pytest.approx(10.0)
    weak = np.zeros(40)
    weak[30] = 0.5  # S0 = 0.25 < threshold
    second = d.update(weak, 0.1)
    assert not second.detected
    assert second.range == 10.0
    assert second.smoothed == pytest.approx(10.0)
    # nothing ever detected: no track (NaN), not a made-up range
    fresh = DDRE(window=4, threshold=1.0).update(weak, 0.0)
    assert math.isnan(fresh.range) and not fresh.detected


def test_exponential_smoothing_closed_form_on_step() -> None:
    dt, tau = 0.02, 0.5
    d = DDRE(window=1, bin_size=1.0, memory=tau, velocity_cut=0.0)
    a0, a1 = np.zeros(300), np.zeros(300)
    a0[100], a1[140] = 1.0, 1.0
    d.update(a0, 0.0)  # RS initialised at R0 = 100
    alpha = math.exp(-dt / tau)  # seed 001 eq. (10)
    for k in range(1, 80):
        out = d.update(a1, k * dt)
        # seed 001 eq. (9): RS = (1 − α) Σ_τ α^τ R(t − τ), with R = 140 for k samples, then 100
        closed = (1 - alpha) * sum(alpha**j * 140.0 for j in range(k)) + alpha**k * 100.0
        assert out.smoothed == pytest.approx(closed, abs=1e-9)


def test_velocity_cut_limits_rate() -> None:
    dt, vcut = 0.01, 200.0
    d = DDRE(window=1, bin_size=1.0, memory=0.1, velocity_cut=vcut)
    a0, a1 = np.zeros(3000), np.zeros(3000)
    a0[100], a1[2000] = 1.0, 1.0
    prev = d.update(a0, 0.0).smoothed
    steps = []
    for k in range(1, 1200):
        rs = d.update(a1, k * dt).smoothed
        steps.append(rs - prev)
        prev = rs
    steps = np.array(steps)
    assert np.all(np.abs(steps) <= vcut * dt + 1e-9)
    assert steps[:900] == pytest.approx(vcut * dt)  # saturated during the 1900 m jump
    assert prev == pytest.approx(2000.0, abs=1.0)  # eventually reaches the new range


def _ramp(d: DDRE, v: float, dt: float, n: int) -> list:
    outs = []
    for k in range(n):
        r_true = 500.0 + v * k * dt
        a = np.zeros(4000)
        a[round(r_true)] = 1.0  # 1 m bins, integer-valued ramp
        outs.append(d.update(a, k * dt))
    return outs


def test_prediction_extrapolate_and_delay() -> None:
    v, dt = 100.0, 0.01
    ext = _ramp(DDRE(window=1, bin_size=1.0, memory=0.5, t_pred=0.1), v, dt, 1000)
    assert ext[-1].rate == pytest.approx(v, rel=1e-3)
    assert ext[-1].predicted - ext[-1].smoothed == pytest.approx(v * 0.1, rel=1e-3)
    # steady lag of the exponential smoother on a ramp: v·αΔt/(1 − α)
    alpha = math.exp(-dt / 0.5)
    lag = v * alpha * dt / (1 - alpha)
    assert ext[-1].range - ext[-1].smoothed == pytest.approx(lag, rel=1e-3)
    dly = _ramp(DDRE(window=1, bin_size=1.0, memory=0.5, t_pred=0.1, prediction="delay"),
                v, dt, 300)
    for k in range(10, 300):
        assert dly[k].predicted == pytest.approx(dly[k - 10].smoothed, abs=1e-9)
    assert dly[3].predicted == dly[0].smoothed  # history shorter than t_pred


def test_time_must_not_go_back_and_params_validated() -> None:
    d = DDRE()
    a = np.ones(64)
    d.update(a, 1.0)
    with pytest.raises(ValueError):
        d.update(a, 0.5)
    with pytest.raises(ValueError, match="background"):
        DDRE(background="median")
    with pytest.raises(ValueError, match="memory"):
        DDRE(memory=0.0)


def test_reference_scenarios_configure() -> None:
    # seed 001 reference settings (aircraft 24 m window, ship 100 m window)
    air = DDRE(window=8, bin_size=3.0, memory=0.5, velocity_cut=200.0, t_pred=0.1)
    ship = DDRE(window=25, bin_size=4.0, memory=3.0, velocity_cut=3.0, t_pred=0.1)
    assert air.window * air.bin_size == 24.0 and ship.window * ship.bin_size == 100.0
