"""The four models in the direct loop (models/loop.py, no FMI): acquisition → tentative →
confirmed on the default target, noise-only false-alarm rate of the acquisition threshold
against its design (with and without clutter), and track loss when the target fades.

Geometry of the default trajectory (models/radar/trajectory.py): start (−6000, 12000, 1500) m,
13.5 km, az 333.43°, el 6.38°. Seeded throughout; simulated durations are short (≈ 9000 PRIs
per simulated second at ≈ 75 µs each).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from axir.models.loop import DirectLoop
from axir.models.radar import conventions as radar

X0, Y0, Z0 = -6000.0, 12000.0, 1500.0
R0 = math.sqrt(X0 * X0 + Y0 * Y0 + Z0 * Z0)
AZ0 = math.atan2(X0, Y0) % (2.0 * math.pi)
EL0 = math.atan2(Z0, math.hypot(X0, Y0))


def loop_params(gen: dict | None = None, mgr: dict | None = None) -> dict:
    """The brief's designation: +0.01 rad az, −0.005 rad el, +300 m; pedestal 0.05 rad off."""
    return {
        "TargetGenerator": {"seed": 1, **(gen or {})},
        "Tracker": {"designation_az": AZ0 + 0.01, "designation_el": EL0 - 0.005,
                    "designation_range": R0 + 300.0},
        "Pedestal": {"az0": AZ0 - 0.05, "el0": EL0, "seed": 2},
        "RadarManager": {"designation_range": R0 + 300.0, **(mgr or {})},
    }


def run_until(loop: DirectLoop, t_end: float, stop=None) -> list[tuple[float, int]]:
    """Step to ``t_end`` [s]; returns the (time, mode) transitions (and stops early on
    ``stop(loop)``)."""
    trans: list[tuple[float, int]] = []
    prev = None
    while loop.t < t_end:
        loop.step()
        m = loop.out["RadarManager"]["mode"]
        if m != prev:
            trans.append((loop.t, m))
            prev = m
        if stop is not None and stop(loop):
            break
    return trans


def angle_error(loop: DirectLoop) -> float:
    """Angle [rad] between the antenna boresight and the target line of sight."""
    g, p = loop.out["TargetGenerator"], loop.out["Pedestal"]

    def unit(az: float, el: float) -> np.ndarray:
        return np.array([math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)])

    c = float(unit(g["truth.az"], g["truth.el"]) @ unit(p["az"], p["el"]))
    return math.acos(min(1.0, max(-1.0, c)))


# ----------------------------------------------------------------------- (a) acquire + hold
def test_default_target_acquired_confirmed_and_held():
    loop = DirectLoop.from_params(loop_params())
    trans = run_until(loop, 2.2)  # the pedestal settles from its 2.9° start in ≈ 2 s
    modes = [m for _, m in trans]
    assert modes[0] == radar.ACQUISITION
    # acquisition → tentative → confirmed (a tentative episode may fail back once or twice)
    first_conf = modes.index(radar.CONFIRMED)
    assert radar.TENTATIVE in modes[:first_conf]
    assert modes[first_conf - 1] == radar.TENTATIVE
    t_lock = trans[first_conf][0]
    assert t_lock < 0.3, trans
    # held from lock to the end of the run
    assert modes[-1] == radar.CONFIRMED and len(modes) == first_conf + 1, trans
    g, tr, mg = loop.out["TargetGenerator"], loop.out["Tracker"], loop.out["RadarManager"]
    assert abs(tr["track.range"] - g["truth.range"]) < 2 * radar.BIN_M
    assert mg["ambiguity.resolved"]
    assert abs(mg["range.resolved"] - g["truth.range"]) < 3 * radar.BIN_M
    # pointing error well inside the 2.5° beamwidth once the servo transient is over
    assert angle_error(loop) < math.radians(0.5)


# -------------------------------------------------------------------- (b) noise-only Pfa
PFA = 1e-3
P_DWELL = 1.0 - (1.0 - PFA) ** (radar.N_BINS * radar.N_DOPPLER)  # 48 cells tested per dwell


def acquisition_false_alarms(clutter: bool, n_dwells: int, seed: int
                             ) -> tuple[int, int, float, float]:
    """Target removed (rcs = 0), antenna on the target's direction (el 6.4°: clutter through
    the −30 dB sidelobe floor, 0 dB per pulse per beam, in the 0 Hz filter of every bin).
    Returns (false alarms, acquisition dwells, fraction of PRIs spent in acquisition, mean
    tentative PRIs per false alarm)."""
    p = loop_params(gen={"rcs": 0.0, "clutter": clutter, "seed": seed},
                    mgr={"pfa_acq": PFA, "designation_range": R0})
    p["Tracker"].update(designation_az=AZ0, designation_el=EL0, designation_range=R0)
    p["Pedestal"].update(az0=AZ0)
    loop = DirectLoop.from_params(p)
    fa = n = in_acq = in_tent = 0
    prev = radar.ACQUISITION
    while n < n_dwells:
        loop.step()
        o = loop.out["RadarManager"]
        assert o["mode"] != radar.CONFIRMED
        if prev == radar.ACQUISITION and o["dwell.done"]:
            n += 1
            fa += bool(o["detection"])
        in_acq += prev == radar.ACQUISITION
        in_tent += prev == radar.TENTATIVE
        prev = o["mode"]
    return fa, n, in_acq / loop.steps, in_tent / max(fa, 1)


def test_noise_only_false_alarm_rate_matches_design():
    """Thermal noise only: the exact dwell-sum law (manager.dwell_sum_factors) puts the
    per-dwell false-alarm rate on the design value (binomial 99.9 % interval; measured
    67/1500 = 4.5 % for a design of 4.7 % with seed 3)."""
    fa, n, acq, episode = acquisition_false_alarms(False, 1200, seed=3)
    lo, hi = stats.binom.interval(0.999, n, P_DWELL)
    assert lo <= fa <= hi, (fa, n, n * P_DWELL)
    # each false alarm costs a short tentative episode (< 50 ms), back to acquisition: ≈ 2
    # passes over the first PRI's ≈ 3 windows of 63 PRIs. Measured (tentative PRIs per false
    # alarm, seeds 3-5): main at a85474c 368-397, with the Doppler peak search 385-408; with
    # clutter (next test, seeds 3-4) 361-367 and 378-452. Not the share of time in
    # acquisition (> 0.8 before): it follows the number of false alarms (main, seed 5: 0.77)
    assert episode < 500, (fa, episode, acq)


def test_clutter_false_alarm_rate_near_design():
    """Default clutter (CNR 30 dB, −30 dB sidelobes): the 0 Hz filter is clutter-dominated
    (≈ 1 look per cell) and gets the one-look threshold, which is conservative for it (measured
    99.9 % quantile 3.03 × median vs 3.16 for one Rayleigh look); the two thermal filters are
    at design. Tolerance: above the binomial 99.9 % lower bound of half the design rate, below
    the upper bound of the design rate (measured 45/1500 = 3.0 % for a design of 4.7 %)."""
    fa, n, acq, episode = acquisition_false_alarms(True, 1200, seed=3)
    lo = stats.binom.ppf(0.0005, n, 0.5 * P_DWELL)
    hi = stats.binom.ppf(0.9995, n, P_DWELL)
    assert lo <= fa <= hi, (fa, n, n * P_DWELL)
    assert episode < 500, (fa, episode, acq)


# ------------------------------------------------------------------------------ (c) fade
def test_track_lost_after_miss_limit_when_target_fades():
    """Confirm, then make the target vanish: the generator's rcs is set to 0 mid-run
    (``gen.rcs = 0; gen._check()`` recomputes the radar-equation amplitude without resetting
    the state). The manager drops to acquisition after ``miss_limit`` missed confirmed
    dwells and searches around the last track range."""
    miss_limit = 4
    loop = DirectLoop.from_params(loop_params(mgr={"miss_limit": miss_limit}))
    run_until(loop, 0.5, stop=lambda lp: lp.out["RadarManager"]["mode"] == radar.CONFIRMED)
    assert loop.out["RadarManager"]["mode"] == radar.CONFIRMED
    run_until(loop, loop.t + 0.05)
    assert loop.out["RadarManager"]["mode"] == radar.CONFIRMED
    loop.gen.rcs = 0.0
    loop.gen._check()
    t_fade, steps0 = loop.t, loop.steps
    last_range = loop.out["Tracker"]["track.range"]
    run_until(loop, t_fade + 0.1,
              stop=lambda lp: lp.out["RadarManager"]["mode"] != radar.CONFIRMED)
    o = loop.out["RadarManager"]
    assert o["mode"] == radar.ACQUISITION
    # a confirmed dwell: dwell_conf PRIs after the Doppler dither's settling PRIs
    dwell = loop.mgr.dwell_conf + (loop.mgr.doppler_dither_settle
                                   if loop.mgr.doppler_dither_fraction > 0.0 else 0)
    # miss_limit missed dwells (the dwell in progress at the fade may still hold a hit, and
    # the Doppler filters ring for a few PRIs)
    assert (miss_limit - 1) * dwell < loop.steps - steps0 <= (miss_limit + 1) * dwell + 10
    ru = radar.unambiguous_range(o["pri"])
    centre = o["gate.command"] + 6 * radar.BIN_M
    assert centre == pytest.approx(round(last_range / radar.BIN_M) * radar.BIN_M % ru,
                                   abs=2 * radar.BIN_M)
