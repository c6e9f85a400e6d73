"""RadarManager (models/manager.py) driven by synthetic SUM arrays built here.

The test scene plays the TargetGenerator + Tracker: noise is four Rayleigh beam magnitudes per
cell and PRI (seeded generator), a target is four Rice magnitudes (per-beam SNR chosen) in the
range bins around its apparent range R mod Ru (triangular 75 m response, radar.py convention:
bin r samples gate_start + (r − 1)·75 m, window at apparent delay gate_start mod Ru) and in the
Doppler filter nearest to its folded Doppler. Commands reach the scene one step late (co-simulation
lag). Gate convention of models/tracker.py: ``gate.command`` is the gate start (bin 1); in modes
0-1 the tracker gates there, in mode 2 the scene is a perfect tracker: gate start = true range −
range.offset − 6·75 m, track.range = truth. The test noise is independent from PRI to PRI, so
the manager is built with ``doppler_pole = 0``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from axir.models.manager import INPUTS, OUTPUTS, RadarManager
from axir.models.manager import ambiguity as amb
from axir.models.manager.thresholds import (
    dwell_sum_looks,
    envelope_correlation,
    rayleigh_sum_factors,
)
from axir.models.radar import conventions as radar

LAM = radar.DEFAULT_WAVELENGTH


class Scene:
    """Synthetic generator + tracker around one target (true range r0 + rdot·t)."""

    def __init__(self, r0: float, rdot: float = -150.0, snr_db: float = 6.0, seed: int = 0):
        self.r0, self.rdot = r0, rdot
        self.amp = math.sqrt(2.0 * 10.0 ** (snr_db / 10.0))  # σ = 1 per quadrature → E|n|² = 2
        self.rng = np.random.default_rng(seed)
        self.t = 0.0
        self.prev: dict | None = None
        self.present = True
        self.bins = np.arange(radar.N_BINS) * radar.BIN_M

    def truth(self) -> float:
        return self.r0 + self.rdot * self.t

    def sum_array(self, gate_start: float, pri: float, dc: float) -> np.ndarray:
        ru = radar.unambiguous_range(pri)
        a = radar.apparent_range(self.truth(), pri)
        delta = (gate_start + self.bins - a + 0.5 * ru) % ru - 0.5 * ru
        tri = np.clip(1.0 - np.abs(delta) / radar.BIN_M, 0.0, None)
        prf = 1.0 / pri
        fd = radar.fold_doppler(radar.doppler_hz(self.rdot, LAM), pri)
        centres = dc + (np.arange(3) - 1) * prf / 3.0
        df = np.abs((fd - centres + 0.5 * prf) % prf - 0.5 * prf)
        mask = (df == df.min()).astype(float)
        s = (self.amp * self.present) * tri[:, None] * mask[None, :]
        n = self.rng.standard_normal((2, 4, radar.N_BINS, 3))
        return np.abs(s[None] + n[0] + 1j * n[1]).sum(axis=0)

    def inputs(self) -> dict:
        o = self.prev
        if o is None:
            pri, gate, dc, mode, off = amb.pri_seconds(200), 0.0, 0.0, 0, 0.0
        else:
            pri, gate, dc = o["pri"], o["gate.command"], o["doppler.centre"]
            mode, off = o["mode"], o["range.offset"]
        gs = gate  # modes 0-1: the tracker gates on gate.command (range of bin 1)
        if mode == radar.CONFIRMED:  # perfect tracker gates on its (true) track
            gs = radar.gate_start_for(self.truth() - off)
        return {
            "sum": self.sum_array(gs, pri, dc),
            "gate.start": gs,
            "track.range": self.truth(),
            "track.range_rate": self.rdot,
            "maneuver": False,
        }


def run(mgr: RadarManager, scene: Scene, n: int, until=None, extra=None) -> list[dict]:
    outs = []
    for _ in range(n):
        inp = scene.inputs()
        if extra:
            inp.update(extra(len(outs), outs))
        pri = scene.prev["pri"] if scene.prev else amb.pri_seconds(200)
        o = mgr.step(pri, inp)
        scene.prev = o
        scene.t += pri
        outs.append(o)
        if until is not None and until(o):
            break
    return outs


def make(**kw) -> RadarManager:
    base = {"designation_range": 37_000.0, "search_extent": 3_000.0, "doppler_pole": 0.0,
            "latency_pris": 2}
    base.update(kw)
    return RadarManager(**base)


# ------------------------------------------------------------------------ acquisition → confirmed
@pytest.mark.parametrize(
    ("r0", "designation", "seed"),
    [
        (37_000.0, 37_000.0, 1),   # 2.5 Ru
        (52_310.0, 51_000.0, 2),   # 3.5 Ru, designation 1.3 km off
        (4_020.0, 3_000.0, 3),     # first Ru
        (120_500.0, 120_000.0, 4),  # 8 Ru
        (45_010.0, 45_000.0, 5),   # apparent ≈ 0 at PRI 1 (eclipse margin → other PRI kept)
    ],
)
def test_acquisition_tentative_confirmed_with_resolved_range(r0, designation, seed):
    mgr = make(designation_range=designation)
    scene = Scene(r0, seed=seed)
    outs = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    modes = [o["mode"] for o in outs]
    assert modes[-1] == radar.CONFIRMED, f"not confirmed after {len(outs)} PRIs"
    assert modes[0] == radar.ACQUISITION
    first_t = modes.index(radar.TENTATIVE)
    assert radar.CONFIRMED not in modes[:first_t]
    o = outs[-1]
    truth = scene.truth()
    assert o["ambiguity.resolved"]
    assert abs(o["range.resolved"] - truth) <= 1.5 * radar.BIN_M
    ru = radar.unambiguous_range(o["pri"])
    n = o["range.offset"] / ru
    assert n == pytest.approx(round(n), abs=1e-9)  # offset is N·Ru of the current PRI
    centre = o["gate.command"] + 6 * radar.BIN_M  # bin 7
    assert abs(centre + o["range.offset"] - truth) <= 1.5 * radar.BIN_M
    assert 0.0 <= centre < ru + radar.BIN_M
    assert any(o["pri"] == pytest.approx(amb.pri_seconds(k)) for k in amb.DEFAULT_PRI_BINS)
    # tentative used the three PRIs
    pris = {round(x["pri"] * 1e9) for x in outs if x["mode"] == radar.TENTATIVE}
    assert len(pris) == 3
    # the kept PRI keeps the target away from the eclipse at 0 / Ru
    assert min(centre, ru - centre) > 5 * radar.BIN_M


def test_range_offset_consistent_while_tentative():
    """Every tentative window: gate.command + range.offset is a candidate true range and the
    offset is N·Ru of the PRI then in force."""
    mgr = make()
    scene = Scene(37_000.0, seed=11)
    outs = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    tent = [o for o in outs if o["mode"] == radar.TENTATIVE]
    assert tent
    for o in tent:
        ru = radar.unambiguous_range(o["pri"])
        n = o["range.offset"] / ru
        assert n == pytest.approx(round(n), abs=1e-9) and n >= 0


# ------------------------------------------------------------------------------- noise only
def noise_only_run(adaptive: bool, seed: int) -> tuple[int, int, list[dict]]:
    pfa = 1e-3
    mgr = make(pfa_acq=pfa, dwell_acq=8, latency_pris=1, noise_avg_dwells=32.0,
               adaptive_looks=adaptive)
    scene = Scene(37_000.0, seed=seed)
    scene.present = False
    outs = run(mgr, scene, 24_000)
    prev_mode = [radar.ACQUISITION] + [o["mode"] for o in outs[:-1]]
    acq_dwells = [o for o, pm in zip(outs, prev_mode, strict=True)
                  if pm == radar.ACQUISITION and o["dwell.done"]]
    return sum(o["detection"] for o in acq_dwells), len(acq_dwells), outs


def test_noise_only_false_alarm_rate_adaptive_looks_within_bounds():
    """With the effective looks estimated from the data (default), the false-alarm rate stays
    within a factor of the design (measured ≈ 0.5× here: the spread estimate is biased high)."""
    fa, n, outs = noise_only_run(True, 22)
    p_dwell = 1.0 - (1.0 - 1e-3) ** 48
    assert 0.2 * n * p_dwell <= fa <= 2.0 * n * p_dwell, (fa, n * p_dwell)
    assert not any(o["mode"] == radar.CONFIRMED for o in outs)


def test_noise_only_false_alarm_rate_matches_design_pfa():
    """Threshold design: with the exact noise model (adaptive_looks off) the acquisition
    false-alarm rate matches the design Pfa (binomial 99.9 % interval)."""
    pfa = 1e-3
    fa, n, outs = noise_only_run(False, 21)
    p_dwell = 1.0 - (1.0 - pfa) ** 48  # 48 independent cells tested per dwell
    lo, hi = stats.binom.interval(0.999, n, p_dwell)
    assert n > 1500
    assert lo <= fa <= hi, (fa, n, n * p_dwell)
    modes = np.array([o["mode"] for o in outs])
    assert not np.any(modes == radar.CONFIRMED)
    # each false alarm costs a short tentative episode (≈ 2 × (settle + dwell) PRIs) that ends
    # back in acquisition: ≈ 85 % of the time is spent searching at this (high) Pfa
    assert np.mean(modes == radar.ACQUISITION) > 0.75


def test_acquisition_steps_the_gate_across_the_search_window():
    mgr = make(designation_range=37_000.0, search_extent=1_800.0, search_step_bins=12)
    scene = Scene(37_000.0, seed=5)
    scene.present = False
    outs = run(mgr, scene, 400)
    ru = amb.unambiguous_range_m(200)
    centre = round(37_000.0 / 75.0) * 75.0 % ru  # designation snapped to the 75 m grid
    gates = sorted({o["gate.command"] + 6 * 75.0 for o in outs})  # window centres (bin 7)
    # 24 bins of extent / 12-bin steps → windows at 0, ±12, ±24 bins around the designation
    assert np.allclose(gates, sorted(centre + np.array([-24, -12, 0, 12, 24]) * 75.0))
    assert all(o["range.offset"] == 0.0 for o in outs)


# ------------------------------------------------------------------------------ track loss
def test_track_lost_after_miss_limit_dwells():
    mgr = make(miss_limit=4, dwell_conf=16)
    scene = Scene(37_000.0, seed=31)
    outs = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert outs[-1]["mode"] == radar.CONFIRMED
    held = run(mgr, scene, 400)
    assert all(o["mode"] == radar.CONFIRMED for o in held)  # strong target is held
    scene.present = False
    faded = run(mgr, scene, 400, until=lambda o: o["mode"] != radar.CONFIRMED)
    assert faded[-1]["mode"] == radar.ACQUISITION
    # lost after exactly miss_limit missed dwells (± the dwell in progress at the fade)
    assert 3 * 16 < len(faded) <= 5 * 16
    # the new search is centred on the last track range
    ru = amb.unambiguous_range_m(200)
    assert faded[-1]["gate.command"] + 6 * 75.0 == pytest.approx(
        round(scene.truth() / 75.0) * 75.0 % ru, abs=76.0)


# ------------------------------------------------------------------------ bandwidth schedule
def test_bandwidth_decreases_monotonically_to_floor_in_confirmed():
    mgr = make(bw_start=6.0, bw_floor=1.5, bw_decay_time=0.1)
    scene = Scene(37_000.0, seed=41)
    pre = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert all(o["bandwidth"] == 6.0 for o in pre[:-1])
    conf = run(mgr, scene, 1500)
    assert all(o["mode"] == radar.CONFIRMED for o in conf)
    bw = np.array([pre[-1]["bandwidth"]] + [o["bandwidth"] for o in conf])
    assert np.all(np.diff(bw) <= 0.0)
    assert bw[0] == 6.0 and bw[1] < bw[0]  # starts from bw_start at the transition
    assert bw[-1] == 1.5 and np.all(bw >= 1.5)
    t_floor = np.argmax(bw == 1.5) * conf[0]["pri"]
    assert t_floor == pytest.approx(0.1, abs=2 * conf[0]["pri"])


# --------------------------------------------------------------------------------- α-β gains
def kalata_reference(lam: float) -> tuple[float, float]:
    """Kalata (1984) as written in the brief: r = (4 + Λ − √(8Λ + Λ²))/4, α = 1 − r²,
    β = 2(2 − α) − 4√(1 − α)."""
    r = (4.0 + lam - math.sqrt(8.0 * lam + lam * lam)) / 4.0
    a = 1.0 - r * r
    return a, 2.0 * (2.0 - a) - 4.0 * math.sqrt(1.0 - a)


def test_steady_gains_follow_kalata_and_open_during_maneuver():
    hold = 0.02
    mgr = make(sigma_man=50.0, sigma_man_high=800.0, sigma_meas=1.0, maneuver_hold=hold)
    scene = Scene(37_000.0, seed=51)
    pre = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert pre[-1]["mode"] == radar.CONFIRMED
    # modes 0-1: 0 → the tracker runs its evolutive gains
    assert all(o["alpha"] == 0.0 and o["beta"] == 0.0 for o in pre[:-1])
    T = pre[-1]["pri"]
    lam_lo, lam_hi = 50.0 * T * T / 1.0, 800.0 * T * T / 1.0
    a_lo, b_lo = kalata_reference(lam_lo)
    a_hi, b_hi = kalata_reference(lam_hi)
    conf = [pre[-1], *run(mgr, scene, 200)]
    for o in conf:
        assert o["tracking.index"] == pytest.approx(lam_lo, rel=1e-12)
        assert o["alpha"] == pytest.approx(a_lo, rel=1e-9)
        assert o["beta"] == pytest.approx(b_lo, rel=1e-6)
        # Kalata's steady-state relation Λ = β/√(1 − α)
        assert o["beta"] / math.sqrt(1.0 - o["alpha"]) == pytest.approx(lam_lo, rel=1e-9)
    # maneuver opens the gains
    man = run(mgr, scene, 50, extra=lambda i, o: {"maneuver": True})
    assert a_hi > 3 * a_lo
    for o in man:
        assert o["alpha"] == pytest.approx(a_hi, rel=1e-9)
        assert o["beta"] == pytest.approx(b_hi, rel=1e-6)
    # ... which stay open for maneuver_hold, then close
    after = run(mgr, scene, int(2 * hold / T))
    t = np.arange(1, len(after) + 1) * T
    a = np.array([o["alpha"] for o in after])
    assert np.allclose(a[t < hold - 2 * T], a_hi, rtol=1e-9)
    assert np.allclose(a[t > hold + 2 * T], a_lo, rtol=1e-9)
    # gains back to 0 when the track is lost
    scene.present = False
    lost = run(mgr, scene, 400, until=lambda o: o["mode"] == radar.ACQUISITION)
    assert lost[-1]["mode"] == radar.ACQUISITION
    assert lost[-1]["alpha"] == 0.0 and lost[-1]["beta"] == 0.0


# ------------------------------------------------------------------------------------ Doppler
@pytest.mark.parametrize("rdot", [-150.0, 240.0, -700.0])
def test_doppler_centre_is_folded_track_doppler(rdot):
    mgr = make(doppler_track_delay=0.01)
    scene = Scene(37_000.0, rdot=rdot, seed=61)
    pre = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert pre[-1]["mode"] == radar.CONFIRMED
    assert all(o["doppler.centre"] == 0.0 for o in pre[:-1])
    pri = pre[-1]["pri"]
    prf = 1.0 / pri
    fd = radar.fold_doppler(-2.0 * rdot / LAM, pri)
    coarse = pre[-1]["doppler.centre"]  # the filter that held the target in tentative
    assert coarse == pytest.approx(radar.fold_doppler(round(fd / (prf / 3)) * prf / 3, pri))
    conf = run(mgr, scene, 400)
    assert all(o["mode"] == radar.CONFIRMED for o in conf)
    assert conf[-1]["doppler.centre"] == pytest.approx(fd, abs=1e-6)
    assert -0.5 * prf <= conf[-1]["doppler.centre"] < 0.5 * prf


# ---------------------------------------------------------------------------- validation
@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"nonsense": 1}, "unknown parameter"),
        ({"pfa_acq": 0.0}, "pfa_acq"),
        ({"pfa_track": 0.5}, "pfa_track"),
        ({"dwell_acq": 0}, "dwell_acq"),
        ({"dwell_acq": 2.5}, "dwell_acq"),
        ({"bw_start": 1.0, "bw_floor": 2.0}, "bw_floor"),
        ({"confirm_m": 5, "confirm_n": 4}, "confirm_m"),
        ({"pri2_bins": 200}, "must differ"),
        ({"pri1_bins": 200, "pri2_bins": 400, "pri3_bins": 600}, "ambiguous"),
        ({"designation_range": 200_000.0}, "designation_range"),
        ({"sigma_man": 30.0, "sigma_man_high": 20.0}, "sigma_man_high"),
        ({"acq_pri_index": 4}, "acq_pri_index"),
        ({"wavelength": float("nan")}, "wavelength"),
    ],
)
def test_parameter_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        RadarManager(**kw)


def test_threshold_factors_match_rayleigh_statistics():
    # one look: Rayleigh quantile √(−2 ln Pfa), median √(2 ln 2), mean √(π/2)
    q = math.sqrt(-2.0 * math.log(1e-4))
    c_med, c_mean = rayleigh_sum_factors(1, 1e-4)
    assert c_med == pytest.approx(q / math.sqrt(2.0 * math.log(2.0)), rel=1e-3)
    assert c_mean == pytest.approx(q / math.sqrt(math.pi / 2.0), rel=1e-3)
    # 16 looks: Monte Carlo tail at the computed threshold
    rng = np.random.default_rng(7)
    x = rng.rayleigh(size=(400_000, 16)).sum(axis=1)
    c_med, c_mean = rayleigh_sum_factors(16, 1e-3)
    for th in (c_med * np.median(x), c_mean * 16 * math.sqrt(math.pi / 2)):
        p = np.mean(x > th)
        lo, hi = stats.binom.interval(0.999, x.size, 1e-3)
        assert lo / x.size <= p <= hi / x.size


def test_dwell_sum_looks_and_settling():
    # exact moments: an uncorrelated dwell (pole 0) keeps all looks_per_pri·K looks; one PRI
    # keeps the beams; a faster filter (smaller pole) decorrelates the PRIs more
    assert dwell_sum_looks(4, 16, 0.0) == 64
    assert dwell_sum_looks(4, 1, 0.9) == 4
    assert dwell_sum_looks(4, 16, 0.5) > dwell_sum_looks(4, 16, 0.9) > 4
    assert envelope_correlation(0.0) == pytest.approx(0.0, abs=1e-12)
    assert envelope_correlation(1.0) == pytest.approx(1.0)
    m = RadarManager(doppler_pole=0.9, latency_pris=3, settle_db=40.0)
    assert m.get_state()["_settle_pris"] == 3 + 44  # 0.9**44 < 10**(-40/20) < 0.9**43
    assert RadarManager(doppler_pole=0.0, latency_pris=3).get_state()["_settle_pris"] == 3


def test_declared_inputs_outputs_match_step():
    mgr = make()
    o = mgr.step(1e-4, {"sum": np.ones((16, 3))})
    assert [p.name for p in OUTPUTS] == list(o)
    assert {p.name for p in INPUTS} == {"sum", "gate.start", "track.range", "track.range_rate",
                                        "maneuver"}
    names = {p.name for p in RadarManager.PARAMS}
    assert {"pri1_bins", "pfa_acq", "bw_floor", "sigma_man_high", "wavelength"} <= names
    assert RadarManager().wavelength == radar.DEFAULT_WAVELENGTH


# -------------------------------------------------------------------------------- NaN path
def test_nan_inputs_never_crash_nor_corrupt_state():
    mgr = make()
    scene = Scene(37_000.0, seed=71)
    run(mgr, scene, 40)
    noise_before = mgr.get_state()["_noise_f"].copy()
    phi_before = mgr.get_state()["_spread"].copy()
    bad_inputs = [
        {"sum": np.full((16, 3), np.nan)},
        {"sum": np.full((16, 3), np.inf)},
        {"sum": np.zeros((5, 3))},
        {"sum": "garbage"},
        {"sum": None, "gate.start": float("nan")},
        {"gate.start": float("inf")},
        {"sum": np.full((16, 3), np.nan), "track.range": float("nan"),
         "track.range_rate": float("inf"), "maneuver": float("nan")},
    ]
    for bad in bad_inputs:
        for _ in range(40):
            inp = scene.inputs()
            inp.update(bad)
            o = mgr.step(float("nan"), inp)
            scene.prev = o
            scene.t += o["pri"]
            assert not o["detection"]
            for key in ("pri", "alpha", "beta", "bandwidth", "range.offset", "gate.command",
                        "doppler.centre"):
                assert math.isfinite(o[key]), key
    # only misses: the tentative track (the target was detected in the first 40 PRIs) fails
    nan_sum = {"sum": np.full((16, 3), np.nan)}
    tail = run(mgr, scene, 5000, until=lambda o: o["mode"] == radar.ACQUISITION,
               extra=lambda i, o: nan_sum)
    assert tail[-1]["mode"] == radar.ACQUISITION
    assert not any(o["detection"] for o in tail)
    st = mgr.get_state()
    assert np.all(np.isfinite(st["_dwell"].acc))
    assert np.array_equal(st["_noise_f"], noise_before)
    assert np.array_equal(st["_spread"], phi_before)
    # ... and the manager still acquires and confirms afterwards
    outs = run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert outs[-1]["mode"] == radar.CONFIRMED


def test_nan_sum_in_confirmed_counts_as_misses():
    mgr = make(miss_limit=3, dwell_conf=16)
    scene = Scene(37_000.0, seed=72)
    run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    outs = run(mgr, scene, 200, until=lambda o: o["mode"] != radar.CONFIRMED,
               extra=lambda i, o: {"sum": np.full((16, 3), np.nan)})
    assert outs[-1]["mode"] == radar.ACQUISITION
    assert 2 * 16 < len(outs) <= 4 * 16


# ------------------------------------------------------------------------ state round trip
def test_get_state_set_state_round_trip_is_bit_identical():
    mgr = make()
    scene = Scene(37_000.0, seed=81)
    run(mgr, scene, 10)  # in acquisition
    state = mgr.get_state()
    inputs = []
    for _ in range(600):
        inp = scene.inputs()
        inputs.append(inp)
        o = mgr.step(scene.prev["pri"], inp)
        scene.prev = o
        scene.t += o["pri"]
    other = RadarManager()
    other.set_state(state)
    replay = [other.step(1e-4, i_) for i_ in inputs]
    mgr.set_state(state)
    again = [mgr.step(1e-4, i_) for i_ in inputs]
    assert repr(replay) == repr(again)  # bit-identical, NaN-safe
    modes = {o["mode"] for o in replay}
    assert len(modes) >= 2  # the replay crosses a mode change


# ---------------------------------------------------------------------------- performance
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


def _turn_loop(mgr: dict) -> tuple[list[int], np.ndarray]:
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
        "Tracker": {"designation_az": az0, "designation_el": el0, "designation_range": r0},
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
    # the check above can fail for the defect
    modes0, _ = _turn_loop({"doppler_loop_gain": 0.0})
    assert any(m != radar.CONFIRMED for m in modes0)
