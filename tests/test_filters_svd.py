"""SVD filter of seed 002: full form (eqs. 16-29) and reduced form (eqs. 30-39).

What "same" means here (docs/filters.md):
- reduced form (eqs. 30-39) = full form with C = 0, term by term: equal to rounding
  (≤ 1e-12 relative);
- full form with Q_u = 0 = the augmented three-state Kalman filter [r, v, u] (Friedland's
  two-stage decomposition is exact for a constant input), for C = 0 and for C = T²/2 (filterpy);
- with the printed C = T²/2 the full form models a position state that lags the target by C·u:
  on a noise-free constant acceleration a its compensated position converges to truth − C·a
  while the reduced form converges to truth.
"""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter
from radial_track import radial_maneuver

from axir.models.filters.base import FilterConfig
from axir.models.filters.kalman import KalmanCV, q_cwna
from axir.models.filters.svd import SVDFilter, SVDReducedFilter

maneuver = radial_maneuver


def compensated(f: SVDFilter | SVDReducedFilter) -> tuple[float, float, float]:
    """X_n = X + V û (eq. 28), whatever the detector says."""
    if isinstance(f, SVDFilter):
        return f.base.pos + f.V1 * f.u, f.base.vel + f.V2 * f.u, f.u
    return f.X1 + f.V1 * f.u, f.X2 + f.V2 * f.u, f.u


@pytest.mark.parametrize("seed,T_lo,T_hi", [(1, 1.0, 1.0), (2, 0.5, 1.5)])
def test_reduced_equals_full_with_c_zero(seed: int, T_lo: float, T_hi: float) -> None:
    Ts, _, z = maneuver(150, seed, T_lo=T_lo, T_hi=T_hi)
    cfg = FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_a=2.0, svd_c="zero")
    full, red = SVDFilter(cfg), SVDReducedFilter(cfg)
    worst = 0.0
    flags = []
    for k in range(len(z)):
        if k in (60, 61):  # coasts too
            full.coast(0.5)
            red.coast(0.5)
        nf, nr = full.update(z[k], Ts[k]), red.update(z[k], Ts[k])
        b = full.base
        a = (nf, b.pos, b.vel, b.p11, b.p12, b.p22, full.u, full.pu, full.U1, full.U2,
             full.V1, full.V2, full.ku, full.fmd.L, *full.x)
        c = (nr, red.X1, red.X2, red.P11, red.P12, red.P22, red.u, red.Pu, red.U1, red.U2,
             red.V1, red.V2, red.Ku, red.fmd.L, *red.x)
        worst = max(worst, *(abs(u - v) / max(1.0, abs(v)) for u, v in zip(a, c, strict=True)))
        assert abs(red.P12 - red.P21) <= 1e-12 * max(1.0, abs(red.P12))
        flags.append(full.maneuver == red.maneuver)
    assert worst < 1e-12, worst
    assert all(flags)


@pytest.mark.parametrize("c_mode", ["zero", "paper"])
def test_full_form_is_augmented_kalman_when_qu_zero(c_mode: str) -> None:
    Ts, _, z = maneuver(150, 3, T_lo=0.6, T_hi=1.4)
    sm, sr = 5.0, 100.0
    f = SVDFilter(FilterConfig(sigma_m=sm, sigma_meas=sr, sigma_a=0.0, svd_c=c_mode))
    ref = None
    worst = 0.0
    for k in range(len(z)):
        f.update(z[k], Ts[k])
        if k == 1:
            b = f.base
            ref = KalmanFilter(dim_x=3, dim_z=1)
            ref.x = np.array([[b.pos], [b.vel], [0.0]])
            ref.P = np.array([[b.p11, b.p12, 0.0], [b.p12, b.p22, 0.0], [0.0, 0.0, f.pu]])
            ref.R = np.array([[sr * sr]])
        elif k > 1:
            T = Ts[k]
            C = 0.5 * T * T if c_mode == "paper" else 0.0
            # eq. (16): X(k) = Φ X(k−1) + B u(k−1), B = [T²/2, T] (eq. 17); u constant
            ref.F = np.array([[1.0, T, 0.5 * T * T], [0.0, 1.0, T], [0.0, 0.0, 1.0]])
            q11, q12, q22 = q_cwna(sm * sm, T)
            ref.Q = np.array([[q11, q12, 0.0], [q12, q22, 0.0], [0.0, 0.0, 0.0]])
            ref.H = np.array([[1.0, 0.0, C]])  # eq. (20): Y = H X + C u + V
            ref.predict()
            ref.update(z[k])
            b = f.base
            pn = (b.p11 + f.V1 ** 2 * f.pu, b.p12 + f.V1 * f.V2 * f.pu,
                  b.p22 + f.V2 ** 2 * f.pu, f.pu)  # eq. (29)
            ours = (*compensated(f), *pn)
            theirs = (*ref.x[:, 0], ref.P[0, 0], ref.P[0, 1], ref.P[1, 1], ref.P[2, 2])
            worst = max(worst, *(abs(u - v) / max(1.0, abs(v))
                                 for u, v in zip(ours, theirs, strict=True)))
    assert worst < 1e-9, worst


def test_printed_c_biases_the_position_by_c_times_u() -> None:
    """Noise-free constant acceleration: reduced form → truth, full form (C = T²/2) →
    truth − C·a; the acceleration estimates agree."""
    T, a = 1.0, 20.0
    t = np.arange(300) * T
    truth = 1000.0 + 250.0 * t + 0.5 * a * t * t
    full = SVDFilter(FilterConfig(sigma_m=5.0, sigma_a=2.0, svd_c="paper"))
    red = SVDReducedFilter(FilterConfig(sigma_m=5.0, sigma_a=2.0))
    for k, zk in enumerate(truth):
        full.update(zk, T)
        red.update(zk, T)
        if k >= 150:
            pf, vf, uf = compensated(full)
            pr, vr, ur = compensated(red)
            assert uf == pytest.approx(a, abs=1e-3) and ur == pytest.approx(a, abs=1e-3)
            assert pr - truth[k] == pytest.approx(0.0, abs=1e-3)
            assert pf - truth[k] == pytest.approx(-0.5 * T * T * a, abs=1e-3)
            assert vf == pytest.approx(vr, abs=1e-3)


def test_maneuver_detected_and_compensation_helps() -> None:
    """During a 30 m/s² maneuver the FMD flags it and the compensated output (eq. 28) has a
    smaller error than the two-state filter alone (seed 002 Figs. 10-11); the flag drops after
    the maneuver (acceleration no longer significant)."""
    Ts, truth, z = maneuver(160, 11)
    cfg = FilterConfig(sigma_m=5.0, sigma_meas=100.0, sigma_a=2.0)
    for cls in (SVDFilter, SVDReducedFilter):
        f, kf = cls(cfg), KalmanCV(cfg)
        e_svd, e_kf, flags = [], [], []
        for k in range(len(z)):
            f.update(z[k], Ts[k])
            kf.update(z[k], Ts[k])
            e_svd.append(f.x[0] - truth[k])
            e_kf.append(kf.x[0] - truth[k])
            flags.append(f.maneuver)
        win = slice(50, 80)
        rms_svd = np.sqrt(np.mean(np.square(e_svd[win])))
        rms_kf = np.sqrt(np.mean(np.square(e_kf[win])))
        assert rms_svd < 0.5 * rms_kf, (cls.kind, rms_svd, rms_kf)
        assert not any(flags[5:35])  # no false alarm on this seed before the maneuver
        assert any(flags[40:55])  # detected within 15 samples
        assert not any(flags[130:])  # ended
        assert f.maneuver == flags[-1] and f.x[2] == 0.0  # no maneuver: two-state output


def test_outputs_switch_with_the_flag() -> None:
    Ts, _, z = maneuver(60, 4)
    f = SVDFilter(FilterConfig())
    for k in range(50):
        f.update(z[k], Ts[k])
    b = f.base
    f.fmd.flag = False
    cov = f.P
    assert f.x == (b.pos, b.vel, 0.0) and cov == (b.p11, b.p12, b.p22)
    f.fmd.flag = True
    assert f.x == compensated(f)
    assert f.P[0] == pytest.approx(b.p11 + f.V1 ** 2 * f.pu)
    p, v, a = f.x
    assert f.predict(2.0) == pytest.approx((p + 2 * v + 2 * a, v + 2 * a, a))


def test_state_round_trip_bit_identical() -> None:
    Ts, _, z = maneuver(120, 5)
    for cls in (SVDFilter, SVDReducedFilter):
        f = cls(FilterConfig())
        for k in range(50):
            f.update(z[k], Ts[k])
        state = f.get_state()
        first = [f.update(z[k], Ts[k]) for k in range(50, 120)] + [f.x, f.P]
        g = cls(FilterConfig(sigma_m=99.0))
        g.set_state(state)
        again = [g.update(z[k], Ts[k]) for k in range(50, 120)] + [g.x, g.P]
        assert first == again
