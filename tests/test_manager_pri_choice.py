"""The PRI kept for M of N / confirmed tracking by predicted canceller loss (issue 11, low11;
models/manager/pri_choice.py, docs/clutter.md "M of N and confirmed tracking off the notch")."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from axir.models.manager import RadarManager
from axir.models.manager.pri_choice import (
    MIN_MARGIN_BINS,
    choose_confirm_pri,
    eclipse_margin,
    predicted_loss_db,
)
from axir.models.radar import conventions as radar
from axir.orchestrator.envelope import run_cell
from axir.orchestrator.envelope_run import ANCHOR

_D = RadarManager.defaults()
KS = [_D["pri1_bins"], _D["pri2_bins"], _D["pri3_bins"]]
PRIS = [k * radar.BIN_S for k in KS]


def test_two_pulse_canceller_loss_by_hand():
    # |H|² = (2 sin πν)²/2: ν = 1/4 → 1 (0 dB), ν = 1/2 → 2 (−3.01 dB), ν = 1/12 → 0.134
    pri = 1e-4
    assert predicted_loss_db(0.25 / pri, pri, 1) == pytest.approx(0.0, abs=1e-9)
    assert predicted_loss_db(0.5 / pri, pri, 1) == pytest.approx(-10 * math.log10(2.0))
    assert predicted_loss_db(-0.5 / pri, pri, 1) == pytest.approx(-10 * math.log10(2.0))
    exp = -10 * math.log10(2.0 * math.sin(math.pi / 12) ** 2)  # 8.73 dB
    assert predicted_loss_db(1.0 / (12 * pri), pri, 1) == pytest.approx(exp)
    assert predicted_loss_db(1.0 / (12 * pri), pri, 0) == 0.0


def test_eclipse_margin():
    assert eclipse_margin(205, 200) == 5
    assert eclipse_margin(395, 200) == 5
    assert eclipse_margin(300, 200) == 100


def _bin_with_margins() -> int:
    """A true range bin with an eclipse margin ≥ MIN_MARGIN_BINS at every PRI."""
    for b in range(2000, 4000):
        if min(eclipse_margin(b, k) for k in KS) >= MIN_MARGIN_BINS + 5:
            return b
    raise AssertionError("no such bin")


def test_the_pri_in_the_notch_is_not_kept_when_another_sees_the_target():
    b = _bin_with_margins()
    margins = [eclipse_margin(b, k) for k in KS]
    ci0 = max(range(3), key=lambda i: margins[i])
    # a Doppler folding to 0.05 cycles at the largest-margin PRI (12 dB of loss there)
    f = 0.05 / PRIS[ci0]
    losses = [predicted_loss_db(f, p, 1) for p in PRIS]
    assert losses[ci0] > 10.0
    ci = choose_confirm_pri(b, KS, PRIS, f, set(), 3.0, 1)
    assert ci != ci0
    assert losses[ci] == min(losses)
    # disabled: the eclipse margin alone
    assert choose_confirm_pri(b, KS, PRIS, f, set(), 0.0, 1) == ci0
    assert choose_confirm_pri(b, KS, PRIS, f, set(), 3.0, 0) == ci0
    # a Doppler clear of the notch at the largest-margin PRI keeps it
    g = 0.3 / PRIS[ci0]
    if predicted_loss_db(g, PRIS[ci0], 1) <= 3.0:
        assert choose_confirm_pri(b, KS, PRIS, g, set(), 3.0, 1) == ci0


def test_a_blind_pri_is_never_chosen_by_loss():
    b = _bin_with_margins()
    f = 0.05 / PRIS[0]
    losses = [predicted_loss_db(f, p, 1) for p in PRIS]
    best = min(range(3), key=lambda i: losses[i])
    ci = choose_confirm_pri(b, KS, PRIS, f, {best}, 3.0, 1)
    assert ci != best


@pytest.mark.slow
def test_fast_closing_target_at_20_km_1_deg_confirms_off_the_notch():
    # main (d0d9063): M of N and confirmed tracking on PRI 1, where −785.71 m/s folds to
    # −0.069 cycles (10.3 dB of canceller loss): M of N failed, lock at 1.145 s and a drop
    from engagement import assert_meets_goals

    out = run_cell(replace(ANCHOR, range_m=20_000.0, speed=-785.71, el_deg=1.0, seed=1))
    assert_meets_goals(out)
