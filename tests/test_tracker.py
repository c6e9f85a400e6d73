"""AXIR_B Tracker unit: deviations, closed-loop tracking, coasting, modes, state, params."""

from __future__ import annotations

import math

import numpy as np
import pytest

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.geometry import boresight_offsets, cart_to_sph, sph_to_cart
from axir.models.tracker import Tracker

ANT = MonopulseAntenna()
K_M = 4 * math.log(2) * math.radians(1.25) / math.radians(2.5) ** 2  # antenna.py slope
DOP = np.array([0.4, 1.0, 0.4])


def make_beams(target: tuple[float, float, float], ped_az: float, ped_el: float,
               gate_start: float, offset: float = 0.0, amp: float = 100.0,
               floor: float = 0.0) -> np.ndarray:
    """Noise-free beams built in the test: Gaussian squinted beams, triangular range response
    (0.5 µs pulse, 75 m samples), bin r at gate_start + (r − 1)·75 m (apparent range)."""
    rho, az_t, el_t = cart_to_sph(*target)
    lat, elo = boresight_offsets(az_t, el_t, ped_az, ped_el)
    g = ANT.gains(lat, elo)
    bins = gate_start + 75.0 * np.arange(16)
    tri = np.clip(1.0 - np.abs((rho - offset) - bins) / 75.0, 0.0, None)
    return amp * g[:, None, None] * tri[None, :, None] * DOP[None, None, :] + floor


def inputs(beams, az, el, mode, gate, offset=0.0, alpha=0.0, beta=0.0) -> dict:
    return {"beam": beams, "ped.az": az, "ped.el": el, "mode": mode, "alpha": alpha,
            "beta": beta, "range.offset": offset, "gate.command": gate}


def _pos(trk: Tracker) -> list[float]:
    """Filtered (X, Y, Z) [m] of the tracker's Cartesian axis filters."""
    return [f.x[0] for f in trk.core.axes]


def _vel(trk: Tracker) -> list[float]:
    """Filtered (VX, VY, VZ) [m/s]."""
    return [f.x[1] for f in trk.core.axes]


def finite_outputs(out: dict) -> bool:
    return all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in out.values())


def test_sum_is_eq1() -> None:
    rng = np.random.default_rng(0)
    b = rng.uniform(0, 10, (4, 16, 3))
    out = Tracker().step(1e-3, inputs(b, 0.0, 0.1, 0, 1000.0))
    assert np.array_equal(out["sum"], b[0] + b[1] + b[2] + b[3])
    assert out["sum"].shape == (16, 3)


@pytest.mark.parametrize("mode", [1, 2])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_deviation_signs_and_magnitudes(mode: int, sign: float) -> None:
    az_a, el_a, gate = 0.5, 0.2, 6000.0
    d_az, d_el, d_r = sign * 4e-3, sign * 3e-3, sign * 20.0
    target = sph_to_cart(gate + 450.0 + d_r, az_a + d_az, el_a + d_el)
    lat, elo = boresight_offsets(az_a + d_az, el_a + d_el, az_a, el_a)
    b = make_beams(target, az_a, el_a, gate)
    exact = Tracker(monopulse_law="exact").step(1e-3, inputs(b, az_a, el_a, mode, gate))
    # SYSTEM.md signs: east → dev.az > 0, above → dev.el > 0, farther → dev.range > 0
    assert np.sign(exact["dev.az"]) == sign
    assert np.sign(exact["dev.el"]) == sign
    assert np.sign(exact["dev.range"]) == sign
    # Gaussian pattern: ε = tanh(k_m θ) exactly, so the exact law returns the true offsets
    assert exact["dev.el"] == pytest.approx(elo, abs=1e-12)
    assert exact["dev.lat"] == pytest.approx(lat, abs=1e-12)
    assert exact["dev.az"] == pytest.approx(d_az, rel=1e-3)  # dAz = dLat/cos El (1st order)
    assert exact["dev.range"] == pytest.approx(d_r, abs=1e-9)  # triangular response: exact
    lin = Tracker(monopulse_law="linear").step(1e-3, inputs(b, az_a, el_a, mode, gate))
    assert lin["dev.el"] == pytest.approx(math.tanh(K_M * elo) / K_M, abs=1e-12)
    assert lin["dev.lat"] == pytest.approx(math.tanh(K_M * lat) / K_M, abs=1e-12)
    assert not lin["coasting"] and lin["track.n"] == 1


def test_confirmed_uses_central_filter_only() -> None:
    az_a, el_a, gate = 0.0, 0.1, 3000.0
    target = sph_to_cart(gate + 450.0, az_a + 2e-3, el_a)
    b = make_beams(target, az_a, el_a, gate)
    # corrupt the side Doppler filters with a target at a very different angle
    b2 = b.copy()
    b2[:, :, 0] = make_beams(sph_to_cart(gate + 450.0, az_a - 8e-3, el_a + 8e-3),
                             az_a, el_a, gate)[:, :, 0] * 5
    conf = Tracker(monopulse_law="exact").step(1e-3, inputs(b2, az_a, el_a, 2, gate))
    tent = Tracker(monopulse_law="exact").step(1e-3, inputs(b2, az_a, el_a, 1, gate))
    lat, _ = boresight_offsets(az_a + 2e-3, el_a, az_a, el_a)
    assert conf["dev.lat"] == pytest.approx(lat, abs=1e-12)
    assert tent["dev.lat"] < 0  # the Σ over filters is dominated by the corrupting signal


def _closed_loop(n0: int, n1: int, n2: int, offset: float = 0.0, latency: int = 1,
                 **params: object):
    """Target flying a straight line; pedestal = ideal rate integrator of cmd·rate_per_volt."""
    dt = 1e-3
    # target starts at az 0.6947, el 0.1515 rad; designation ≈ 0.3° off, pedestal 1.4° off
    trk = Tracker(designation_az=0.69, designation_el=0.15, pointing_gain=5.0,
                  gate_latency=latency, **params)
    p0, v = np.array([5000.0, 6000.0, 1200.0]), np.array([-150.0, 40.0, 10.0])
    az, el = 0.67, 0.14
    gate_hist = [cart_to_sph(*p0)[0] - offset - 470.0]
    log = []
    for k in range(n0 + n1 + n2):
        t = k * dt
        target = tuple(p0 + v * t)
        mode = 0 if k < n0 else (1 if k < n0 + n1 else 2)
        gate_used = gate_hist[-latency] if len(gate_hist) >= latency else gate_hist[0]
        b = make_beams(target, az, el, gate_used, offset)
        # manager's coarse gate: true range at mode-1 start rounded to a bin
        gcmd = 75.0 * round((cart_to_sph(*p0)[0] - offset - 450.0) / 75.0)
        out = trk.step(dt, inputs(b, az, el, mode, gcmd, offset, alpha=0.05, beta=0.002))
        gate_hist.append(out["gate.start"])
        log.append((mode, target, (az, el), out))
        az += out["cmd.az"] * trk.rate_per_volt * dt
        el += out["cmd.el"] * trk.rate_per_volt * dt
    return trk, log, v


def test_acquisition_points_at_designation() -> None:
    # (no acquisition search: its first lap would begin at 0.5 s; tests/test_tracker_search.py)
    _, log, _ = _closed_loop(1500, 0, 0, search_radius=0.0)
    _, _, (az, el), out = log[0]
    assert out["cmd.az"] > 0 and out["cmd.el"] > 0  # designation is at larger az and el
    assert out["cmd.az"] == pytest.approx(5.0 * 0.02 / 0.1)  # K·error / rate_per_volt
    assert out["cmd.el"] == pytest.approx(5.0 * 0.01 / 0.1)
    _, _, (az, el), out = log[-1]
    assert az == pytest.approx(0.69, abs=1e-4) and el == pytest.approx(0.15, abs=1e-4)
    assert not out["track.valid"] and out["track.n"] == 0
    gcmd = 75.0 * round((math.dist((0, 0, 0), (5000.0, 6000.0, 1200.0)) - 450.0) / 75.0)
    assert out["gate.start"] == gcmd


@pytest.mark.parametrize("kind", ["alphabeta", "kalman", "svd", "svd_reduced", "vd", "imm"])
def test_closed_loop_track_converges(kind: str) -> None:
    _, log, v = _closed_loop(300, 300, 2400, filter_x=kind, filter_y=kind, filter_z=kind)
    first = next(o for m, _, _, o in log if m == 1)
    tgt0, (az0, el0) = log[300][1], log[300][2]
    _, az_t, el_t = cart_to_sph(*tgt0)
    # cmd voltages drive the pedestal toward the target on the first measurement
    assert np.sign(first["cmd.az"]) == np.sign(az_t - az0)
    assert np.sign(first["cmd.el"]) == np.sign(el_t - el0)
    _, target, (az, el), out = log[-1]
    pos = np.array([out["track.x"], out["track.y"], out["track.z"]])
    assert np.linalg.norm(pos - np.array(target)) < 0.5
    assert np.array([out["track.vx"], out["track.vy"], out["track.vz"]]) == pytest.approx(
        v, abs=0.5)
    rho, az_t, el_t = cart_to_sph(*target)
    assert out["track.range"] == pytest.approx(rho, abs=0.5)
    assert out["track.range_rate"] == pytest.approx(float(v @ np.array(target)) / rho, abs=0.5)
    assert (out["track.az"], out["track.el"]) == pytest.approx((az_t, el_t), abs=1e-4)
    assert (az, el) == pytest.approx((az_t, el_t), abs=2e-4)  # pedestal on target
    # confirmed mode: the tracker's own gate puts the next range on bin 7
    rho_next = cart_to_sph(*(np.array(target) + v * 1e-3))[0]
    assert out["gate.start"] == pytest.approx(rho_next - 450.0, abs=0.5)
    assert out["maneuver"] is False and not out["coasting"]


@pytest.mark.parametrize("latency", [1, 2])
def test_closed_loop_with_range_offset_and_latency(latency: int) -> None:
    offset = 22_500.0  # N·Ru of the manager: beams are at apparent range
    _, log, _ = _closed_loop(50, 200, 1500, offset=offset, latency=latency)
    _, target, _, out = log[-1]
    assert out["track.range"] == pytest.approx(cart_to_sph(*target)[0], abs=0.5)
    assert out["gate.start"] == pytest.approx(cart_to_sph(*target)[0] - offset - 450.0, abs=1.0)


def test_measured_range_uses_previous_gate() -> None:
    az, el, g0 = 0.3, 0.1, 4000.0
    target = sph_to_cart(g0 + 450.0 + 10.0, az, el)
    trk = Tracker()
    trk.step(1e-3, inputs(make_beams(target, az, el, g0), az, el, 1, g0))
    # the manager moves the gate now; these beams were still formed with g0
    out = trk.step(1e-3, inputs(make_beams(target, az, el, g0), az, el, 1, g0 + 30.0))
    assert out["track.n"] == 2  # α(2) = 1: the filtered position is the measurement
    # (the filter's state: a tentative track reports the manager's hypothesis, issue 11)
    assert math.hypot(out["track.x"], out["track.y"], out["track.z"]) == pytest.approx(
        g0 + 460.0, abs=1e-6)
    assert out["gate.start"] == g0 + 30.0  # mode 1: gate follows the command


@pytest.mark.parametrize("bad", ["nan_beam", "inf_beam", "nan_az", "inf_el", "zero", "weak",
                                 "nan_offset", "nan_side_bin"])
def test_bad_inputs_coast_and_state_stays_finite(bad: str) -> None:
    az, el, gate, dt = 0.3, 0.1, 4000.0, 1e-3
    trk = Tracker()
    p0, v = np.array(sph_to_cart(gate + 450.0, az, el)), np.array([30.0, -20.0, 5.0])
    for k in range(20):
        trk.step(dt, inputs(make_beams(tuple(p0 + v * k * dt), az, el, gate), az, el, 1, gate))
    x_before, v_before, n_before = _pos(trk), _vel(trk), trk.core.axes[0].n
    b = make_beams(tuple(p0 + v * 20 * dt), az, el, gate, floor=1.0)
    a_in, e_in, off = az, el, 0.0
    if bad == "nan_beam":
        b[1, 6, 1] = np.nan
    elif bad == "inf_beam":
        b[:, 5, :] = np.inf
    elif bad == "nan_az":
        a_in = math.nan
    elif bad == "inf_el":
        e_in = math.inf
    elif bad == "zero":
        b[:] = 0.0
    elif bad == "weak":
        b = np.full((4, 16, 3), 1.0)
        b[:, 6, :] = 1.5  # gate centre below 2 × the side-bin mean
    elif bad == "nan_offset":
        off = math.nan
    elif bad == "nan_side_bin":
        b[0, 14, 0] = np.nan
    out = trk.step(dt, inputs(b, a_in, e_in, 1, gate, off))
    assert out["coasting"] is True
    assert trk.core.axes[0].n == n_before
    assert _pos(trk) == pytest.approx([x + vv * dt for x, vv in zip(x_before, v_before,
                                                                    strict=True)])
    out.pop("sum")  # eq. (1) passes the input through (NaN in, NaN out)
    assert finite_outputs(out)
    assert all(math.isfinite(u) for u in _pos(trk) + _vel(trk))
    # a good measurement afterwards resumes the update
    out = trk.step(dt, inputs(make_beams(tuple(p0 + v * 21 * dt), az, el, gate), az, el, 1,
                              gate))
    assert not out["coasting"] and trk.core.axes[0].n == n_before + 1


def test_nan_before_any_track_and_in_acquisition() -> None:
    trk = Tracker()
    b = np.full((4, 16, 3), np.nan)
    for mode in (0, 1, 2):
        out = trk.step(1e-3, inputs(b, math.nan, math.nan, mode, 1000.0))
        out.pop("sum")
        assert finite_outputs(out)
        assert out["track.n"] == 0
    assert out["coasting"] is True


def test_mode_zero_resets_track() -> None:
    az, el, gate = 0.3, 0.1, 4000.0
    target = sph_to_cart(gate + 450.0, az, el)
    b = make_beams(target, az, el, gate)
    trk = Tracker()
    for _ in range(10):
        out = trk.step(1e-3, inputs(b, az, el, 2, gate))
    assert out["track.n"] == 10 and out["track.valid"]
    out = trk.step(1e-3, inputs(b, az, el, 0, gate))
    assert out["track.n"] == 0 and not out["track.valid"] and out["gate.start"] == gate
    out = trk.step(1e-3, inputs(b, az, el, 1, gate))
    assert out["track.n"] == 1
    assert (out["track.vx"], out["track.vy"], out["track.vz"]) == (0.0, 0.0, 0.0)


def test_get_set_state_round_trip_bit_identical() -> None:
    trk, _, _ = _closed_loop(20, 50, 100)
    rng = np.random.default_rng(9)
    seq = [inputs(rng.uniform(0, 50, (4, 16, 3)), 0.62 + 1e-4 * k, 0.12, 2, 5000.0,
                  alpha=0.3, beta=0.05) for k in range(30)]
    state = trk.get_state()
    first = [trk.step(1e-3, s) for s in seq]
    other = Tracker(monopulse_law="exact")
    other.set_state(state)
    second = [other.step(1e-3, s) for s in seq]
    for a, b in zip(first, second, strict=True):
        assert a.keys() == b.keys()
        for key in a:
            assert np.array_equal(a[key], b[key]), key


def test_parameter_validation() -> None:
    with pytest.raises(ValueError, match="monopulse_law"):
        Tracker(monopulse_law="cubic")
    with pytest.raises(ValueError, match="rate_per_volt"):
        Tracker(rate_per_volt=0.0)
    with pytest.raises(ValueError, match="squint"):
        Tracker(squint=0.1, beamwidth=0.05)
    with pytest.raises(ValueError, match="unknown"):
        Tracker(bandwidth=3.0)
    with pytest.raises(ValueError, match="gate_latency"):
        Tracker(gate_latency=0)
    with pytest.raises(ValueError, match="maneuver_fading"):
        Tracker(maneuver_fading=1.0)
    assert Tracker().rate_per_volt == 0.1


def test_command_saturates() -> None:
    trk = Tracker(designation_az=3.0, cmd_limit=7.0)
    out = trk.step(1e-3, inputs(np.zeros((4, 16, 3)), 0.0, 0.1, 0, 1000.0))
    assert out["cmd.az"] == 7.0
    out = trk.step(1e-3, inputs(np.zeros((4, 16, 3)), 3.01, 0.1, 0, 1000.0))
    assert out["cmd.az"] == pytest.approx(-2.0 * 0.01 / 0.1)  # unsaturated: K·err/rate_per_volt
    trk = Tracker(designation_az=0.1, cmd_limit=7.0, pointing_gain=0.1)
    out = trk.step(1e-3, inputs(np.zeros((4, 16, 3)), 6.2, 0.1, 0, 1000.0))
    # shortest way round: wrap(0.1 − 6.2) = +0.183 rad (not −6.1)
    assert out["cmd.az"] == pytest.approx(0.1 * (0.1 - 6.2 + 2 * math.pi) / 0.1)


def test_optional_ddre_on_sum_profile() -> None:
    az, el, gate, offset = 0.3, 0.1, 4000.0, 15_000.0
    target = sph_to_cart(offset + gate + 450.0 + 25.0, az, el)
    b = make_beams(target, az, el, gate, offset)
    out = Tracker().step(1e-3, inputs(b, az, el, 2, gate, offset))
    assert out["ddre.valid"] is False and out["ddre.range"] == 0.0  # disabled by default
    trk = Tracker(ddre_window=3)
    for _ in range(3):  # mode 1: the gate stays where the beams were formed
        out = trk.step(1e-3, inputs(b, az, el, 1, gate, offset))
    # independent: |SUM|² summed over the filters, best 3-bin window, weighted centroid
    p2 = (b[0] + b[1] + b[2] + b[3]).sum(axis=1) ** 2
    r = max(range(14), key=lambda i: p2[i:i + 3].sum())
    ranges = offset + gate + 75.0 * np.arange(r, r + 3)
    expected = float((p2[r:r + 3] * ranges).sum() / p2[r:r + 3].sum())
    assert out["ddre.valid"] is True
    assert out["ddre.range"] == pytest.approx(expected, abs=1e-9)
    assert out["ddre.smoothed"] == pytest.approx(expected, abs=1e-9)  # constant input


@pytest.mark.parametrize("input_mode", ["beams", "measurement"])
def test_step_outputs_are_the_declared_ports_in_order(input_mode: str) -> None:
    """Both input modes return exactly the declared outputs, in the order of OUTPUTS."""
    trk = Tracker(input_mode=input_mode)
    beams = make_beams((1000.0, 5000.0, 500.0), 0.2, 0.1, 4500.0)
    out = trk.step(1e-4, {**inputs(beams, 0.2, 0.1, 2, 4500.0), "meas.range": 5000.0,
                          "meas.az": 0.2, "meas.el": 0.1, "meas.valid": 1.0, "meas.new": 1.0})
    assert list(out) == [p.name for p in Tracker.OUTPUTS]


@pytest.mark.parametrize("off_deg, clip_deg, expect_deg", [
    (2.0, 2.5, 2.0),   # inside the clip: the true offset (ε = tanh(k_m θ) inverted)
    (3.5, 2.5, 2.5),   # beyond: the clip angle itself
    (3.5, 4.0, 3.5),   # a wider clip reads it again
])
def test_exact_law_clipped_to_main_lobe(off_deg: float, clip_deg: float,
                                        expect_deg: float) -> None:
    """Session 13: the exact law reads at most ``exact_max_angle`` (the ratio clipped to
    ±tanh(k_m·clip)); a noisy ratio near ±1 no longer reads 13°. Noise-free beams in the
    elevation plane (boresight el 0.1 rad, target above it)."""
    az_a, el_a, gate = 0.3, 0.1, 5000.0
    d_el = math.radians(off_deg)
    b = make_beams(sph_to_cart(gate + 450.0, az_a, el_a + d_el), az_a, el_a, gate)
    out = Tracker(monopulse_law="exact", exact_max_angle=math.radians(clip_deg)).step(
        1e-3, inputs(b, az_a, el_a, 2, gate))
    assert out["dev.el"] == pytest.approx(math.radians(expect_deg), rel=1e-9)
    lin = Tracker(monopulse_law="linear", exact_max_angle=math.radians(clip_deg)).step(
        1e-3, inputs(b, az_a, el_a, 2, gate))  # the linear law ignores the clip
    assert lin["dev.el"] == pytest.approx(math.tanh(K_M * d_el) / K_M, rel=1e-9)
