"""Doppler centre and discriminator (models/manager/doppler.py): folded track Doppler,
resonator gain against the filter recursion, profile inversion, the 3 g turn held."""

from __future__ import annotations

import math

import numpy as np
import pytest
from manager_scene import LAM, Scene, make, run

from axir.models.radar import conventions as radar


# ------------------------------------------------------------------------------------ Doppler
@pytest.mark.parametrize("rdot", [-150.0, 240.0, -700.0])
def test_doppler_centre_is_folded_track_doppler(rdot):
    mgr = make(doppler_track_delay=0.01)
    scene = Scene(37_000.0, rdot=rdot, seed=61)
    pre = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert pre[-1]["mode"] == radar.CONFIRMED
    # pole 0 (no selectivity): one Doppler step, the search centre 0 until the range and the
    # Doppler are resolved; then the centre is the resolved Doppler
    resolved = next(i for i, o in enumerate(pre) if o["ambiguity.resolved"])
    assert all(o["doppler.centre"] == 0.0 for o in pre[:resolved])
    pri = pre[-1]["pri"]
    prf = 1.0 / pri
    fd = radar.fold_doppler(-2.0 * rdot / LAM, pri)
    coarse = pre[-1]["doppler.centre"]  # the resolved Doppler folded at the kept PRI
    # (pole 0: each PRI's measurement is a filter centre, ±PRF/6; the least-squares
    # candidate is within one filter spacing)
    assert abs(radar.fold_doppler(coarse - fd, pri)) <= prf / 3.0
    conf = run(mgr, scene, 400)
    assert all(o["mode"] == radar.CONFIRMED for o in conf)
    assert conf[-1]["doppler.centre"] == pytest.approx(fd, abs=1e-6)
    assert -0.5 * prf <= conf[-1]["doppler.centre"] < 0.5 * prf


# ------------------------------------------------------------------ Doppler discriminator
def _resonator_steady_amplitude(offset_cycles: float, pole: float, n: int = 400) -> float:
    """|y| after n pulses of the recursion y ← ρ·y + (1 − ρ)·x, x = e^{j2πδk} (the generator's
    filter in the frame of its centre), simulated pulse by pulse."""
    y = 0j
    for k in range(n):
        y = pole * y + (1.0 - pole) * np.exp(2j * np.pi * offset_cycles * k)
    return abs(y)


@pytest.mark.parametrize("delta", [-0.47, -0.3, -0.12, 0.0, 0.05, 0.21, 0.4])
def test_resonator_gain_matches_the_filter_recursion(delta):
    from axir.models.manager.doppler import resonator_gain

    assert resonator_gain(delta, 0.9) == pytest.approx(
        _resonator_steady_amplitude(delta, 0.9), rel=1e-9)


@pytest.mark.parametrize("pole", [0.8, 0.9, 0.95])
def test_doppler_offset_inverts_the_three_filter_profile(pole):
    from axir.models.manager.doppler import doppler_offset

    spacing = 1.0 / 3.0
    rng = np.random.default_rng(7)
    for delta in rng.uniform(-spacing / 2, spacing / 2, 40):  # the searched interval
        prof = [_resonator_steady_amplitude(delta - (f - 1) * spacing, pole) for f in range(3)]
        scale = rng.uniform(0.1, 100.0)  # unknown target amplitude
        d = doppler_offset(scale * np.array(prof), spacing, pole)
        err = (d - delta + 0.5) % 1.0 - 0.5
        # half the 1/720-PRF search grid (≤ 7 Hz at 10 kHz PRF; filter half-width ≈ 170 Hz)
        assert abs(err) < 0.5 / 720.0, (delta, d)


def _turn_loop(mgr: dict, trk: dict | None = None) -> tuple[list[int], np.ndarray]:
    """Closed loop (direct models) on the default aircraft with its 3 g left turn moved to
    3-6 s (radial acceleration up to ≈ 26 m/s²); designation and pedestal on the target.
    Returns the modes after the first lock and |truth Doppler − doppler.centre| [Hz] in
    confirmed mode after the tracker's steady gains took over (t > 1.5 s)."""
    import json

    from axir.models.radar.trajectory import DEFAULT_TRAJECTORY_SPEC

    spec = dict(DEFAULT_TRAJECTORY_SPEC)
    spec["segments"] = [{"type": "cv", "onset": 0.0},
                        {"type": "turn", "g": 3.0, "direction": "left", "onset": 3.0,
                         "duration": 3.0}]
    r0 = math.sqrt(6000.0**2 + 12000.0**2 + 1500.0**2)
    az0 = math.atan2(-6000.0, 12000.0) % (2 * math.pi)
    el0 = math.atan2(1500.0, math.hypot(6000.0, 12000.0))
    from axir.models.loop import DirectLoop

    loop = DirectLoop.from_params({
        "TargetGenerator": {"seed": 3, "rcs": 5.0, "trajectory": json.dumps(spec)},
        "Tracker": {"designation_az": az0, "designation_el": el0, "designation_range": r0,
                    **(trk or {})},
        "Pedestal": {"az0": az0, "el0": el0, "seed": 4},
        "RadarManager": {"designation_range": r0, **mgr},
    })
    modes, offs, locked = [], [], False
    while loop.t < 6.0:
        loop.step()
        m, g = loop.out["RadarManager"], loop.out["TargetGenerator"]
        locked = locked or m["mode"] == radar.CONFIRMED
        if locked:
            modes.append(int(m["mode"]))
        if m["mode"] == radar.CONFIRMED and loop.t > 1.5 and loop.steps % 20 == 0:
            prf = 1.0 / m["pri"]
            fd = -2.0 * g["truth.range_rate"] / radar.DEFAULT_WAVELENGTH
            offs.append(abs((fd - m["doppler.centre"] + 0.5 * prf) % prf - 0.5 * prf))
    return modes, np.array(offs)


def test_track_held_through_a_3g_turn_with_the_doppler_discriminator():
    """Regression of the default scenario's track drops in the turn: the track range rate lags
    under radial acceleration, so a Doppler centre computed from it alone slides the target
    out of the central filter (3 dB half-width ≈ 170 Hz at ρ = 0.9, 10 kHz PRF) and the
    confirmed track is lost (miss_limit). With the discriminator's bias the track is held."""
    modes, _ = _turn_loop({})
    assert modes and all(m == radar.CONFIRMED for m in modes), "track dropped"
    # the same seeded run with the centre from the track range rate only drops the track:
    # the check above can fail for the defect (with the plain early/late ratio: the noise
    # correction of issue 11 round 3 makes the track range rate good enough to hold this run
    # without the discriminator; so does the ≈ 0.25 s memory of the session-6 tracking index
    # σ_n = 1 m, σ_m = 30 m/s²: the control run keeps the former index, 15 m and 5 m/s²; and
    # session 25's miss_limit of 10 dwells holds it too: the control keeps the former 5)
    modes0, _ = _turn_loop({"doppler_loop_gain": 0.0, "sigma_meas": 15.0, "sigma_man": 5.0,
                            "miss_limit": 5},
                           {"range_noise_correction": False, "n_max": 0})
    assert any(m != radar.CONFIRMED for m in modes0)


# ------------------------------------------------------ dithered centre filter (radar6)
@pytest.mark.parametrize("pole", [0.8, 0.9])
def test_dither_offset_inverts_the_displaced_filter_ratio(pole):
    """The amplitude ratio of the centre filter displaced by +Δ and −Δ (steady amplitudes of
    the filter recursion, simulated pulse by pulse) gives back the target's offset δ where
    the ratio is monotonic in δ (±0.0177·PRF at ρ = 0.9, about the 3 dB half-width),
    whatever the target amplitude."""
    from axir.models.manager.doppler_track import dither_offset

    dither = 0.006
    rng = np.random.default_rng(11)
    for delta in rng.uniform(-0.017, 0.017, 20):
        scale = rng.uniform(0.1, 100.0)
        a_plus = scale * _resonator_steady_amplitude(delta - dither, pole)
        a_minus = scale * _resonator_steady_amplitude(delta + dither, pole)
        d = dither_offset(a_plus / a_minus, dither, pole)
        assert abs(d - delta) < 2e-4, (delta, d)  # 2 Hz at a 10 kHz PRF


def test_dither_offset_has_the_sign_of_the_offset_beyond_the_main_lobe():
    """Far off the centre the ratio tends back to 1: the inversion is clamped where it stops
    being monotonic, so it keeps the right sign (the loop moves the centre toward the
    target, never away)."""
    from axir.models.manager.doppler_track import dither_offset

    for delta in (0.08, 0.12, -0.08, -0.12):
        a_plus = _resonator_steady_amplitude(delta - 0.006, 0.9)
        a_minus = _resonator_steady_amplitude(delta + 0.006, 0.9)
        assert np.sign(dither_offset(a_plus / a_minus, 0.006, 0.9)) == np.sign(delta)
