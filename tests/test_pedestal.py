"""Tests of the two-axis pedestal (models/pedestal.py).

Expected values come from the documented servo law (first-order rate lag τ = 1/(2πB), rate and
acceleration limits, angle = ∫ rate) and the potentiometer model (seed 000: 1 V/deg, second pot
offset), computed independently of the implementation.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from axir.models.pedestal import (
    OUTPUTS,
    Pedestal,
    decode_pots,
    propagate_axis,
    quantize,
    unwrap_step,
    wrap_2pi,
)

TWO_PI = 2.0 * math.pi
K = 180.0 / math.pi  # 1 V/deg (seed 000)


def circ(a: float) -> float:
    """Signed circular difference in [-π, π)."""
    return (a + math.pi) % TWO_PI - math.pi


def run(p: Pedestal, dt: float, n: int, inputs: dict) -> list[dict]:
    return [p.step(dt, inputs) for _ in range(n)]


# ---------------------------------------------------------------- servo response
@pytest.mark.parametrize("bw", [1.0, 5.0])
def test_step_response_follows_bandwidth(bw: float) -> None:
    """Small rate step (no saturation): 63.2 % at t = τ, 2 % settling at τ ln 50, τ = 1/(2πB)."""
    tau = 1.0 / (2.0 * math.pi * bw)
    p = Pedestal(pot_noise=0.0, accel_limit_az=100.0, accel_limit_el=100.0)
    u = 2.0  # V -> r = 0.2 rad/s; initial acceleration r/τ ≤ 6.3 rad/s² < 100: linear regime
    r = 0.1 * u
    dt = 1e-4
    rates = np.array([o["az.rate"] for o in run(p, dt, int(10 * tau / dt), {"cmd.az": u,
                                                                            "cmd.el": -u,
                                                                            "bandwidth": bw})])
    t = dt * np.arange(1, rates.size + 1)
    t63 = t[np.argmax(rates >= (1.0 - math.exp(-1.0)) * r)]
    assert t63 == pytest.approx(tau, abs=1.5 * dt)
    outside = np.nonzero(np.abs(rates - r) > 0.02 * r)[0]
    t_settle = t[outside[-1] + 1]
    assert t_settle == pytest.approx(tau * math.log(50.0), abs=1.5 * dt)
    assert rates.max() <= r  # first-order law: no overshoot
    # elevation: same law, opposite sign
    assert p.outputs()["el.rate"] == pytest.approx(-r * (1.0 - math.exp(-rates.size * dt / tau)),
                                                   rel=1e-9)


def test_step_response_acceleration_limited_ramp() -> None:
    """Large step: constant-acceleration ramp until |r − ω| = a τ, at t1 = (r − aτ)/a."""
    bw, a, r = 2.0, 0.5, 1.0
    tau = 1.0 / (2.0 * math.pi * bw)
    p = Pedestal(pot_noise=0.0, accel_limit_az=a, rate_limit_az=r)
    dt = 1e-3
    t1 = (r - a * tau) / a
    n1 = int(t1 / dt)
    outs = run(p, dt, n1, {"cmd.az": 1e3, "bandwidth": bw})
    for i, o in enumerate(outs, 1):
        assert o["az.rate"] == pytest.approx(a * i * dt, rel=1e-12)
        assert o["az.acc"] == a
    # afterwards exponential approach from r − aτ: ω(t1 + s) = r − aτ e^{−s/τ}
    o = run(p, dt, 300, {"cmd.az": 1e3, "bandwidth": bw})[-1]
    s = (n1 + 300) * dt - t1
    assert o["az.rate"] == pytest.approx(r - a * tau * math.exp(-s / tau), rel=1e-9)


@pytest.mark.parametrize("dt", [5e-5, 1e-3, 0.1])
def test_rate_and_acceleration_limits_hold_and_are_reached(dt: float) -> None:
    w_max, a_max = 0.8, 1.5
    p = Pedestal(pot_noise=0.0, rate_limit_az=w_max, rate_limit_el=w_max / 2,
                 accel_limit_az=a_max, accel_limit_el=a_max / 3)
    t_total = 6.0
    n = round(t_total / dt)
    seq = ([{"cmd.az": 1e4, "cmd.el": -1e4, "bandwidth": 20.0}] * (n // 2)
           + [{"cmd.az": -1e4, "cmd.el": 1e4, "bandwidth": 0.5}] * (n // 2))
    rates, accs, ela = [], [], []
    prev = 0.0
    for inp in seq:
        o = p.step(dt, inp)
        rates.append(o["az.rate"])
        accs.append(o["az.acc"])
        ela.append(o["el.rate"])
        # acceleration over the step never exceeds the limit (finite difference of the rate)
        assert abs(o["az.rate"] - prev) <= a_max * dt * (1.0 + 1e-12)
        prev = o["az.rate"]
    rates_a, accs_a = np.abs(rates), np.abs(accs)
    assert rates_a.max() <= w_max and np.abs(ela).max() <= w_max / 2
    assert accs_a.max() <= a_max
    assert rates_a.max() >= 0.999 * w_max  # reached
    assert np.abs(ela).max() >= 0.999 * w_max / 2
    if dt < 0.05:
        assert accs_a.max() == a_max  # the acceleration limit is active at the start


def test_rate_limit_constant_after_settling_and_position_linear() -> None:
    """Saturated command: the angle grows at exactly the rate limit once settled."""
    p = Pedestal(pot_noise=0.0, rate_limit_el=0.3, accel_limit_el=10.0)
    run(p, 1e-2, 300, {"cmd.el": 50.0, "bandwidth": 3.0})  # 3 s ≫ τ = 53 ms
    e0 = p.outputs()["el.true"]
    run(p, 1e-2, 100, {"cmd.el": 50.0, "bandwidth": 3.0})
    assert p.outputs()["el.true"] - e0 == pytest.approx(0.3 * 1.0, rel=1e-12)


def test_position_is_integral_of_rate() -> None:
    """From rest, no saturation: θ(t) = θ0 + r (t − τ (1 − e^{−t/τ})); then slope r."""
    bw = 1.5
    tau = 1.0 / (2.0 * math.pi * bw)
    az0, el0 = 1.0, -0.5
    p = Pedestal(pot_noise=0.0, az0=az0, el0=el0, rate_per_volt=0.05)
    u_az, u_el = 3.0, -4.0  # r = 0.15, −0.2 rad/s; r/τ < 2 rad/s²
    dt = 2e-3
    for i in range(1, 1501):
        o = p.step(dt, {"cmd.az": u_az, "cmd.el": u_el, "bandwidth": bw})
        t = i * dt
        for r, th0, key in ((0.05 * u_az, az0, "az.true"), (0.05 * u_el, el0, "el.true")):
            expect = th0 + r * (t - tau * (1.0 - math.exp(-t / tau)))
            assert circ(o[key] - expect) == pytest.approx(0.0, abs=1e-12)
    # trapezoidal integral of the output rate matches the angle change (independent check)
    p2 = Pedestal(pot_noise=0.0, el0=0.2)
    rates = [0.0] + [o["el.rate"] for o in run(p2, 1e-4, 20000, {"cmd.el": 7.0})]
    integral = np.trapezoid(rates, dx=1e-4) if hasattr(np, "trapezoid") else np.trapz(rates,
                                                                                     dx=1e-4)
    assert p2.outputs()["el.true"] - 0.2 == pytest.approx(integral, abs=1e-6)


def test_bandwidth_change_between_steps() -> None:
    """The time constant follows the bandwidth input step by step."""
    p = Pedestal(pot_noise=0.0, accel_limit_az=100.0)
    run(p, 0.01, 100, {"cmd.az": 1.0, "bandwidth": 0.5})  # settle-ish at slow τ
    w0 = p.outputs()["az.rate"]
    o = p.step(0.01, {"cmd.az": 3.0, "bandwidth": 10.0})
    tau = 1.0 / (2.0 * math.pi * 10.0)
    assert o["az.rate"] == pytest.approx(0.3 - (0.3 - w0) * math.exp(-0.01 / tau), rel=1e-12)


# ---------------------------------------------------------------- potentiometers
def test_pot_voltages_follow_seed_gain_and_offset() -> None:
    """Pot A = 1 V/deg · (θ mod 360°), pot B offset by 180° (seed 000 Figs 6-7)."""
    p = Pedestal(pot_noise=0.0, adc_bits=32, az0=math.radians(10.0), el0=math.radians(-30.0))
    o = p.outputs()
    lsb = 360.0 / 2**32
    assert o["pot.az.a"] == pytest.approx(10.0, abs=lsb)
    assert o["pot.az.b"] == pytest.approx(190.0, abs=lsb)
    assert o["pot.el.a"] == pytest.approx(330.0, abs=lsb)
    assert o["pot.el.b"] == pytest.approx(150.0, abs=lsb)


def test_pot_noise_statistics() -> None:
    """At rest, each pot reading scatters with the declared σ around k·θ (fine ADC)."""
    sigma = 0.05
    p = Pedestal(pot_noise=sigma, adc_bits=24, az0=1.0, el0=2.0, seed=7)
    outs = run(p, 1e-3, 4000, {})
    for key, mean in (("pot.az.a", K * 1.0), ("pot.az.b", K * (1.0 + math.pi)),
                      ("pot.el.a", K * 2.0), ("pot.el.b", K * (2.0 + math.pi))):
        v = np.array([o[key] for o in outs])
        assert v.std() == pytest.approx(sigma, rel=0.05)
        assert v.mean() == pytest.approx(mean, abs=4 * sigma / math.sqrt(v.size))
    a = np.array([o["pot.az.a"] for o in outs])
    b = np.array([o["pot.az.b"] for o in outs])
    assert abs(np.corrcoef(a, b)[0, 1]) < 0.1  # independent noise per pot


@pytest.mark.parametrize("offset", [math.pi, 0.5 * math.pi, 1.5 * math.pi, 2.0])
@pytest.mark.parametrize("bits", [8, 12, 16])
def test_decoder_dense_grid(offset: float, bits: int) -> None:
    """Pure decoder on a dense grid: error ≤ LSB/2 (in angle) everywhere, incl. near 0/360°."""
    n_codes = 2**bits
    lsb = K * TWO_PI / n_codes
    grid = np.concatenate([np.linspace(0.0, TWO_PI, 20001, endpoint=False),
                           [1e-12, TWO_PI - 1e-12, offset, offset + 1e-12, offset - 1e-12]])
    worst = 0.0
    for th in grid.tolist():
        va = quantize(K * (th % TWO_PI), lsb, n_codes)
        vb = quantize(K * ((th - offset) % TWO_PI), lsb, n_codes)
        d = decode_pots(va, vb, K, offset)
        assert 0.0 <= d < TWO_PI
        worst = max(worst, abs(circ(d - th)))
    assert worst <= 0.5 * lsb / K * (1.0 + 1e-9)
    assert worst >= 0.3 * lsb / K  # the quantization is really applied


def test_decoder_with_noise_near_discontinuity() -> None:
    """Pot A reads around 0/360 V with noise: decoder uses B and is never 360° off."""
    rng = np.random.default_rng(3)
    sigma = 0.2  # V (= 0.2°): large, to straddle pot A's jump often
    for th in rng.uniform(-0.02, 0.02, 5000).tolist():
        va = quantize(K * (th % TWO_PI) + sigma * rng.standard_normal(), 360.0 / 2**16, 2**16)
        vb = quantize(K * ((th - math.pi) % TWO_PI) + sigma * rng.standard_normal(),
                      360.0 / 2**16, 2**16)
        assert abs(circ(decode_pots(va, vb, K, math.pi) - th)) <= (6 * sigma + 0.01) / K


def test_sample_equals_the_pure_helpers_bit_for_bit() -> None:
    """The step's pot reading (written out for speed, issue 14) is quantize → decode_pots →
    unwrap_step → wrap_2pi of the pure helpers, bit for bit, with the noise draws known: both
    ADC clips (below 0 V and at the top code), both pots chosen, turns both ways."""
    sigma, bits = 4.0, 10  # large noise: readings below 0 V and above the top code occur
    p = Pedestal(pot_noise=sigma, adc_bits=bits, az0=0.001, el0=-0.001, rate_limit_az=5.0,
                 rate_limit_el=5.0, accel_limit_az=100.0, accel_limit_el=100.0)
    n, lsb, off = 2**bits, K * TWO_PI / 2**bits, math.pi
    rng = np.random.default_rng(11)
    clipped_low = clipped_high = 0
    prev_az, prev_el = p.outputs()["az.unwrapped"], p.outputs()["el"]
    for k in range(3000):
        nz = rng.standard_normal(4).tolist()
        p._noise, p._noise_i = nz * 64, 0  # the next sample uses nz (test-only access)
        cmd = 50.0 * math.sin(k / 300.0)
        o = p.step(0.01, {"cmd.az": cmd, "cmd.el": -cmd})
        az, el = p._az, p._el  # true shaft angles after the step
        raw = (K * (az % TWO_PI) + sigma * nz[0], K * ((az - off) % TWO_PI) + sigma * nz[1],
               K * (el % TWO_PI) + sigma * nz[2], K * ((el - off) % TWO_PI) + sigma * nz[3])
        pots = [quantize(v, lsb, n) for v in raw]
        clipped_low += sum(v < 0.0 for v in raw)
        clipped_high += sum(v > (n - 0.5) * lsb for v in raw)
        assert [o["pot.az.a"], o["pot.az.b"], o["pot.el.a"], o["pot.el.b"]] == pots
        prev_az = unwrap_step(prev_az, decode_pots(pots[0], pots[1], K, off))
        prev_el = unwrap_step(prev_el, decode_pots(pots[2], pots[3], K, off))
        assert o["az.unwrapped"] == prev_az and o["el"] == prev_el
        assert o["az"] == wrap_2pi(prev_az) and o["az.true"] == wrap_2pi(az)
    assert clipped_low > 0 and clipped_high > 0  # both clips exercised
    assert abs(prev_az) > TWO_PI  # at least one full turn


def test_unwrap_step_pure() -> None:
    assert unwrap_step(TWO_PI - 0.01, 0.02) == pytest.approx(TWO_PI + 0.02)
    assert unwrap_step(0.01, TWO_PI - 0.02) == pytest.approx(-0.02)
    assert unwrap_step(-3 * TWO_PI + 1.0, 1.1) == pytest.approx(-3 * TWO_PI + 1.1)


def test_decoded_angles_continuous_through_several_turns_both_ways() -> None:
    """Drive both axes through several turns each way; decoded angle tracks the true one."""
    sigma, bits = 0.02, 14
    lsb = K * TWO_PI / 2**bits
    bound = (0.5 * lsb + 6.0 * sigma) / K  # one reading's worst error [rad]
    w = 4.0
    p = Pedestal(pot_noise=sigma, adc_bits=bits, rate_limit_az=w, rate_limit_el=w,
                 accel_limit_az=20.0, accel_limit_el=20.0, az0=6.0, el0=-3.0, seed=11)
    dt = 2e-3
    seq = [{"cmd.az": 1e3, "cmd.el": -1e3, "bandwidth": 5.0}] * 8000 + [
        {"cmd.az": -1e3, "cmd.el": 1e3, "bandwidth": 5.0}] * 8000
    prev = p.outputs()
    true_az_cont = prev["az.true"]
    wraps = 0
    az_hi, el_lo = true_az_cont, prev["el.true"]
    for inp in seq:
        o = p.step(dt, inp)
        true_step = circ(o["az.true"] - prev["az.true"])
        true_az_cont += true_step
        # never a jump larger than the motion plus two readings' error
        d_dec = o["az.unwrapped"] - prev["az.unwrapped"]
        assert abs(d_dec - true_step) <= 2 * bound
        assert abs(o["el"] - prev["el"]) <= abs(o["el.true"] - prev["el.true"]) + 2 * bound
        # decoded within one reading's error of the true angle, continuous angles included
        assert abs(o["az.unwrapped"] - true_az_cont) <= bound
        assert abs(o["el"] - o["el.true"]) <= bound
        assert 0.0 <= o["az"] < TWO_PI and 0.0 <= o["az.true"] < TWO_PI
        assert abs(circ(o["az"] - o["az.true"])) <= bound
        wraps += abs(o["az"] - prev["az"]) > math.pi
        az_hi, el_lo = max(az_hi, true_az_cont), min(el_lo, o["el.true"])
        prev = o
    # az went ≥ 4 turns up then ≥ 4 turns down: 360→0 and 0→360 both crossed several times
    assert az_hi - 6.0 >= 4 * TWO_PI and az_hi - true_az_cont >= 4 * TWO_PI
    assert wraps >= 8
    # el went ≥ 4 turns down then ≥ 4 up (continuous output spans several multiples of 2π)
    assert -3.0 - el_lo >= 4 * TWO_PI and prev["el.true"] - el_lo >= 4 * TWO_PI


# ---------------------------------------------------------------- state and determinism
def _trace(p: Pedestal, n: int) -> bytes:
    keys = [p.name for p in OUTPUTS]
    rows = []
    for i in range(n):
        o = p.step(1e-3, {"cmd.az": 5.0 * math.sin(i * 0.01), "cmd.el": 3.0, "bandwidth": 2.0})
        rows.append([float(o[k]) for k in keys])
    return np.array(rows).tobytes()


def test_determinism_same_seed_same_bytes() -> None:
    a = _trace(Pedestal(seed=42), 500)
    b = _trace(Pedestal(seed=42), 500)
    c = _trace(Pedestal(seed=43), 500)
    assert a == b
    assert a != c


def test_get_set_state_round_trip_bit_identical() -> None:
    p = Pedestal(seed=5)
    _trace(p, 300)
    state = p.get_state()
    ref = _trace(p, 300)
    q = Pedestal(seed=999, pot_noise=0.0, az0=3.0)  # different everything; state overrides
    q.set_state(state)
    assert _trace(q, 300) == ref
    p.set_state(pickle.loads(pickle.dumps(state)))  # serialisable, and restoring in place
    assert _trace(p, 300) == ref


def test_reset_restores_initial_state() -> None:
    p = Pedestal(seed=1)
    first = _trace(p, 100)
    p.reset()
    assert _trace(p, 100) == first


@pytest.mark.parametrize("coarse", [1e-2, 0.1])
def test_any_dt_consistency(coarse: float) -> None:
    """Same piecewise-constant command: 1 ms vs coarse steps give the same angle and rate."""
    def final(dt: float) -> dict:
        p = Pedestal(pot_noise=0.0)
        n = round(0.5 / dt)
        run(p, dt, n, {"cmd.az": 40.0, "cmd.el": -2.0, "bandwidth": 1.0})
        run(p, dt, n, {"cmd.az": -3.0, "cmd.el": 25.0, "bandwidth": 4.0})
        return p.outputs()

    fine, crs = final(1e-3), final(coarse)
    for key in ("az.true", "el.true", "az.rate", "el.rate"):
        assert crs[key] == pytest.approx(fine[key], abs=1e-10)
    assert final(5e-5)["el.true"] == pytest.approx(fine["el.true"], abs=1e-10)


def test_dt_zero_returns_previous_outputs() -> None:
    p = Pedestal()
    o1 = p.step(1e-3, {"cmd.az": 1.0})
    assert p.step(0.0, {"cmd.az": 100.0}) == o1


@pytest.mark.parametrize("dt", [-1e-3, math.nan, math.inf])
def test_bad_dt_raises(dt: float) -> None:
    with pytest.raises(ValueError, match="dt"):
        Pedestal().step(dt, {})


# ---------------------------------------------------------------- invalid inputs
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, None, "x"])
def test_invalid_command_is_zero_and_flagged(bad: object) -> None:
    p, ref = Pedestal(seed=2), Pedestal(seed=2)
    run(p, 1e-3, 50, {"cmd.az": 20.0, "cmd.el": 20.0})
    run(ref, 1e-3, 50, {"cmd.az": 20.0, "cmd.el": 20.0})
    o = p.step(1e-3, {"cmd.az": bad, "cmd.el": 20.0})
    r = ref.step(1e-3, {"cmd.az": 0.0, "cmd.el": 20.0})
    assert o["input.invalid"] is True and o["input.invalid.count"] == 1
    assert r["input.invalid"] is False and r["input.invalid.count"] == 0
    for key in ("az.true", "az.rate", "el.true", "az", "el"):
        assert o[key] == r[key]
    o = p.step(1e-3, {"cmd.az": 1.0, "cmd.el": bad})
    assert o["input.invalid"] is True and o["input.invalid.count"] == 2
    o = p.step(1e-3, {"cmd.az": 1.0, "cmd.el": 1.0})
    assert o["input.invalid"] is False and o["input.invalid.count"] == 2
    assert all(math.isfinite(o[k]) for k in ("az", "el", "az.rate", "el.rate"))


@pytest.mark.parametrize("bad", [math.nan, math.inf, 0.0, -2.0, None])
def test_invalid_bandwidth_keeps_last_and_flagged(bad: object) -> None:
    p, ref = Pedestal(pot_noise=0.0), Pedestal(pot_noise=0.0)
    for q in (p, ref):
        q.step(1e-2, {"cmd.az": 3.0, "bandwidth": 7.0})
    o = p.step(1e-2, {"cmd.az": 3.0, "bandwidth": bad})
    r = ref.step(1e-2, {"cmd.az": 3.0, "bandwidth": 7.0})
    assert o["input.invalid"] is True and o["input.invalid.count"] == 1
    assert o["az.rate"] == r["az.rate"] and o["az.true"] == r["az.true"]


def test_bandwidth_out_of_range_is_clipped_not_flagged() -> None:
    p, ref = Pedestal(pot_noise=0.0), Pedestal(pot_noise=0.0)
    o = p.step(1e-2, {"cmd.az": 3.0, "bandwidth": 1e6})
    r = ref.step(1e-2, {"cmd.az": 3.0, "bandwidth": 100.0})
    assert o["az.rate"] == r["az.rate"] and o["input.invalid"] is False


def test_missing_inputs_default() -> None:
    p = Pedestal(pot_noise=0.0, az0=1.0)
    o = p.step(0.1, {})
    assert o["az.rate"] == 0.0 and o["az.true"] == 1.0 and o["input.invalid"] is False


# ---------------------------------------------------------------- parameter validation
@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("rate_per_volt", 0.0), ("rate_per_volt", 11.0), ("rate_per_volt", math.nan),
        ("rate_limit_az", 0.0), ("rate_limit_az", 21.0),
        ("rate_limit_el", -1.0), ("rate_limit_el", 21.0),
        ("accel_limit_az", 0.0), ("accel_limit_az", 1e4),
        ("accel_limit_el", -1.0), ("accel_limit_el", math.inf),
        ("bandwidth", 0.0), ("bandwidth", 101.0),
        ("az0", -0.1), ("az0", TWO_PI),
        ("el0", -4.0), ("el0", 4.0),
        ("pot_gain", 0.0), ("pot_gain", 2e4),
        ("pot_b_offset", 0.1), ("pot_b_offset", 5.0),
        ("adc_bits", 7), ("adc_bits", 33), ("adc_bits", 12.5),
        ("pot_noise", -0.1),
        ("seed", -1), ("seed", "abc"),
    ],
)
def test_parameter_validation(name: str, value: object) -> None:
    with pytest.raises(ValueError, match=name):
        Pedestal(**{name: value})


def test_cross_parameter_noise_vs_decoder_margin() -> None:
    Pedestal(pot_noise=4.0)  # 10σ = 40 V < 45 V margin at 1 V/deg: accepted
    with pytest.raises(ValueError, match="pot_noise"):
        Pedestal(pot_noise=5.0)
    with pytest.raises(ValueError, match="pot_gain"):
        Pedestal(pot_noise=0.5, pot_gain=1.0)


def test_unknown_parameter() -> None:
    with pytest.raises(ValueError, match="rate_limit"):
        Pedestal(rate_limit=1.0)


def test_propagate_axis_zero_step_and_rest() -> None:
    assert propagate_axis(1.0, 0.0, 0.0, 0.1, 1.0, 0.5) == (1.0, 0.0, 0.0)
    th, w, a = propagate_axis(0.0, 0.5, 0.5, 0.1, 1.0, 0.0)
    assert (th, w, a) == (0.0, 0.5, 0.0)


def test_step_axes_equal_propagate_axis_bit_for_bit() -> None:
    """The step's axis update (the exponential phase written out with expm1(−dt/τ) kept per
    (dt, τ), issue 14 round 5) is propagate_axis + the rate clips, bit for bit: commands that
    saturate the acceleration (ramp phase) and small ones, τ and dt changing between steps."""
    kw = dict(rate_per_volt=0.3, rate_limit_az=1.5, rate_limit_el=0.7, accel_limit_az=3.0,
              accel_limit_el=0.9)
    p = Pedestal(**kw)
    rng = np.random.default_rng(5)
    th = [p._az, p._el]
    w = [0.0, 0.0]
    lims = [(kw["rate_limit_az"], kw["accel_limit_az"]),
            (kw["rate_limit_el"], kw["accel_limit_el"])]
    bw, dt = 2.0, 1e-4
    ramps = exps = 0
    for k in range(4000):
        if k % 500 == 0:
            bw = float(rng.uniform(0.5, 20.0))  # a new τ
        if k % 700 == 0:
            dt = float(rng.choice([1e-4, 2.5e-4, 1e-3]))  # a new dt
        cmds = (float(rng.normal(0.0, 5.0 if k % 300 < 40 else 0.05)),
                float(rng.normal(0.0, 5.0 if k % 300 < 40 else 0.05)))
        o = p.step(dt, {"cmd.az": cmds[0], "cmd.el": cmds[1], "bandwidth": bw})
        tau = 1.0 / (TWO_PI * bw)
        for ax, (lim, amax) in enumerate(lims):
            r = min(max(kw["rate_per_volt"] * cmds[ax], -lim), lim)
            e = r - w[ax]
            if abs(e) > amax * tau:
                ramps += 1
            else:
                exps += 1
            th[ax], wn, acc = propagate_axis(th[ax], w[ax], r, tau, amax, dt)
            w[ax] = min(max(wn, -lim), lim)
            name = ("az", "el")[ax]
            assert o[f"{name}.rate"] == w[ax] and o[f"{name}.acc"] == acc
        assert (p._az, p._el) == (th[0], th[1])
    assert ramps > 100 and exps > 1000  # both phases exercised


def test_finite_inputs_whose_sum_overflows_are_not_invalid() -> None:
    """The common-path check (one isfinite on the sum of the three inputs) hands finite inputs
    whose sum overflows to the item-by-item rule, which accepts them: not flagged, not counted;
    a non-finite one among them is."""
    p = Pedestal()
    o = p.step(1e-3, {"cmd.az": 1e308, "cmd.el": 1e308, "bandwidth": 1e308})
    assert o["input.invalid"] is False and o["input.invalid.count"] == 0
    assert o["az.rate"] > 0.0 and o["el.rate"] > 0.0  # the commands were used (clipped rates)
    o = p.step(1e-3, {"cmd.az": -1e308, "cmd.el": math.inf, "bandwidth": 5.0})
    assert o["input.invalid"] is True and o["input.invalid.count"] == 1


def _propagate_axis_round5(theta, omega, r, tau, a_max, dt, em=None):
    """propagate_axis as it was before issue 14's spd13 branch (the reference)."""
    e = r - omega
    sat = a_max * tau
    if e > sat or e < -sat:
        s = a_max if e > 0.0 else -a_max
        t1 = (abs(e) - sat) / a_max
        if t1 >= dt:
            return theta + (omega + 0.5 * s * dt) * dt, omega + s * dt, s
        theta += (omega + 0.5 * s * t1) * t1
        e = sat if e > 0.0 else -sat
        dt -= t1
        em = None
    if em is None:
        em = math.expm1(-dt / tau)
    theta += r * dt + e * tau * em
    e_new = e * (em + 1.0)
    acc = e_new / tau
    if acc > a_max:
        acc = a_max
    elif acc < -a_max:
        acc = -a_max
    return theta, r - e_new, acc


def test_servo_axis_is_the_old_clip_propagate_clip_bit_for_bit() -> None:
    """Issue 14 (spd13): the clips and the propagation in one body (_servo_axis; propagate_axis
    is it with ±inf limits) give the bytes of the former propagate_axis between the two clips,
    on ramps and exponential phases, with and without a given expm1, NaN and ±inf included."""
    from axir.models.pedestal import _servo_axis

    rng = np.random.default_rng(13)
    specials = [math.nan, math.inf, -math.inf, 0.0, -0.0]
    n_ramp = 0
    for k in range(40000):
        theta, omega = rng.normal(0.0, 3.0), rng.normal(0.0, 1.5)
        r = rng.normal(0.0, 2.0 if k % 2 else 0.05)
        tau = 10.0 ** rng.uniform(-3.0, 0.0)
        a_max = 10.0 ** rng.uniform(-1.0, 2.0)
        dt = float(rng.choice([0.0, 1e-4, 2.5e-4, 1e-3, 0.3]))
        lim = float(rng.choice([0.5, 1.0, 20.0]))
        if k % 97 == 0:
            theta, omega, r = (float(rng.choice(specials)) if rng.random() < 0.5 else v
                               for v in (theta, omega, r))
        em = math.expm1(-dt / tau) if k % 3 else None
        rc = lim if r > lim else (-lim if r < -lim else r)
        th, w, acc = _propagate_axis_round5(theta, omega, rc, tau, a_max, dt, em)
        want = (th, lim if w > lim else (-lim if w < -lim else w), acc)
        got = _servo_axis(theta, omega, r, lim, a_max, tau, dt, em)
        assert np.array(got).tobytes() == np.array(want).tobytes(), (k, got, want)
        plain = propagate_axis(theta, omega, r, tau, a_max, dt, em)
        ref = _propagate_axis_round5(theta, omega, r, tau, a_max, dt, em)
        assert np.array(plain).tobytes() == np.array(ref).tobytes(), (k, plain, ref)
        n_ramp += abs(rc - omega) > a_max * tau
    assert n_ramp > 5000
