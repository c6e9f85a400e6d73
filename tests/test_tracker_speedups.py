"""The per-PRI shortcuts of issue 14 compute what the plain forms compute, bit for bit.

- ``cells.background_sum`` (Python floats) equals numpy's sum of the background bins;
- ``alphabeta.update_axes`` with the schedule and Q shared across axes equals each axis
  updated on its own, also when the axes do not share (other n, other steady gains);
- ``deviations.gate_cells`` equals the slice-and-sum it replaces.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from axir.models.filters.alphabeta import AlphaBetaAxis, update_axes
from axir.models.filters.base import FilterConfig
from axir.models.tracker.cells import _BACKGROUND_BINS, background_sum
from axir.models.tracker.deviations import gate_cells


def test_background_sum_is_numpys_sum_bit_for_bit() -> None:
    rng = np.random.default_rng(14)
    for k in range(20000):
        scale = 10.0 ** rng.uniform(-8, 40)
        col = rng.exponential(scale, 16) if k % 2 else rng.random(16) * scale
        if k % 97 == 0:
            col[rng.integers(16)] = 0.0
        want = float(col[_BACKGROUND_BINS].sum())
        got = background_sum(col.tolist())
        assert got == want, (k, got, want)
    nan_col = np.ones(16)
    nan_col[10] = math.nan
    assert math.isnan(background_sum(nan_col.tolist()))
    # the gate bins 5-8 (0-based 4-8) never enter
    col = np.zeros(16)
    col[4:9] = 1e9
    assert background_sum(col.tolist()) == 0.0


def _state(f: AlphaBetaAxis) -> tuple:
    return (f.n, f.pos, f.vel, f.p11, f.p12, f.p22, f.alpha, f.beta, f.evolutive, f._steady)


@pytest.mark.parametrize("steady", [(0.0, 0.0), (0.02, 2e-4), (0.3, 0.05), (1.5, 2.0)])
def test_update_axes_equals_axis_by_axis(steady: tuple[float, float]) -> None:
    rng = np.random.default_rng(3)
    cfg = FilterConfig(sigma_m=5.0, n_max=0)
    shared = [AlphaBetaAxis(cfg) for _ in range(3)]
    alone = [AlphaBetaAxis(cfg) for _ in range(3)]
    for f in shared + alone:
        f.detect = False
    T = 1e-3
    for k in range(300):
        zs = tuple(float(v) for v in rng.normal(1000.0, 5.0, 3))
        rs = tuple(float(v) for v in rng.uniform(1.0, 50.0, 3))
        if k == 150:  # one axis restarts: the axes stop sharing n
            shared[1].reset()
            alone[1].reset()
        update_axes(shared, zs, T, rs, steady=steady)
        for f, z, r in zip(alone, zs, rs, strict=True):
            f.set_steady_gains(*steady)
            f.update(z, T, r)
        for a, b in zip(shared, alone, strict=True):
            assert _state(a) == _state(b)
    assert shared[0].n == 300 and shared[1].n == 150


def test_update_axes_with_different_steady_gains_per_axis() -> None:
    cfg = FilterConfig()
    shared = [AlphaBetaAxis(cfg) for _ in range(3)]
    alone = [AlphaBetaAxis(cfg) for _ in range(3)]
    gains = [(0.5, 0.1), (0.02, 2e-4), (0.0, 0.0)]
    for axes in (shared, alone):
        for f, g in zip(axes, gains, strict=True):
            f.set_steady_gains(*g)
    for k in range(60):
        zs = (float(k), 2.0 * k, -1.0 * k)
        update_axes(shared, zs, 0.1, (1.0, 1.0, 1.0))
        for f, z in zip(alone, zs, strict=True):
            f.update(z, 0.1, 1.0)
    for a, b in zip(shared, alone, strict=True):
        assert _state(a) == _state(b)
    assert shared[0].alpha == 0.5 and shared[2].alpha < 0.5  # the schedules did differ


@pytest.mark.parametrize("central_only", [True, False])
def test_gate_cells_is_the_slice_and_sum(central_only: bool) -> None:
    beams = np.random.default_rng(5).exponential(3.0, (4, 16, 3))
    cells = beams[:, 5:8, :]
    want = cells[:, :, 1] if central_only else cells.sum(axis=2)
    assert np.array_equal(gate_cells(beams, central_only), want)


def test_outputs_flat_fills_a_fresh_mapping_in_port_order() -> None:
    """outputs_flat (a copy of a template filled in place, issue 14 round 2): every output
    name of ports.OUTPUTS in that order, the values it was given, and no state shared between
    two calls or with the template."""
    from axir.models.tracker.outputs import _TEMPLATE, outputs_dict, outputs_flat
    from axir.models.tracker.ports import OUTPUTS

    sums = np.arange(48.0).reshape(16, 3)
    vals = [float(k) + 0.5 for k in range(33)]
    a = outputs_flat(sums, *vals[:26], (1.0, 2.0, 3.0, True), *vals[26:])
    assert list(a) == [p.name for p in OUTPUTS] == list(_TEMPLATE)
    assert a["sum"] is sums and a["dev.az"] == 0.5 and a["track.P_vv"] == vals[32]
    assert (a["ddre.range"], a["ddre.valid"]) == (1.0, True)
    b = outputs_dict(sums, 1.0, 2.0, 3.0, 4.0, (5.0, 6.0, 7.0), (8.0, 9.0, 10.0), 11.0, 12.0,
                     13.0, 14.0, 15.0, 16.0, 17.0, True, 18.0, 19.0, 20, True, False,
                     (21.0, 22.0, 23.0), (24.0, 25.0, 26.0, False))
    assert a["dev.az"] == 0.5 and b is not a and set(_TEMPLATE.values()) == {0.0}
    assert [b[p.name] for p in OUTPUTS][1:] == [
        1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 16.0,
        17.0, True, 18.0, 19.0, 20, True, False, 21.0, 22.0, 23.0, 24.0, 25.0, 26.0, False,
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("confirmed", [False, True])
def test_step_deviations_and_first_position_equal_the_helpers(confirmed: bool) -> None:
    """The linear-law ratios, the early/late ratio and the measured position are written out
    in BeamTracker.step (issue 14, round 3): on random beams they equal, bit for bit,
    dif_sum/early_late of the gate cells and sph_to_cart + sph_to_cart_diff of the gate-centre
    range and the pedestal angles (the first update initialises the filters at the measurement,
    so track.x/y/z is that measurement). The plain early/late ratio: range_noise_correction off."""
    from axir.models.radar.conventions import BIN_M
    from axir.models.radar.geometry import sph_to_cart, sph_to_cart_diff
    from axir.models.tracker import Tracker
    from axir.models.tracker.deviations import dif_sum, early_late
    from axir.models.tracker.outputs import GATE_CENTRE_M

    rng = np.random.default_rng(21)
    for _ in range(200):
        beams = rng.exponential(1.0, (4, 16, 3))
        beams[:, 5:8, :] += rng.uniform(20.0, 60.0, (4, 3, 3))  # a strong gate signal
        az, el = rng.uniform(0.0, 6.28), rng.uniform(-0.3, 1.2)
        gate, offset = rng.uniform(1e3, 2e4), rng.uniform(0.0, 3e3)
        trk = Tracker(monopulse_law="linear", gate_latency=1, range_noise_correction=False,
                      beam_background=0.0)  # the helpers' raw cells (session 29's rule off)
        o = trk.step(1e-4, {"beam": beams, "ped.az": az, "ped.el": el, "mode": 2 if confirmed
                            else 1, "range.offset": offset, "gate.command": gate})
        cells = (beams[:, 5:8, 1] if confirmed else beams[:, 5:8, :].sum(axis=2)).tolist()
        s = [u + r + d + lo for u, r, d, lo in zip(*cells, strict=True)]
        k = trk.core.inv_slope
        # the strongest gate cell (random floats: no ties)
        i = max(range(3), key=s.__getitem__)
        u, r, d, lo = cells[0][i], cells[1][i], cells[2][i], cells[3][i]
        dev_el, dev_lat = dif_sum(u, d) * k, dif_sum(r, lo) * k
        dev_r = early_late(*s) * BIN_M
        dev_az = dev_lat / math.cos(el)
        assert (o["dev.el"], o["dev.lat"], o["dev.range"], o["dev.az"]) == (
            dev_el, dev_lat, dev_r, dev_az)
        rho = gate + GATE_CENTRE_M + offset
        xa = sph_to_cart(rho, az, el)
        dx = sph_to_cart_diff(rho, az, el, dev_r, dev_az, dev_el)
        assert (o["track.x"], o["track.y"], o["track.z"]) == tuple(
            a + b for a, b in zip(xa, dx, strict=True))


def test_update_axes_q_reused_only_for_the_same_sigma_and_step() -> None:
    """update_axes keeps the last Q (issue 14, round 3): with the step and the scale changing
    from call to call, and a second filter with another σm in between, every covariance equals
    the documented recursion computed here from scratch: ΦPΦᵀ + Q with Q = q_cwna(σm², T)
    (seed 002 eqs. 4, 7), then the Joseph form with K = [α, β/T]."""
    from axir.models.filters.kalman import q_cwna

    rng = np.random.default_rng(8)
    fa, fb = AlphaBetaAxis(FilterConfig(sigma_m=5.0)), AlphaBetaAxis(FilterConfig(sigma_m=0.5))
    ref = {id(fa): None, id(fb): None}
    for k in range(400):
        T = (1e-4, 2.5e-4, 1e-4, 1e-3)[k % 4]
        s = 1.0 if k % 3 else 2.0
        for f in (fa, fb) if k % 2 else (fb, fa):
            r = float(rng.uniform(1.0, 9.0))
            p = ref[id(f)]
            f.update(float(rng.normal(100.0, 3.0)), T, r, s)
            if p is None:
                ref[id(f)] = (r, 0.0, 0.0)
                continue
            q11, q12, q22 = q_cwna((s * f.cfg.sigma_m) ** 2, T)
            a, bt = f.alpha, f.beta / T
            m12 = p[1] + T * p[2]
            m11 = p[0] + T * (p[1] + m12) + q11
            m12, m22 = m12 + q12, p[2] + q22
            ref[id(f)] = ((1.0 - a) ** 2 * m11 + a * a * r,
                          (1.0 - a) * (m12 - bt * m11) + a * bt * r,
                          m22 - 2.0 * bt * m12 + bt * bt * (m11 + r))
            assert (f.p11, f.p12, f.p22) == pytest.approx(ref[id(f)], rel=1e-12, abs=0.0)
    assert fa.n == fb.n == 400


def test_sum_column_equals_the_gate_cells_python_sum_bit_for_bit() -> None:
    """BeamTracker.step reads the confirmed gate cells' SUMs from the SUM output's central
    column (issue 14, round 4) instead of adding the four beams in Python: numpy's reduction
    over the beam axis must give u + r + d + l, in that order, bit for bit — for C- and
    Fortran-ordered inputs, with signs and magnitudes that make the order matter."""
    rng = np.random.default_rng(14)
    for k in range(3000):
        beams = rng.normal(0.0, 1.0, (4, 16, 3)) * 10.0 ** rng.uniform(-8, 8, (4, 16, 3))
        if k % 2:
            beams = np.asfortranarray(beams)
        col = np.add.reduce(beams, 0)[:, 1].tolist()
        u, r, d, lo = (beams[i, :, 1].tolist() for i in range(4))
        want = [((a + b) + c) + e for a, b, c, e in zip(u, r, d, lo, strict=True)]
        assert [v.hex() for v in col] == [v.hex() for v in want]


def _full_state(f: AlphaBetaAxis) -> str:
    """Every field of the axis and of its detector, floats by their bits (NaN compares)."""
    def bits(v: object) -> object:
        return float(v).hex() if isinstance(v, float) else v
    fmd = f.fmd
    return repr((tuple(bits(v) for v in _state(f)), bits(f.alpha_ss), bits(f.beta_ss),
                 bits(fmd.L), fmd.flag, bits(fmd.A)))


@pytest.mark.parametrize("flat,prior", [(False, False), (True, False), (True, True)])
@pytest.mark.parametrize("n_max", [0, 7])
@pytest.mark.parametrize("detect", [False, True])
def test_update_axes_three_axes_written_out_equals_the_loop_bit_for_bit(
        n_max: int, detect: bool, flat: bool, prior: bool, monkeypatch) -> None:
    """update_axes' written-out path for three axes that share config, n and the steady-gain
    tuple with the manager's gains given (the Tracker's X, Y, Z, issue 14 round 7) leaves every
    axis (and its detector) and returns the innovations exactly as the general loop does
    (one-axis calls: AlphaBetaAxis.update): random measurements, variances, steps, scales,
    steady gains that switch between unusable, below, above and equal to the evolutive ones
    (the evolutive → steady hand-over and back, β first or α first; the uncapped gain law is
    written out there, the capped one calls scheduled_gains), NaN/inf inputs, restarts of one
    axis (the axes stop sharing n: the loop) and of all three. ``flat``: the Tracker's call,
    update_xyz with the arguments flat (issue 14, round 8), the same. ``prior``: per-axis
    velocity priors (``vel_prior_r``, the Tracker's ``velocity_prior_axes``): the axes reach
    their steady gains at different PRIs and enter the written-out path by value once all three
    hold them (``steady_all``, session 28), the same."""
    import axir.models.filters.alphabeta as ab

    loop3 = [0]  # the three-axis calls that took the general loop (not the written-out path)
    loop = ab._update_loop

    def counted(axes: Any, *args: Any) -> Any:
        loop3[0] += len(axes) == 3
        return loop(axes, *args)

    monkeypatch.setattr(ab, "_update_loop", counted)
    rng = np.random.default_rng(77)
    cfg = (FilterConfig(sigma_m=3.0, n_max=n_max, vel_prior_k=56.25 / 600.0**2,
                        vel_prior_r=56.25) if prior else FilterConfig(sigma_m=3.0, n_max=n_max))
    fast = [AlphaBetaAxis(cfg) for _ in range(3)]
    slow = [AlphaBetaAxis(cfg) for _ in range(3)]
    for f in fast + slow:
        f.detect = detect
    choices = [(0.0, 0.0), (0.02, 2e-4), (0.3, 0.05), (0.9, 0.5), (1.5, 2.0), (math.nan, 0.1),
               (0.05, math.inf), (2.5, 0.1), (0.5, 0.01)]  # the last: α steady before β
    steady = choices[0]
    taken = 0
    calls = 0
    for k in range(4000):
        if k % 37 == 0:
            steady = choices[int(rng.integers(len(choices)))]
        if k % 500 == 0 and k:
            for axes in (fast, slow):
                for f in axes:
                    f.reset()
                    f.detect = detect
        if k % 500 == 450:  # one axis restarts: the loop until all three restart
            fast[2].reset()
            slow[2].reset()
            fast[2].detect = slow[2].detect = detect
        T = float(rng.choice([1e-4, 2.5e-4, 1e-3, 0.1]))
        s = float(rng.choice([1.0, 1.0, 0.5, 2.0]))
        zs = [float(v) for v in rng.normal(1e4, 30.0, 3)]
        rs = [float(v) for v in rng.uniform(0.5, 900.0, 3)]
        if k % 401 == 3:
            zs[int(rng.integers(3))] = float(rng.choice([math.nan, math.inf, -math.inf]))
        if k % 313 == 5:
            rs[int(rng.integers(3))] = math.nan
        same_n = fast[0].n and fast[1].n == fast[0].n == fast[2].n
        shared = same_n and (
            ab.steady_all(fast[0]._steady, fast[1]._steady, fast[2]._steady, *steady) if prior
            else fast[1]._steady is fast[0]._steady is fast[2]._steady)
        taken += bool(shared)
        calls += 1
        if flat:
            got = ab.update_xyz(*fast, *zs, T, *rs, *steady, s)
            assert type(got) is tuple and len(got) == 3
        else:
            got = update_axes(fast, tuple(zs), T, tuple(rs), s, steady=steady)
        want = []
        for f, z, r in zip(slow, zs, rs, strict=True):
            f.set_steady_gains(*steady)
            want.append(f.update(z, T, r, s))
        assert [float(v).hex() for v in got] == [float(v).hex() for v in want], k
        for a, b in zip(fast, slow, strict=True):
            assert _full_state(a) == _full_state(b), k
    # the written-out path ran, on exactly the key predicted above (counted by the calls that
    # did not reach the general loop)
    assert calls - loop3[0] == taken
    assert taken > (0.15 if prior else 0.8) * calls, taken / calls
    assert ab._q_last[1] in (1e-4, 2.5e-4, 1e-3, 0.1)
