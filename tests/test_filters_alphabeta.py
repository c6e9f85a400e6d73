"""α-β axis filter (seed 000 DSP form): least-squares evolutive phase, steady gains per gain,
n_max cap, exact constant velocity, covariance, innovation factor (three axes as the Tracker
runs them: tests/three_axes.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from three_axes import ThreeAxes

from axir.models.filters.alphabeta import AlphaBetaAxis
from axir.models.filters.base import FilterConfig
from axir.models.filters.gains import evolutive_gains, prior_gains, stable_gains


def test_evolutive_filter_equals_polyfit() -> None:
    rng = np.random.default_rng(1)
    T = 0.1
    t = np.arange(50) * T
    z = np.stack([50 + 3 * t, -20 + 0.5 * t, 7 - 2 * t], axis=1) + rng.normal(0, 1.0, (50, 3))
    ab = ThreeAxes()
    ab.update(tuple(z[0]), T)
    assert ab.x == pytest.approx(list(z[0]), abs=1e-12)  # n = 1: position = measurement
    for n in range(2, 51):
        ab.update(tuple(z[n - 1]), T)
        assert ab.n == n
        for axis in range(3):
            slope, icpt = np.polyfit(t[:n], z[:n, axis], 1)
            assert ab.x[axis] == pytest.approx(icpt + slope * t[n - 1], abs=1e-9)
            assert ab.v[axis] == pytest.approx(slope, abs=1e-9)


def test_steady_gains_take_over_per_gain() -> None:
    ab = ThreeAxes()
    a_ss, b_ss = 0.3, 0.05
    ab.update((0.0, 0.0, 0.0), 1.0, a_ss, b_ss)
    for n in range(2, 40):
        ab.update((1.0, 2.0, 3.0), 1.0, a_ss, b_ss)
        a_n, b_n = 2 * (2 * n - 1) / (n * (n + 1)), 6 / (n * (n + 1))
        assert ab.alpha == max(a_n, a_ss)
        assert ab.beta == max(b_n, b_ss)
    # unstable or missing steady gains are ignored: evolutive only
    ab2 = ThreeAxes()
    for _ in range(1, 30):
        ab2.update((1.0, 2.0, 3.0), 1.0, 1.5, 2.0)  # β > 4 − 2α: unstable pair
    assert ab2.alpha == pytest.approx(2 * (2 * 29 - 1) / (29 * 30))
    assert not stable_gains(1.5, 2.0) and stable_gains(0.5, 0.1) and not stable_gains(0.0, 0.1)


def test_n_max_caps_evolutive_index() -> None:
    ab = ThreeAxes(n_max=10)
    for _ in range(30):
        ab.update((1.0, 1.0, 1.0), 1.0)
    assert (ab.alpha, ab.beta) == pytest.approx(evolutive_gains(10))


def test_dsp_form_constant_velocity_is_exact_and_predict_coast() -> None:
    # any stable gains: a noise-free constant-velocity track is followed without error
    ab = ThreeAxes()
    T = 0.01
    for k in range(200):
        ab.update((100 + 5 * k * T, -3 * k * T, 2.0), T, 0.4, 0.1)
    t_last = 199 * T
    assert ab.x == pytest.approx([100 + 5 * t_last, -3 * t_last, 2.0], abs=1e-8)
    assert ab.v == pytest.approx([5.0, -3.0, 0.0], abs=1e-8)
    assert ab.predict(0.5) == pytest.approx((100 + 5 * (t_last + 0.5), -3 * (t_last + 0.5), 2.0))
    ab.coast(0.5)
    assert ab.x == pytest.approx([100 + 5 * (t_last + 0.5), -3 * (t_last + 0.5), 2.0])


def test_innovation_factor_least_squares_phase() -> None:
    # S/σ² at measurement n = 1 + variance of the LS line extrapolated from n − 1 points
    ab = ThreeAxes()
    for n in range(1, 30):
        ab.update((0.0, 0.0, 0.0), 1.0)
        if n < 3:
            assert ab.innovation_factor() == math.inf
            continue
        m = n - 1
        A = np.stack([np.ones(m), np.arange(1, m + 1)], axis=1)
        g = np.array([1.0, m + 1.0])
        expected = 1.0 + g @ np.linalg.inv(A.T @ A) @ g
        assert ab.innovation_factor() == pytest.approx(expected, rel=1e-9)


def test_alphabeta_covariance_is_least_squares_in_the_evolutive_phase() -> None:
    """σm = 0, evolutive gains: P is the covariance of the LS line fit of n points at the last
    point: P_pp = α(n)σ², P_pv = β(n)σ²/T, P_vv = 12σ²/(T² n(n² − 1))."""
    T, r = 0.5, 4.0
    f = AlphaBetaAxis(FilterConfig(sigma_m=0.0))
    for n in range(1, 40):
        f.update(0.0, T, r)
        if n >= 2:
            a, b = evolutive_gains(n)
            cov = f.P
            assert cov == pytest.approx((a * r, b * r / T, 12 * r / (T * T * n * (n * n - 1))),
                                        rel=1e-9)


@pytest.mark.parametrize("sigma_v", [2.0, 50.0, 1000.0])
def test_velocity_prior_gains_drive_the_recursion(sigma_v: float) -> None:
    """issue 11 (session 17): with ``vel_prior_k`` = r/σv² the α-β axis (no steady gains)
    runs seed 000's recursion with the seed's position gain α(n) and the velocity gain β(n)
    of the fit with a velocity prior (gains.prior_gains, q = vel_prior_k/T²), state for state
    over 80 noisy samples of a 30 m/s ramp (reference: the recursion written here)."""
    r, T = 4.0, 0.05
    k = r / sigma_v**2
    f = AlphaBetaAxis(FilterConfig(vel_prior_k=k))
    rng = np.random.default_rng(3)
    z = 100.0 + 30.0 * T * np.arange(80) + rng.normal(0.0, 2.0, 80)
    x, v = float(z[0]), 0.0
    f.update(float(z[0]), T, r)
    for n, zk in enumerate(z[1:], start=2):
        a = evolutive_gains(n)[0]
        b = prior_gains(n, k / T**2)[1]
        xp = x + v * T
        x, v = xp + a * (zk - xp), v + b / T * (zk - xp)
        f.update(float(zk), T, r)
        assert (f.pos, f.vel) == pytest.approx((x, v), rel=1e-12, abs=1e-9), n


def test_velocity_prior_holds_a_young_track_on_correlated_readings() -> None:
    """The reason for the prior: readings a PRI (100 µs) apart whose noise is AR(1) with
    ρ = 0.9 (the Doppler filters' pole), σ 7.5 m, of a still target. After 10-60 readings the
    seed's evolutive gains read the correlated noise as a velocity of ~10³-10⁴ m/s; with a
    600 m/s prior (the option's documented value, r = σ²/c) the velocity stays ≲ 10² m/s."""
    T, sig, rho = 1e-4, 7.5, 0.9
    c = (1.0 - rho) / (1.0 + rho)
    k = sig * sig / c / 600.0**2
    rng = np.random.default_rng(11)
    v_seed, v_prior = [], []
    for _ in range(200):
        e = rng.normal(0.0, sig * math.sqrt(1.0 - rho * rho), 60)
        noise = np.empty(60)
        noise[0] = rng.normal(0.0, sig)
        for i in range(1, 60):
            noise[i] = rho * noise[i - 1] + e[i]
        fs, fp = AlphaBetaAxis(FilterConfig()), AlphaBetaAxis(FilterConfig(vel_prior_k=k))
        for zi in 10_000.0 + noise:
            fs.update(float(zi), T, sig * sig)
            fp.update(float(zi), T, sig * sig)
        v_seed.append(fs.vel)
        v_prior.append(fp.vel)
    rms_seed = float(np.sqrt(np.mean(np.square(v_seed))))
    rms_prior = float(np.sqrt(np.mean(np.square(v_prior))))
    assert rms_seed > 1000.0 and rms_prior < 100.0, (rms_seed, rms_prior)


def test_a_per_axis_prior_scales_with_each_axis_reading_variance() -> None:
    """Session 20 (``vel_prior_r`` > 0, the Tracker's ``velocity_prior_axes``): X, Y, Z
    updated together with readings of variances r_x, r_y, r_z run the recursion with the
    velocity gain of the prior fit at q = vel_prior_k·r_i/r₀/T² each (the same σv against
    each axis's own reading noise), state for state over 60 samples; with r₀ = 0 all three use
    vel_prior_k as given (the X, Y, Z gains equal)."""
    from axir.models.filters.alphabeta import update_xyz

    T, r0 = 1e-4, 56.25
    k = r0 / 600.0**2
    rs = (56.25, 4.0e4, 2.5e5)  # σr², and (R·σθ)² of 0.1° and 0.25° at 11.5 km
    rng = np.random.default_rng(5)
    zs = 1000.0 + 200.0 * T * np.arange(60)[:, None] + rng.normal(0.0, 5.0, (60, 3))
    for r_ref in (r0, 0.0):
        cfg = FilterConfig(vel_prior_k=k, vel_prior_r=r_ref)
        axes = [AlphaBetaAxis(cfg) for _ in range(3)]
        ref = [[float(zs[0, i]), 0.0] for i in range(3)]
        update_xyz(*axes, *map(float, zs[0]), T, *rs, math.nan, math.nan)
        for n, z in enumerate(zs[1:], start=2):
            update_xyz(*axes, *map(float, z), T, *rs, math.nan, math.nan)
            for i, (f, ri) in enumerate(zip(axes, rs, strict=True)):
                q = k * (ri / r_ref if r_ref else 1.0) / T**2
                a, b = evolutive_gains(n)[0], prior_gains(n, q)[1]
                x, v = ref[i]
                xp = x + v * T
                ref[i] = [xp + a * (z[i] - xp), v + b / T * (z[i] - xp)]
                assert (f.pos, f.vel) == pytest.approx(ref[i], rel=1e-12, abs=1e-9), (n, i)
        betas = [f.beta for f in axes]
        if r_ref:
            assert betas[0] > betas[1] > betas[2]  # the noisier axis, the stronger prior
        else:
            assert betas[0] == betas[1] == betas[2]
