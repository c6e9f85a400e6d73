"""TargetGenerator: radar equation, range folding, straddle, monopulse, Doppler, noise, clutter,
Swerling, measurement fidelity, determinism and validation.

Expected values are derived independently of the model's code: the radar equation and the
reference-SNR definition, the triangular straddle, MonopulseAntenna's closed forms, the IIR
filter's transfer function and the first-order noise theory of the amplitude-comparison
estimator.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import BIN_M, DEFAULT_WAVELENGTH, C, gate_start_for
from axir.models.radar.geometry import boresight_offsets, cart_to_sph, sph_to_cart
from axir.models.target_generator import INPUTS, OUTPUTS, TargetGenerator
from axir.models.tracker.deviations import angle_ratios, gate_cells, range_deviation_m

INPUT_NAMES = [p.name for p in INPUTS]
OUTPUT_NAMES = [p.name for p in OUTPUTS if p.name != "beam"]
PRI = 100e-6
RU = 0.5 * C * PRI  # 14 990 m
ANT = MonopulseAntenna()
G_BORE = float(ANT.voltage(ANT.squint))  # each beam's voltage gain on boresight, v(θs)


def static_spec(r: float, az: float, el: float) -> str:
    """JSON spec of a motionless target at (r, az, el)."""
    return json.dumps({"type": "cv", "position": list(sph_to_cart(r, az, el)),
                       "velocity": [0.0, 0.0, 0.0]})


def quiet(**kw) -> TargetGenerator:
    """Noise-, clutter- and fluctuation-free generator."""
    base = {"noise": False, "clutter": False, "swerling": 0}
    base.update(kw)
    return TargetGenerator(**base)


def inputs(az=0.3, el=0.2, gate_start=0.0, centre=0.0, pri=PRI) -> dict[str, float]:
    return {"antenna.az": az, "antenna.el": el, "gate.start": gate_start,
            "doppler.centre": centre, "pri": pri}


def advance(gen: TargetGenerator, inp: dict, n: int, path: str) -> dict:
    """Run n pulses: one step of n·pri (vectorised path) or n steps of pri (scalar path)."""
    if path == "vector":
        return gen.step(n * inp["pri"], inp)
    for _ in range(n):
        out = gen.step(inp["pri"], inp)
    return out


def settle(gen: TargetGenerator, inp: dict, path: str, n: int = 400) -> dict:
    """Run n pulses (pole 0.9: 0.9⁴⁰⁰ ≈ 5e-19, steady state)."""
    return advance(gen, inp, n, path)


@pytest.fixture(params=["vector", "scalar"])
def path(request) -> str:
    """Both pulse paths of the model (one step of N pulses / one pulse per step)."""
    return request.param


def amplitude(gen: TargetGenerator, r: float) -> float:
    """√SNR at range r from the snr_ref_db definition (one beam, peak gain, mean RCS)."""
    snr = 10 ** (gen.snr_ref_db / 10) * gen.rcs / gen.rcs_ref * (gen.snr_ref_range / r) ** 4
    return math.sqrt(snr)


# ---------------------------------------------------------------------------------------------
# Range: radar equation, folding, straddle
# ---------------------------------------------------------------------------------------------

def test_absolute_amplitude_and_straddle_weights(path):
    """Boresight static target 30 m beyond the bin-7 sample: bin 7 gets 0.6, bin 8 0.4 of the
    radar-equation amplitude times v(θs); every other bin is exactly 0."""
    az, el, r = 0.3, 0.2, 6000.0
    gen = quiet(trajectory=static_spec(r, az, el))
    out = settle(gen, inputs(az, el, gate_start_for(r - 30.0)), path)
    beam = out["beam"]
    expected = amplitude(gen, r) * G_BORE
    np.testing.assert_allclose(beam[:, 6, 1], 0.6 * expected, rtol=1e-9)
    np.testing.assert_allclose(beam[:, 7, 1], 0.4 * expected, rtol=1e-9)
    others = np.delete(beam[:, :, 1], [6, 7], axis=1)
    assert np.all(others == 0.0)
    # a static target (Doppler 0) is rejected by the side filters at ±PRF/3:
    # |H(f)| = (1 − ρ)/|1 − ρ e^{−j2π f T}| with f T = 1/3
    h_side = 0.1 / abs(1 - 0.9 * np.exp(-2j * np.pi / 3))
    np.testing.assert_allclose(beam[:, 6, 0], 0.6 * expected * h_side, rtol=1e-9)
    np.testing.assert_allclose(beam[:, 6, 2], 0.6 * expected * h_side, rtol=1e-9)
    assert out["truth.snr_db"] == pytest.approx(20 * math.log10(amplitude(gen, r)))


def test_range_folding_target_beyond_ru_lands_in_same_bin(path):
    az, el, r = 0.3, 0.2, 5000.0
    inp = inputs(az, el, gate_start_for(r - 20.0))
    near = settle(quiet(trajectory=static_spec(r, az, el)), inp, path)["beam"]
    far = settle(quiet(trajectory=static_spec(r + RU, az, el)), inp, path)["beam"]
    assert np.count_nonzero(near) > 0
    np.testing.assert_array_equal(near > 0, far > 0)  # same bins
    # same magnitudes up to the radar equation's R⁻² in amplitude
    np.testing.assert_allclose(far, near * (r / (r + RU)) ** 2, rtol=1e-9)
    # the gate may be given at the true range or folded: the window samples it modulo Ru
    far2 = settle(quiet(trajectory=static_spec(r + RU, az, el)),
                  inputs(az, el, gate_start_for(r - 20.0) + RU), path)["beam"]
    np.testing.assert_allclose(far2, far, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("wrap", [False, True])
def test_straddle_range_deviation_recovers_offset(wrap, path):
    """ε_R·75 m (deviations.range_deviation_m) recovers the offset to < 7.5 m anywhere in bins
    6–8, also when the window straddles Ru (bins before and after the fold)."""
    az, el = 0.3, 0.2
    centre_app = 150.0 if wrap else 9000.0  # apparent range of the bin-7 sample
    gate = gate_start_for(centre_app) % RU  # wrap: bins 1..4 lie before Ru, 5.. after 0
    for off in np.linspace(-74.0, 74.0, 23):
        r_true = centre_app + off + (2 * RU if wrap else 0.0)
        gen = quiet(trajectory=static_spec(r_true, az, el))
        beam = advance(gen, inputs(az, el, gate), 50, path)["beam"]
        for central_only in (True, False):
            dev = range_deviation_m(gate_cells(beam, central_only=central_only))
            assert abs(dev - off) < 0.1 * BIN_M, (off, dev)


# ---------------------------------------------------------------------------------------------
# Angles
# ---------------------------------------------------------------------------------------------

def test_boresight_target_gives_equal_beams(path):
    az, el, r = 1.1, 0.15, 8000.0
    beam = settle(quiet(trajectory=static_spec(r, az, el)),
                  inputs(az, el, gate_start_for(r)), path)["beam"]
    np.testing.assert_allclose(beam[0], beam[2], rtol=1e-12)  # up = down
    np.testing.assert_allclose(beam[1], beam[3], rtol=1e-12)  # right = left


@pytest.mark.parametrize("d_az,d_el", [(0.004, -0.006), (-0.015, 0.01), (0.0, 0.02)])
def test_off_boresight_ratios_equal_antenna_ratio(d_az, d_el, path):
    az_a, el_a, r = 2.0, 0.3, 9000.0
    az_t, el_t = az_a + d_az, el_a + d_el
    beam = settle(quiet(trajectory=static_spec(r, az_t, el_t)),
                  inputs(az_a, el_a, gate_start_for(r)), path)["beam"]
    lat, elo = boresight_offsets(az_t, el_t, az_a, el_a)
    eps_lat, eps_el = angle_ratios(gate_cells(beam, central_only=True))
    assert eps_lat == pytest.approx(float(ANT.ratio(lat)), abs=1e-9)
    assert eps_el == pytest.approx(float(ANT.ratio(elo)), abs=1e-9)
    if d_az > 0:
        assert eps_lat > 0  # clockwise (east) of boresight → dev.az > 0 (SYSTEM.md)


# ---------------------------------------------------------------------------------------------
# Doppler
# ---------------------------------------------------------------------------------------------

def radial_target(r_end: float, rdot: float, t_end: float, az=0.3, el=0.2) -> str:
    """Target moving radially with range rate rdot [m/s], at range r_end at t_end."""
    u = np.array(sph_to_cart(1.0, az, el))
    p0 = u * (r_end - rdot * t_end)
    return json.dumps({"type": "cv", "position": p0.tolist(), "velocity": (u * rdot).tolist()})


@pytest.mark.parametrize("f", [1, 2, 3])
def test_target_at_filter_centre_peaks_in_that_filter(f, path):
    pri, centre, n = PRI, 1200.0, 400
    spacing = 1.0 / (3 * pri)  # default spacing: PRF/3
    fd = centre + (f - 2) * spacing
    rdot = -fd * DEFAULT_WAVELENGTH / 2  # f_d = −2ṙ/λ (radar.py)
    t_end, r_end = n * pri, 7000.0
    gen = quiet(trajectory=radial_target(r_end, rdot, t_end))
    out = advance(gen, inputs(0.3, 0.2, gate_start_for(r_end), centre, pri), n, path)
    cell = out["beam"][:, 6, :]
    assert np.all(np.argmax(cell, axis=1) == f - 1)
    # unit gain at the filter centre (the target moves < 3 cm/pulse: straddle ≈ 1)
    np.testing.assert_allclose(cell[:, f - 1], amplitude(gen, r_end) * G_BORE, rtol=0.01)
    assert out["truth.doppler"] == pytest.approx(fd)


def test_doppler_spacing_parameter(path):
    pri, n, sp = PRI, 400, 500.0
    fd = -sp  # filter 1 when the spacing is 500 Hz (centre 0)
    rdot = -fd * DEFAULT_WAVELENGTH / 2
    gen = quiet(trajectory=radial_target(7000.0, rdot, n * pri), doppler_spacing=sp)
    inp = inputs(0.3, 0.2, gate_start_for(7000.0), 0.0, pri)
    cell = advance(gen, inp, n, path)["beam"][:, 6]
    assert np.all(np.argmax(cell, axis=1) == 0)


def test_doppler_folding_fd_plus_prf_gives_same_outputs(path):
    """Range rates differing by PRF·λ/2 give phase sequences equal modulo 2π per pulse."""
    pri, n = 1e-3, 300
    prf = 1.0 / pri
    t_end, r_end = n * pri, 7000.0
    fd = 250.0  # filter 2 with centre 250 Hz
    outs = []
    for f_true in (fd, fd + prf, fd - 2 * prf):
        rdot = -f_true * DEFAULT_WAVELENGTH / 2
        gen = quiet(trajectory=radial_target(r_end, rdot, t_end), pole=0.8)
        inp = inputs(0.3, 0.2, gate_start_for(r_end), fd, pri)
        outs.append(advance(gen, inp, n, path)["beam"])
    assert np.all(np.argmax(outs[0][:, 6, :], axis=1) == 1)
    # the faster targets walk < 1 m further in the filter's memory: straddle differs < 1 %
    np.testing.assert_allclose(outs[1][:, 6, :], outs[0][:, 6, :], rtol=0.01)
    np.testing.assert_allclose(outs[2][:, 6, :], outs[0][:, 6, :], rtol=0.02)


# ---------------------------------------------------------------------------------------------
# Noise and monopulse accuracy (SYSTEM acceptance)
# ---------------------------------------------------------------------------------------------

POLE = 0.9
NOISE_GAIN = (1 - POLE) / (1 + POLE)  # Σ|h_k|² of h_k = (1 − ρ) ρ^k: filtered noise power


def test_noise_only_filter_output_power():
    """Unit-power complex noise through y = p y + (1 − ρ) x has power (1 − ρ)/(1 + ρ)."""
    gen = TargetGenerator(rcs=0.0, clutter=False, seed=11)
    inp = inputs()
    gen.step(100 * PRI, inp)
    powers = [gen.step(60 * PRI, inp)["beam"] ** 2 for _ in range(150)]
    p = np.mean(powers)  # 150 × 192 samples
    assert p == pytest.approx(NOISE_GAIN, rel=0.05)


@pytest.mark.parametrize("snr_out_db", [10.0, 20.0, 30.0])
def test_monopulse_angle_noise_matches_theory(snr_out_db):
    r"""σ of ε/k_m at the central filter output vs theory for OUR estimator.

    Each beam's filter output on boresight is y_i = A + n_i, A = √S·v(θs) (S: per-pulse SNR
    at peak gain, v(θs) the crossover gain), n_i ~ CN(0, σ²) independent, σ² = (1 − ρ)/(1 + ρ)
    (unit-power input noise; the signal sees unit gain at the filter centre). So the SNR in the
    cell where the deviations are formed is SNR = A²/σ² = S v(θs)² (1 + ρ)/(1 − ρ).
    With m_i = |y_i| ≈ A + Re n_i to first order,
        ε = (m1 − m3)/(m1 + m3) ≈ (Re n1 − Re n3)/(2A),  var ε = 2(σ²/2)/(4A²) = 1/(4 SNR),
        σθ = σε/k_m = 1/(k_m √(4 SNR)) = 1/(k_m √(2 SNR_Σ)),
    SNR_Σ = 2 SNR being the SNR of the two-beam sum (amplitude 2A, noise 2σ²): the textbook
    θ3/(k_m√(2 SNR)) with normalised slope. (A Monte-Carlo check of the magnitude estimator gives
    the first-order value within 0.3 % at 10 dB.) Samples 60 pulses apart (ρ⁶⁰ ≈ 0.002) are
    independent; N = 2000 gives a ±1.6 % (1σ) sampling error of σ.
    """
    az, el, r = 0.3, 0.2, 10_000.0
    snr_cell = 10 ** (snr_out_db / 10)
    s_pulse = snr_cell / (G_BORE**2) / ((1 + POLE) / (1 - POLE))
    gen = TargetGenerator(trajectory=static_spec(r, az, el), clutter=False, swerling=0,
                          rcs=1.0, rcs_ref=1.0, snr_ref_range=r,
                          snr_ref_db=10 * math.log10(s_pulse), seed=int(snr_out_db))
    inp = inputs(az, el, gate_start_for(r))
    gen.step(200 * PRI, inp)
    eps = np.empty((2000, 2))
    for i in range(eps.shape[0]):
        beam = gen.step(60 * PRI, inp)["beam"]
        eps[i] = angle_ratios(gate_cells(beam, central_only=True))
    k_m = ANT.slope
    sigma_theory = 1.0 / (k_m * math.sqrt(4.0 * snr_cell))
    sigma_meas = np.std(eps / k_m, axis=0)
    assert np.all(np.abs(sigma_meas / sigma_theory - 1.0) < 0.25), (sigma_meas, sigma_theory)
    assert np.all(np.abs(np.mean(eps, axis=0)) < 4 * sigma_theory * k_m / math.sqrt(2000))


# ---------------------------------------------------------------------------------------------
# Clutter and Swerling
# ---------------------------------------------------------------------------------------------

def _clutter_power_theory(cnr: float, gain2: float, pri: float, spread: float) -> float:
    """E|y|² of AR(1) clutter (power P = CNR·g², lag-1 correlation ρc = e^{−2πBT}) through the
    0-Hz filter h_k = (1 − ρ) ρ^k:  Σ_k Σ_l h_k h_l P ρc^{|k−l|}
    = P (1 − ρ)² (1 + ρ ρc) / ((1 − ρ²)(1 − ρ ρc))."""
    rc = math.exp(-2 * math.pi * spread * pri)
    p = POLE
    return cnr * gain2 * (1 - p) ** 2 * (1 + p * rc) / ((1 - p * p) * (1 - p * rc))


@pytest.mark.parametrize("el_a,gain2", [(0.0, G_BORE**2), (math.radians(15.0), 1e-3)])
def test_clutter_power_spectrum_and_elevation(el_a, gain2):
    """Clutter seen through the beams' gain toward the horizon (boresight on the horizon: the
    crossover gain v(θs)²; antenna 15° up: the −30 dB sidelobe floor). The clutter model
    itself: no MTI canceller."""
    cnr_db = 30.0
    gen = TargetGenerator(rcs=0.0, noise=False, clutter=True, cnr_db=cnr_db, seed=5, mti=0)
    inp = inputs(0.7, el_a)
    gen.step(300 * PRI, inp)
    beams = np.array([gen.step(200 * PRI, inp)["beam"] for _ in range(250)])
    theory = _clutter_power_theory(10 ** (cnr_db / 10), gain2, PRI, 15.0)
    centre = np.mean(beams[:, :, :, 1] ** 2)
    assert centre == pytest.approx(theory, rel=0.12)
    side = np.mean(beams[:, :, :, [0, 2]] ** 2)
    assert side < 0.01 * centre  # ground clutter sits near 0 Hz
    # the same clutter signal in all beams (gains equal here): identical magnitudes
    np.testing.assert_allclose(beams[:, 0], beams[:, 2], rtol=1e-9)


def test_swerling1_rcs_held_per_dwell_exponential():
    dwell = 4
    gen = TargetGenerator(swerling=1, dwell_pulses=dwell, rcs=2.0, seed=3)
    inp = inputs()
    # within a dwell the RCS is constant; it changes at dwell boundaries
    values = [gen.step(PRI, inp)["truth.rcs"] for _ in range(4 * dwell)]
    for d in range(4):
        assert len(set(values[d * dwell:(d + 1) * dwell])) == 1
    assert len({values[d * dwell] for d in range(4)}) == 4
    rcs = np.array([gen.step(dwell * PRI, inp)["truth.rcs"] for _ in range(4000)])
    assert rcs.mean() == pytest.approx(2.0, rel=0.06)  # mean RCS σ
    assert rcs.std() / rcs.mean() == pytest.approx(1.0, rel=0.08)  # exponential: CV = 1
    assert TargetGenerator(swerling=0).step(PRI, inp)["truth.rcs"] == 5.0


# ---------------------------------------------------------------------------------------------
# Truth, time handling, vectorised path
# ---------------------------------------------------------------------------------------------

def test_truth_outputs_consistent():
    gen = TargetGenerator()
    inp = inputs()
    o1 = gen.step(0.5, inp)
    o2 = gen.step(1e-3, inp)
    assert set(OUTPUT_NAMES) | {"beam"} == set(o1)
    r, az, el = cart_to_sph(o1["truth.x"], o1["truth.y"], o1["truth.z"])
    assert (o1["truth.range"], o1["truth.az"], o1["truth.el"]) == pytest.approx((r, az, el))
    assert o1["truth.range_rate"] == pytest.approx(
        (o2["truth.range"] - o1["truth.range"]) / 1e-3, rel=1e-3)
    assert o1["truth.doppler"] == pytest.approx(-2 * o1["truth.range_rate"] / DEFAULT_WAVELENGTH)
    assert o1["truth.apparent_range"] == pytest.approx(o1["truth.range"] % RU)
    assert o1["beam"].shape == (4, 16, 3)


def _truth_at(traj: str, t: float) -> dict:
    """Outputs of a fresh measurement-fidelity generator stepped once to time ``t`` [s]."""
    return TargetGenerator(fidelity="measurement", trajectory=traj).step(t, {})


_LOS = np.array(sph_to_cart(1.0, 0.7, 0.1))  # a unit line-of-sight vector (az 0.7, el 0.1 rad)
RANGE_ACC_CASES = {
    # default closed-loop trajectory: before, inside and after its 3 g turn (16 s to 24 s)
    "turn_before": (None, 10.0),
    "turn_inside": (None, 20.0),
    "turn_after": (None, 30.0),
    # crossing target at constant velocity: ρ̈ = |v⊥|²/ρ > 0 without any acceleration
    "cv_crossing": (json.dumps({"type": "cv", "position": [-3000.0, 2000.0, 500.0],
                                "velocity": [250.0, 30.0, 0.0]}), 9.0),
    # receding radially with an acceleration along the line of sight: ρ̈ = a exactly
    "ca_radial": (json.dumps({"type": "ca", "position": list(1000.0 * _LOS),
                              "velocity": list(250.0 * _LOS),
                              "acceleration": list(20.0 * _LOS)}), 5.0),
}


@pytest.mark.parametrize("case", sorted(RANGE_ACC_CASES))
def test_truth_range_acc_matches_finite_difference(case):
    """truth.range_acc equals the central second difference of truth.range
    (r(t+h) − 2 r(t) + r(t−h))/h², h = 10 ms: truncation O(h² r⁗) and rounding
    ≈ 4 ε r / h² stay far below the 1e-4 m/s² tolerance at these ranges."""
    traj, t = RANGE_ACC_CASES[case]
    traj = traj or TargetGenerator().trajectory
    h = 1e-2
    r_m, r_0, r_p = (_truth_at(traj, tt)["truth.range"] for tt in (t - h, t, t + h))
    fd = (r_p - 2.0 * r_0 + r_m) / (h * h)
    acc = _truth_at(traj, t)["truth.range_acc"]
    assert acc == pytest.approx(fd, abs=1e-4)
    if case == "ca_radial":
        assert acc == pytest.approx(20.0, abs=1e-9)
    if case == "cv_crossing":
        o = _truth_at(traj, t)
        v2 = o["truth.vx"] ** 2 + o["truth.vy"] ** 2 + o["truth.vz"] ** 2
        assert acc == pytest.approx((v2 - o["truth.range_rate"] ** 2) / o["truth.range"])


def test_multi_pulse_step_equals_single_steps_and_counts_pulses():
    """One step of N·pri (vectorised path) = N steps of pri (scalar path), noise, clutter and
    Swerling on, with a maneuvering target and a window folded across Ru."""
    traj = json.dumps({"type": "turn", "position": [3000.0, 14000.0, 900.0],
                       "velocity": [-150.0, -120.0, 5.0], "g": 6})
    kw = {"trajectory": traj, "swerling": 1, "dwell_pulses": 3, "seed": 9}
    inp = inputs(0.21, 0.06, 14_500.0, 700.0)
    a, b = TargetGenerator(**kw), TargetGenerator(**kw)
    for _ in range(7):
        oa = a.step(PRI, inp)
    ob = b.step(7 * PRI, inp)
    np.testing.assert_allclose(ob["beam"], oa["beam"], rtol=1e-7, atol=1e-9)
    assert a._pulse == b._pulse == 7
    # dt not a multiple of pri: round(dt/pri) pulses; dt = 0: no pulse, beams unchanged
    assert b.step(2.4 * PRI, inp) and b._pulse == 9
    before = b.step(0.0, inp)["beam"]
    assert b._pulse == 9
    np.testing.assert_array_equal(before, b.step(0.0, inp)["beam"])


def test_vectorised_geometry_matches_shared_functions():
    gen = TargetGenerator()
    rng = np.random.default_rng(0)
    p = rng.uniform(-2e4, 2e4, (50, 3))
    az_a, el_a = 2.5, 0.4
    r, g = gen._geometry(p, az_a, el_a)
    for i in range(50):
        rr, az, el = cart_to_sph(*p[i])  # the shared scalar functions
        r1, g1 = max(rr, 1.0), ANT.gains(*boresight_offsets(az, el, az_a, el_a))
        assert r[i] == pytest.approx(r1, rel=1e-12)
        np.testing.assert_allclose(g[i], g1, rtol=1e-9, atol=1e-300)
    for el_a in (0.0, 0.3, -0.2, 1.4, 2.0, 3.0):
        lat, elo = boresight_offsets(1.0, 0.0, 1.0, el_a)
        expect = np.maximum(ANT.gains(lat, elo), 10 ** (-30 / 20))
        np.testing.assert_allclose(gen._clutter_gains(el_a), expect, rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# Measurement fidelity
# ---------------------------------------------------------------------------------------------

def test_measurement_fidelity_samples_and_holds():
    gen = TargetGenerator(fidelity="measurement", meas_interval=1.0, meas_sigma_range=0.0,
                          meas_sigma_angle=0.0)
    truth_at = {}
    flags = []
    for k in range(1, 13):  # steps of 0.25 s
        o = gen.step(0.25, {})
        flags.append(o["meas.new"])
        assert np.all(o["beam"] == 0.0) and o["meas.valid"]
        if o["meas.new"]:
            truth_at[round(k * 0.25, 9)] = (o["truth.range"], o["truth.az"], o["truth.el"])
        t_sample = math.floor(k * 0.25 + 1e-9)  # last sample time ≤ t
        if t_sample in truth_at:
            assert (o["meas.range"], o["meas.az"], o["meas.el"]) == pytest.approx(
                truth_at[t_sample], rel=1e-12)
    # first step (t = 0.25) takes the t = 0 sample, then t = 1, 2, 3
    assert flags == [True, False, False, True, False, False, False, True, False, False, False,
                     True]


def test_measurement_noise_statistics():
    gen = TargetGenerator(fidelity="measurement", meas_interval=0.5, meas_sigma_range=100.0,
                          meas_sigma_angle=2e-3, seed=4)
    err = []
    for _ in range(1500):
        o = gen.step(0.5, {})
        assert o["meas.new"]
        err.append((o["meas.range"] - o["truth.range"], o["meas.el"] - o["truth.el"]))
    err = np.array(err)
    np.testing.assert_allclose(err.std(axis=0), [100.0, 2e-3], rtol=0.08)
    assert abs(err[:, 0].mean()) < 4 * 100.0 / math.sqrt(1500)
    assert TargetGenerator(fidelity="measurement").step(1e-3, {})["meas.new"]


# ---------------------------------------------------------------------------------------------
# Determinism and state
# ---------------------------------------------------------------------------------------------

def _run(gen: TargetGenerator, n: int = 20) -> bytes:
    inp = inputs(0.5, 0.1, 12_000.0, 300.0)
    out = b""
    for _ in range(n):
        o = gen.step(PRI, inp)
        out += o["beam"].tobytes() + np.array([o[k] for k in OUTPUT_NAMES]).tobytes()
    return out


def test_same_seed_same_bytes_different_seed_differs():
    kw = {"swerling": 1, "dwell_pulses": 5}
    assert _run(TargetGenerator(seed=1, **kw)) == _run(TargetGenerator(seed=1, **kw))
    assert _run(TargetGenerator(seed=1, **kw)) != _run(TargetGenerator(seed=2, **kw))
    m1 = TargetGenerator(seed=1, fidelity="measurement", meas_interval=1e-4)
    m2 = TargetGenerator(seed=1, fidelity="measurement", meas_interval=1e-4)
    assert _run(m1) == _run(m2)


def test_get_state_set_state_bit_identical():
    gen = TargetGenerator(seed=7, swerling=1, dwell_pulses=3)
    _run(gen, 10)
    state = gen.get_state()
    first = _run(gen, 10)
    gen.set_state(state)
    assert _run(gen, 10) == first
    other = TargetGenerator(seed=99)
    other.set_state(state)
    assert _run(other, 10) == first
    gen.reset()
    assert _run(gen, 10) == _run(TargetGenerator(seed=7, swerling=1, dwell_pulses=3), 10)


# ---------------------------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------------------------

BAD_PARAMS = {
    "seed": -1, "fidelity": "exact", "trajectory": '{"type": "cv"}', "rcs": -1.0,
    "rcs_ref": 0.0, "snr_ref_db": float("nan"), "snr_ref_range": 0.0, "swerling": 2,
    "dwell_pulses": 0, "noise": "maybe", "clutter": 2, "cnr_db": float("inf"),
    "clutter_spread": -1.0, "clutter_sidelobe_db": 1.0, "wavelength": 0.0, "beamwidth": 0.0,
    "squint": 0.0, "doppler_spacing": -5.0, "pole": 1.0, "mti": 3, "mti_max_el": 4.0,
    "mti_hysteresis": -0.1,
    "meas_sigma_range": -1.0,
    "meas_sigma_angle": -1e-3, "meas_interval": 0.0,
}


def test_every_parameter_has_a_validation_case():
    assert set(BAD_PARAMS) == {p.name for p in TargetGenerator.PARAMS}


@pytest.mark.parametrize("name", sorted(BAD_PARAMS))
def test_bad_parameter_raises_naming_it(name):
    with pytest.raises(ValueError, match=name):
        TargetGenerator(**{name: BAD_PARAMS[name]})


def test_trajectory_error_names_key_and_unknown_parameter():
    with pytest.raises(ValueError, match=r"trajectory.*'position'"):
        TargetGenerator(trajectory='{"type": "cv", "velocity": [1, 0, 0]}')
    with pytest.raises(ValueError, match="bogus"):
        TargetGenerator(bogus=1)


@pytest.mark.parametrize("name", sorted(INPUT_NAMES))
@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf"), "x"])
def test_non_finite_input_holds_last_valid_value_and_flags_it(name, value):
    """A bad input is replaced by its last valid value: the run equals one given that value."""
    inp = inputs()
    ref, gen = TargetGenerator(seed=2), TargetGenerator(seed=2)
    ref.step(PRI, inp), gen.step(PRI, inp)
    out_ref = ref.step(PRI, inp)
    out = gen.step(PRI, {**inp, name: value})
    assert out["input.invalid"] and out["input.invalid.count"] == 1
    assert not out_ref["input.invalid"]
    np.testing.assert_array_equal(out["beam"], out_ref["beam"])
    assert not gen.step(PRI, inp)["input.invalid"]  # recovers when the input is valid again


@pytest.mark.parametrize("dt", [float("nan"), float("inf"), -1e-3])
def test_bad_dt_raises(dt):
    with pytest.raises(ValueError, match="dt"):
        TargetGenerator().step(dt, inputs())


def test_pri_shorter_than_window_is_held_and_flagged():
    gen = TargetGenerator()
    assert gen.step(PRI, {**inputs(), "pri": 5e-6})["input.invalid"]  # held, flagged
    assert not gen.step(PRI, {**inputs(), "pri": 8.1e-6})["input.invalid"]  # window fits


# ------------------------------------------------------------------------ MTI canceller
def _mti_filtered_power(psd, pri: float, centre_cycles: float, order: int) -> float:
    """∫ S(ν)·|H_mti(ν)|²·|H_f(ν)|² dν over one PRF (ν in cycles per pulse), S a one-sided
    power spectral density per cycle integrating to the input power: binomial canceller of
    ``order`` with unit white-noise gain, |H_mti|² = (2 sin πν)^(2·order) / C(2·order, order),
    and the one-pole resonator |H_f|² = (1 − ρ)² / |1 − ρ e^{j2π(ν − ν_f)}|²."""
    nu = (np.arange(200_000) + 0.5) / 200_000 - 0.5
    mti = (2.0 * np.sin(np.pi * nu)) ** (2 * order) / math.comb(2 * order, order)
    hf = (1 - POLE) ** 2 / np.abs(1 - POLE * np.exp(2j * np.pi * (nu - centre_cycles))) ** 2
    return float(np.mean(psd(nu) * mti * hf))


@pytest.mark.parametrize("order", [1, 2])
def test_mti_filtered_clutter_and_noise_power_match_the_spectra(order):
    """Boresight on the horizon, CNR 30 dB: the MTI removes the clutter peak from the 0-Hz
    filter (≥ 25 dB less than without), and the powers of clutter and of white noise through
    canceller + filter match the spectral integrals (AR(1) clutter spectrum)."""
    cnr = 10 ** 3.0
    rc = math.exp(-2 * math.pi * 15.0 * PRI)

    def clutter_psd(nu):
        return cnr * G_BORE**2 * (1 - rc * rc) / np.abs(1 - rc * np.exp(-2j * np.pi * nu)) ** 2

    powers = {}
    for mti in (0, order):
        gen = TargetGenerator(rcs=0.0, noise=False, clutter=True, cnr_db=30.0, seed=5, mti=mti)
        inp = inputs(0.7, 0.0)
        gen.step(300 * PRI, inp)
        beams = np.array([gen.step(200 * PRI, inp)["beam"] for _ in range(250)])
        powers[mti] = np.mean(beams[:, :, :, 1] ** 2)
    assert powers[order] < powers[0] * 10 ** -2.5
    assert powers[order] == pytest.approx(_mti_filtered_power(clutter_psd, PRI, 0.0, order),
                                          rel=0.15)
    # antenna at 17°: canceller forced on by its elevation switch set above
    gen = TargetGenerator(rcs=0.0, noise=True, clutter=False, seed=6, mti=order,
                          mti_max_el=0.5)
    inp = inputs(0.7, 0.3)
    gen.step(300 * PRI, inp)
    beams = np.array([gen.step(50 * PRI, inp)["beam"] for _ in range(400)])
    for f, c in ((1, 0.0), (2, 1.0 / 3.0)):
        theory = _mti_filtered_power(lambda nu: np.ones_like(nu), PRI, c, order)
        assert np.mean(beams[:, :, :, f] ** 2) == pytest.approx(theory, rel=0.1)


def test_mti_multi_pulse_step_equals_single_steps():
    kw = {"trajectory": static_spec(14_000.0, 0.21, 0.06), "seed": 9, "mti": 2}
    inp = inputs(0.21, 0.06, 13_500.0, 700.0)
    a, b = TargetGenerator(**kw), TargetGenerator(**kw)
    for _ in range(3):
        b.step(5 * PRI, inp)  # three chunks: the canceller's memory crosses chunk borders
        for _ in range(5):
            oa = a.step(PRI, inp)
    np.testing.assert_allclose(b.outputs()["beam"], oa["beam"], rtol=1e-7, atol=1e-9)


def test_block_drawn_normals_are_the_per_pulse_stream():
    """Issue 14: the one-pulse path draws its normals in blocks; whatever the mix of one-pulse
    and N-pulse steps, pulse k uses normals 162·k … 162·k + 161 of the seeded stream (after
    the 32 of the clutter start), exactly as one draw per pulse would."""
    from axir.models.target_generator import _DRAW_BLOCK, _N_CLUT, _N_DRAW

    gen = TargetGenerator(seed=11)
    ref = np.random.Generator(np.random.PCG64(11))
    ref.standard_normal(_N_CLUT)
    expect = ref.standard_normal((3 * _DRAW_BLOCK + 50, _N_DRAW)) * math.sqrt(0.5)
    u = {"pri": 100e-6}
    for _ in range(5):  # 5 one-pulse steps: rows 0-4 of the first block
        gen.step(100e-6, u)
    got = gen._draws(_DRAW_BLOCK)  # rows 5 … 36: the block's rest, then fresh draws
    assert got.tobytes() == expect[5:5 + _DRAW_BLOCK].tobytes()
    for _ in range(_DRAW_BLOCK + 3):  # one-pulse steps across a block boundary
        gen.step(100e-6, u)
    k = 5 + 2 * _DRAW_BLOCK + 3  # rows used so far
    assert gen._draws(4).tobytes() == expect[k:k + 4].tobytes()


def test_one_pulse_views_follow_the_state_through_copies():
    """Issue 14: the one-pulse path reads its normals through views of the draw block that
    are not part of the state; a deep copy, a set_state into another instance, and a
    mid-block restore continue with the same beams as the original (MTI on: antenna low)."""
    import copy

    u = {"pri": 100e-6, "antenna.el": 0.01, "antenna.az": 0.0, "gate.start": 9_900.0}
    gen = TargetGenerator(seed=4, swerling=1, dwell_pulses=3, mti=2)
    for _ in range(7):  # mid-block: the views exist and point into the current block
        gen.step(100e-6, u)
    assert "_v" not in gen.get_state()
    twin = copy.deepcopy(gen)
    other = TargetGenerator(seed=0)
    other.set_state(gen.get_state())
    ref = [gen.step(100e-6, u)["beam"].tobytes() for _ in range(40)]  # crosses a block
    assert [twin.step(100e-6, u)["beam"].tobytes() for _ in range(40)] == ref
    assert [other.step(100e-6, u)["beam"].tobytes() for _ in range(40)] == ref


def test_hold_inputs_holds_each_bad_input_and_only_it():
    """Issue 14: the all-at-once conversion of radar/hold.py falls back to the per-input rule:
    a NaN, an inf, a non-number and a too-short pri each keep their last valid value."""
    from axir.models.radar.hold import hold_inputs

    defaults = (("a", 1.0), ("b", 2.0), ("pri", 1e-4))
    last = {"a": 10.0, "b": 20.0, "pri": 2e-4}
    floors = {"pri": 8e-6}
    assert hold_inputs({"a": 3, "pri": 5e-5}, last, defaults, floors) == (
        {"a": 3.0, "b": 2.0, "pri": 5e-5}, False)
    for bad in ({"a": math.nan}, {"b": math.inf}, {"a": "x"}, {"pri": 1e-6}):
        u, held = hold_inputs(bad, last, defaults, floors)
        (name,) = bad
        assert held and u[name] == last[name]
        assert all(u[k] == d for k, d in defaults if k != name)


def test_output_mapping_has_every_declared_output_in_order_and_none_left_unset():
    """Round 4 builds the mapping from a template copy (radar/tg_outputs.py): every step's
    mapping holds exactly the declared outputs, in declaration order, none left at the
    template's None, and a fresh dict and beam array per step (callers may keep them)."""
    names = [p.name for p in OUTPUTS]
    for fid in ("frontend", "measurement"):
        gen = TargetGenerator(fidelity=fid, meas_interval=1e-4)
        u = {"antenna.az": 0.1, "antenna.el": 0.05, "gate.start": 9000.0, "pri": 1e-4}
        o1 = gen.step(1e-4, u)
        o2 = gen.step(1e-4, u)
        for o in (gen.outputs(), o1, o2):
            assert list(o) == names
            assert all(v is not None for v in o.values()), fid
        assert o1 is not o2 and o1["beam"] is not o2["beam"]
        assert o2["beam"].shape == (4, 16, 3)


def test_noted_invalid_inputs_flag_one_step_and_survive_a_saved_state() -> None:
    """note_invalid_inputs (the caller replaced out-of-domain inputs) flags input.invalid in
    the coming step only and counts it once; a state saved between the note and the step
    carries the note; the flag of a clean step is False."""
    inp = {"antenna.az": 0.0, "antenna.el": 0.1, "gate.start": 1000.0, "pri": 1e-4}
    g = TargetGenerator(seed=3)
    assert g.step(1e-4, inp)["input.invalid"] is False
    g.note_invalid_inputs(["pri"])
    saved = g.get_state()
    o = g.step(1e-4, inp)
    assert o["input.invalid"] is True and o["input.invalid.count"] == 1
    o = g.step(1e-4, inp)
    assert o["input.invalid"] is False and o["input.invalid.count"] == 1
    h = TargetGenerator(seed=3)
    h.set_state(saved)
    o = h.step(1e-4, inp)
    assert o["input.invalid"] is True and o["input.invalid.count"] == 1
    assert h.step(1e-4, inp)["input.invalid"] is False


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # poles of a 1e308 Hz Doppler centre
def test_step_input_rule_written_out_equals_hold_inputs():
    """Issue 14 (spd13): ``step`` writes out the usual case of the input rule (five finite
    numbers, pri above its floor) and leaves the rest to ``_hold_valid``; on valid, missing,
    non-finite, non-numeric, overflowing and too-short inputs of several types, the inputs
    used, the flag and the count are hold_inputs' (fed the same last valid values)."""
    from axir.models.radar.hold import hold_inputs
    from axir.models.target_generator import _IN_DEFAULTS, _IN_FLOORS

    rng = np.random.default_rng(14)
    kinds = [lambda v: v, lambda v: np.float64(v), lambda v: np.float32(v), lambda v: int(v),
             lambda v: str(v), lambda v: None, lambda v: math.nan, lambda v: -math.inf,
             lambda v: "x", lambda v: 1e308, lambda v: -1e308]
    base = {"antenna.az": 0.1, "antenna.el": 0.05, "gate.start": 9000.0,
            "doppler.centre": 300.0, "pri": 1e-4}
    gen = TargetGenerator(seed=3)
    count = 0
    for k in range(600):
        inp = dict(base)
        for name in base:
            r = rng.random()
            if r < 0.1:
                del inp[name]
            elif r < 0.35:  # (no 1e308 pri: the step would be 1e308 s long)
                inp[name] = kinds[int(rng.integers(len(kinds) - 2 * (name == "pri")))](
                    base[name])
        if k % 7 == 0:
            inp["pri"] = 1e-6  # below the floor
        last = dict(gen._last_u)
        want, bad = hold_inputs(inp, last, _IN_DEFAULTS, _IN_FLOORS)
        if k % 50 == 0:
            gen.note_invalid_inputs(["antenna.az"])
            bad = True
        gen.step(want["pri"], inp)
        count += bad
        assert list(gen._last_u.items()) == list(want.items()), (k, inp)
        assert all(type(v) is float for v in gen._last_u.values())
        assert gen._invalid is bad and gen._invalid_count == count, (k, inp)


def test_one_pulse_test_is_round_of_the_step_ratio():
    """Issue 14 (spd13): ``step`` takes the one-pulse path when dt/pri < 1.5, which is
    max(1, round(dt/pri)) == 1 (round half to even: 1.5 -> 2 pulses, 0.5 -> 1): the pulses
    counted equal max(1, round(dt/pri)) at and around the half-integers."""
    u = {"antenna.az": 0.1, "antenna.el": 0.05, "gate.start": 9000.0, "pri": 1e-4}
    gen = TargetGenerator(seed=1)
    for q in (0.1, 0.5, 1.0, 1.4999999999999998, 1.5, 1.5000000000000002, 2.5, 3.0):
        n0 = gen._pulse
        gen.step(q * 1e-4, u)
        assert gen._pulse - n0 == max(1, round(q * 1e-4 / 1e-4)), q
