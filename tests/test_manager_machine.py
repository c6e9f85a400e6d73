"""RadarManager state machine (models/manager/machine.py) on the synthetic scene of
tests/manager_scene.py: acquisition → tentative → confirmed, gate search, track loss, bandwidth
and gain schedules, parameter validation, declared ports, non-finite inputs, state round trip."""

from __future__ import annotations

import math

import numpy as np
import pytest
from manager_scene import LAM, Scene, make, run  # noqa: F401

from axir.models.manager import INPUTS, OUTPUTS, RadarManager
from axir.models.manager import ambiguity as amb
from axir.models.radar import conventions as radar


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


def test_acquisition_steps_the_gate_across_the_search_window():
    mgr = make(designation_range=37_000.0, search_extent=1_800.0, search_step_bins=12,
               acq_pri_cycle=False)
    scene = Scene(37_000.0, seed=5)
    scene.present = False
    outs = run(mgr, scene, 400)
    ru = amb.unambiguous_range_m(200)
    centre = round(37_000.0 / 75.0) * 75.0 % ru  # designation snapped to the 75 m grid
    gates = sorted({o["gate.command"] + 6 * 75.0 for o in outs})  # window centres (bin 7)
    # 24 bins of extent / 12-bin steps → windows at 0, ±12, ±24 bins around the designation
    assert np.allclose(gates, sorted(centre + np.array([-24, -12, 0, 12, 24]) * 75.0))
    assert all(o["range.offset"] == 0.0 for o in outs)


def test_acquisition_cycles_the_pri_from_one_pass_to_the_next():
    """PRI staggering (issue 11): each pass over the 5 windows uses the next PRI
    (acq_all_pri_windows = 0: one PRI per pass)."""
    mgr = make(designation_range=37_000.0, search_extent=1_800.0, search_step_bins=12,
               acq_all_pri_windows=0)
    scene = Scene(37_000.0, seed=5)
    scene.present = False
    outs = run(mgr, scene, 400)
    pris = [outs[i - 1]["pri"] for i, o in enumerate(outs) if o["dwell.done"] and i]
    ks = [round(p / amb.pri_seconds(1)) for p in pris]
    assert ks[:15] == [200] * 5 + [211] * 5 + [223] * 5


def test_acquisition_searches_the_designation_window_at_the_three_pris_first():
    """Default acq_all_pri_windows = 1 (issue 11, radar6): each pass begins with the window on
    the designation at the pass' PRI then at the two others, then the 4 other windows at the
    pass' PRI; the pass' PRI cycles. The centre window's gate is the designated range folded
    at each PRI."""
    mgr = make(designation_range=37_000.0, search_extent=1_800.0, search_step_bins=12)
    scene = Scene(37_000.0, seed=5)
    scene.present = False
    outs = run(mgr, scene, 600)
    done = [outs[i - 1] for i, o in enumerate(outs) if o["dwell.done"] and i]
    ks = [round(o["pri"] / amb.pri_seconds(1)) for o in done]
    assert ks[:21] == ([200, 211, 223] + [200] * 4 + [211, 223, 200] + [211] * 4
                       + [223, 200, 211] + [223] * 4)
    for o, k in zip(done[:3], (200, 211, 223), strict=True):
        centre = round(37_000.0 / 75.0) % k * 75.0
        assert o["gate.command"] + 6 * 75.0 == centre


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
    noise_before = mgr.get_state()["_noise_pos"].copy()
    phi_before = mgr.get_state()["_spread_pos"].copy()
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
    assert np.array_equal(st["_noise_pos"], noise_before, equal_nan=True)
    assert np.array_equal(st["_spread_pos"], phi_before)
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


@pytest.mark.parametrize("bad", [None, math.nan, math.inf, -math.inf])
def test_one_nonfinite_sample_makes_its_dwell_a_miss(bad):
    """A confirmed dwell with one NaN/±inf cell in one of its samples is a miss, and the next
    dwell (finite samples) sees the target again; None: no bad sample, no miss (the scene's
    reference). The finiteness is tested on the dwell's accumulated sum (session 17)."""
    mgr = make(miss_limit=3, dwell_conf=16)
    scene = Scene(37_000.0, seed=72)
    run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    run(mgr, scene, 200, until=lambda o: mgr._dwell_done and mgr._track.misses == 0)
    injected = []

    def poison(i: int, outs: list) -> dict:
        dw = mgr._dwell
        if bad is None or injected or dw.settle or dw.n_seen != 5:
            return {}
        s = scene.inputs()["sum"].copy()
        s[3, 1] = bad
        injected.append(i)
        return {"sum": s}

    misses = []
    for _ in range(100):
        run(mgr, scene, 1, extra=poison)
        if mgr._dwell_done:
            misses.append(mgr._track.misses)
            if len(misses) == 2:
                break
    assert misses == ([0, 0] if bad is None else [1, 0])
    assert mgr.mode == radar.CONFIRMED
    assert bad is None or len(injected) == 1


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




def test_read_sum_fast_path_matches_general_rule() -> None:
    """Issue 14: a float64 (16, 3) array is taken as it is; every other form through the
    general rule, with the same values and the same rejections (non-finite, overflowing sum)."""
    from axir.models.manager.ports import read_sum

    a = np.random.default_rng(14).rayleigh(size=(16, 3))
    assert read_sum(a) is a
    for other in (a.astype(">f8"), a.ravel().tolist(), a.reshape(48), a.astype(np.float32)):
        got = read_sum(other)
        assert got is not None and got.shape == (16, 3)
        assert np.array_equal(got, np.asarray(other, dtype=np.float64).reshape(16, 3))
    with np.errstate(over="ignore"):  # 48 × 1e307 overflows the sum: rejected
        for bad in (np.full((16, 3), np.inf), np.full((16, 3), np.nan),
                    np.full((16, 3), 1e307)):
            assert read_sum(bad) is None
            assert read_sum(bad.tolist()) is None
    assert read_sum(np.zeros((3, 16))) is not None  # 48 values: reshaped, as before
    assert read_sum(np.zeros((4, 16))) is None


def test_step_common_path_equals_per_input_rule() -> None:
    """Issue 14: the all-numbers fast screening of the scalar inputs gives the same outputs as
    the per-input rule (forced here by leaving ``maneuver`` out: held False, as 0.0 gives)."""
    rng = np.random.default_rng(7)
    a, b = RadarManager(), RadarManager()
    for i in range(400):
        s = rng.rayleigh(size=(16, 3))
        common = {"sum": s, "track.range": 20_000.0 + i, "track.range_rate": -3.0}
        oa = a.step(a.pri, {**common, "maneuver": False})
        ob = b.step(b.pri, common)
        assert oa.keys() == ob.keys()
        for k in oa:
            assert oa[k] == ob[k] or (oa[k] != oa[k] and ob[k] != ob[k]), k


def test_step_screening_by_one_sum_equals_the_one_by_one_rule() -> None:
    """Issue 14, round 7: the common path screens dt, track.range, track.range_rate and
    maneuver with one isfinite of their sum. Finite values whose sum overflows (each one
    ±1e308) and a NaN/±inf in any position give the outputs of the one-by-one rule (forced in
    the twin by leaving ``maneuver`` out: held, as the value last given)."""
    rng = np.random.default_rng(8)
    a, b = RadarManager(), RadarManager()
    a.step(a.pri, {"track.range": 2e4, "track.range_rate": -3.0, "maneuver": 1.0})
    b.step(b.pri, {"track.range": 2e4, "track.range_rate": -3.0, "maneuver": 1.0})
    specials = [1e308, -1e308, math.nan, math.inf, -math.inf]
    for i in range(600):
        vals = [float(a.pri), 20_000.0 + i, -3.0, 1.0]
        for _ in range(int(rng.integers(0, 3))):
            vals[int(rng.integers(1, 4))] = float(rng.choice(specials))
        if i % 50 == 0:
            vals[0] = float(rng.choice(specials))
        s = rng.rayleigh(size=(16, 3))
        common = {"sum": s, "track.range": vals[1], "track.range_rate": vals[2]}
        oa = a.step(vals[0], {**common, "maneuver": vals[3]})
        ob = b.step(vals[0], common if vals[3] == 1.0 else {**common, "maneuver": vals[3]})
        assert repr(oa) == repr(ob), i
    assert repr(a.get_state()) == repr(b.get_state())


def _plausible_round6(mgr: RadarManager, rng: float | None) -> bool:
    """RadarManager._plausible as it was before issue 14's round 7 wrote it into ``step`` (the
    reference): range inside [0, max_range], anchored speed, range rate once settled; records
    the anchor and the last plausible range."""
    from axir.models.manager.machine import ANCHOR_MARGIN_M, ANCHOR_PERIOD

    tr = mgr._track
    if rng is None:
        return True
    if not (0.0 <= rng <= mgr.max_range):
        return False
    age = tr.conf_time - tr.anchor_time
    if abs(rng - tr.anchor_range) > mgr.max_speed * age + ANCHOR_MARGIN_M:
        return False
    if tr.conf_time >= mgr.doppler_track_delay and abs(tr.last_rate) > mgr.max_speed:
        return False
    if age >= ANCHOR_PERIOD:
        tr.anchor_range, tr.anchor_time = rng, tr.conf_time
    tr.good_range = rng
    return True


def test_step_plausibility_written_out_equals_the_former_method() -> None:
    """Issue 14, round 7: the confirmed-track plausibility test is written out in ``step``. From
    a confirmed manager, with random anchors, ages, rates and track ranges (inside, outside
    [0, max_range], just within and beyond the anchored speed, NaN/absent: held), one step
    leaves the track record, the gate and the mode where the former ``_plausible`` (then
    ``_drop_track`` when it failed) leaves them."""
    import copy

    mgr = make()
    scene = Scene(37_000.0, seed=11)
    run(mgr, scene, 3000, until=lambda o: o["mode"] == radar.CONFIRMED)
    assert mgr.mode == radar.CONFIRMED
    base = copy.deepcopy(mgr)
    rng = np.random.default_rng(12)
    dropped = kept = anchored = 0
    for k in range(400):
        m = copy.deepcopy(base)
        tr = m._track
        tr.anchor_range = float(rng.uniform(1e3, m.max_range))
        tr.conf_time = float(rng.uniform(0.0, 3.0))
        tr.anchor_time = float(rng.uniform(0.0, tr.conf_time))
        age = tr.conf_time + 1e-4 - tr.anchor_time  # the step adds dt = 1e-4 first
        reach = m.max_speed * age + 3 * radar.BIN_M
        r = float(rng.choice([tr.anchor_range + reach * rng.uniform(-1.5, 1.5),
                              tr.anchor_range + reach * rng.uniform(-0.999, 0.999),
                              -5.0, m.max_range * 1.01, math.nan]))
        rate = float(rng.choice([-3.0, 2.0 * m.max_speed, -1.5 * m.max_speed]))
        ref = copy.deepcopy(m)
        m.step(1e-4, {"track.range": r, "track.range_rate": rate, "maneuver": False})
        # the reference: the same step's first part by hand, then the former method
        rt = ref._track
        rr = r if math.isfinite(r) else None
        if rr is not None:
            rt.last_range = rr
        rt.last_rate = rate
        rt.since_maneuver += 1e-4
        rt.conf_time += 1e-4
        before = (rt.anchor_range, rt.anchor_time)
        if not _plausible_round6(ref, rr):
            ref._drop_track()
            dropped += 1
        elif rr is not None:
            ref._gate = rr - ref._offset
            kept += 1
            anchored += (rt.anchor_range, rt.anchor_time) != before
        got = (m.mode, m._gate, tr.anchor_range, tr.anchor_time, tr.good_range)
        want = (ref.mode, ref._gate, rt.anchor_range, rt.anchor_time, rt.good_range)
        assert repr(got) == repr(want), k
    assert dropped > 50 and kept > 50 and anchored > 10


def test_step_sum_common_case_equals_read_sum() -> None:
    """Issue 14, round 7: ``step`` takes a float64 (16, 3) SUM as ``read_sum`` does (its common
    case written out). A twin fed the same SUMs as nested lists (``read_sum``'s general path)
    gives the same outputs and final state, with NaN, ±inf and overflowing (48 × 1e307) SUMs
    and float32 arrays among them, from acquisition to confirmed tracking."""
    a, b = make(), make()
    sa, sb = Scene(37_000.0, seed=5), Scene(37_000.0, seed=5)
    bad = [np.full((16, 3), np.nan), np.full((16, 3), np.inf), np.full((16, 3), 1e307)]
    modes = set()
    with np.errstate(over="ignore"):
        for i in range(2500):
            ia, ib = sa.inputs(), sb.inputs()
            if i % 97 == 13:
                ia["sum"] = bad[i % 3].copy()
            elif i % 89 == 7:
                ia["sum"] = ia["sum"].astype(np.float32)
            ib["sum"] = ia["sum"].tolist()
            pa = sa.prev["pri"] if sa.prev else amb.pri_seconds(200)
            pb = sb.prev["pri"] if sb.prev else amb.pri_seconds(200)
            oa, ob = a.step(pa, ia), b.step(pb, ib)
            assert repr(oa) == repr(ob), i
            sa.prev, sb.prev = oa, ob
            sa.t += pa
            sb.t += pb
            modes.add(oa["mode"])
    assert repr(a.get_state()) == repr(b.get_state())
    assert radar.CONFIRMED in modes and radar.ACQUISITION in modes
