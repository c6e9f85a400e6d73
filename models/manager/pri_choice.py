"""Choice of the PRI kept for M of N and confirmed tracking by predicted loss (issue 11, low11).

Seed 000 ("Algorithms and Hardware"): "waveform (DCP, PRI) are continuously optimized" while the
track is maintained; tentative tracking uses "at least 3 different PRIs". The seed does not say
by what the PRI is optimised; the designer's choice here (docs/clutter.md "M of N and confirmed
tracking off the notch"):

- the default remains the PRI with the largest eclipse margin (the apparent range farthest from
  0 / Ru, ``models/manager/tentative.py: _resolve``) among the PRIs not blind for the resolved
  Doppler;
- when that PRI's **predicted loss** exceeds ``confirm_max_loss_db``, the PRI with the smallest
  predicted loss is kept instead, among the non-blind PRIs whose eclipse margin is at least
  ``MIN_MARGIN_BINS`` (the 16-bin gate, centred on bin 7, then does not straddle the transmit
  pulse); ties: the larger eclipse margin.

Predicted loss of a PRI for the resolved Doppler f [Hz]: the loss of the MTI canceller of order m
(``confirm_loss_mti_order``) at the folded Doppler ν = f·PRI (models/radar/mti.py
``mti_power_gain``, the binomial canceller with unit noise gain, |H(ν)|² = (2 sin πν)^(2m) /
C(2m, m)), L = −10·log10 |H(ν)|² [dB] (0 dB at ν = 1/4 for m = 1, −3 dB at ν = 1/2, +10.3 dB at
ν = 0.069). The Doppler filter's own loss is the same at every PRI (M of N and confirmed tracking
centre the central filter on the resolved Doppler), so the canceller decides. The manager has no
MTI or elevation input (the canceller is the generator's, switched by elevation); with the
canceller off, a PRI folding the target near the clutter line still sees the clutter through the
filter's skirts, so the same ranking is kept (only its size is wrong there).

**In confirmed tracking** (issue 11, branch env14; ``confirm_switch_db``). A target in a turn
ramps its Doppler (2·a_r/λ, 2-3.4 kHz/s at 5-7 g at X band) and its folded Doppler can walk
into the clutter line of the kept PRI within a second: traced on three random engagements
(26.7 km / 6.9 g, 37.0 km / 5.1 g, 11.1 km / 6.2 g; docs/envelope.md) the folded Doppler went
0.44 → 0.02, 0.24 → 0.05 and 0.26 → 0.05 cycles, the centre filter's noise rose with the
clutter (2.3× at 16.6°, no canceller), the target's excess fell from ≈ 10 to 2-4 × the noise,
the dither loop lost its clear pairs and the track was dropped by ``miss_limit``. The same
predicted loss is therefore evaluated after every confirmed dwell at the tracked unfolded
Doppler (the confirmation's resolved Doppler carried by the confirmed centre's own changes);
above ``confirm_max_loss_db`` the track moves to the PRI of least predicted loss when that is
``confirm_switch_db`` smaller and its eclipse margin is ≥ ``MIN_MARGIN_BINS``. The true range
is kept (gate and ``range.offset`` re-expressed at the new Ru), the Doppler centre is the
unfolded Doppler folded at the new PRF, and the dwell waits for the filters' transient.
Seed 000 ("waveform (DCP, PRI) are continuously optimized" while tracking) allows it; the
criterion is the designer's.

**Confirmed-tracking PRIs** (issue 11, session 11, branch env15; ``track_pri_bins``). The three
acquisition PRIs (200/211/223 bins, PRFs within 11 %) share bands where every one predicts more
than ``confirm_max_loss_db`` = 3 dB of canceller loss (two-pulse canceller: |ν| < 1/6 of a PRF,
so 8.3-10.5 kHz, 18.3-19.4 kHz and 28.31-28.38 kHz and their negatives over ±1500 m/s
(``max_speed``, ±94 kHz), besides the clutter band |f| < 1.49 kHz); a turning target whose
Doppler ramps through one is dropped whatever PRI of the three it is on. Once a track is
confirmed its range ambiguity is resolved and tracking can continue on any PRI (the gate and
``range.offset`` are re-expressed at the new Ru, as above), so the switch also considers the
PRIs of ``track_pri_bins`` (indices 3, 4, … after the three acquisition PRIs). They are
**never** used in acquisition or tentative (the ambiguity resolver knows only the three) nor for
the M-of-N confirmation. The default, 157 and 128 bins (PRF 12.73 and 15.61 kHz), is the
designer's choice computed with :func:`predicted_loss_db` (``reports/track_pris.py``,
docs/doppler_coverage.md "Confirmed- tracking PRIs"): each alone, added to the three, leaves no
band above 3 dB over ±1500 m/s outside the clutter band (worst predicted loss of the best PRI
2.68 dB with 157, 2.82 dB with 128, 1.47 dB with both, for |f| ≥ 2.2 kHz); two of them so that a
target eclipsed at one (apparent range within ``MIN_MARGIN_BINS`` of 0 / Ru) still has the
other.
**Return to the acquisition PRIs** (``track_pri_return``, default on): the co-simulation step
is the PRI, so a track on 157 / 128 bins costs 1.34 / 1.65× the steps per second of PRI 2, and
the switch alone leaves it there until that PRI's own loss exceeds 3 dB (measured: the default
scenario's 3 g turn moved to 128 bins at 21.4 s and stayed, +34 % steps over 40 s). After
each confirmed dwell on a tracking PRI the track therefore returns to the acquisition PRI of
least predicted loss (eclipse margin ≥ ``MIN_MARGIN_BINS``) once that loss is at most
``confirm_max_loss_db`` − ``confirm_switch_db`` (0 dB by default: the same 3 dB hysteresis as
the switch, no back and forth at a band edge); and a switch away from an acquisition PRI goes to
such an acquisition PRI when there is one (else it would come straight back:
:func:`next_confirmed_pri`). The designer's choice.
Shorter than the acquisition PRIs on purpose: a longer PRI narrows the Doppler filters in Hz
and lengthens the dwell, so a ramping Doppler walks farther across them per dwell.
"""

from __future__ import annotations

import math

import numpy as np

from ..radar.conventions import N_BINS
from ..radar.mti import mti_power_gain

#: smallest eclipse margin [bins] of a PRI chosen by loss: the 16-bin gate stays inside one Ru
MIN_MARGIN_BINS = N_BINS // 2
_FLOOR = 1e-12  # |H|² floor (a Doppler exactly on the clutter line: 120 dB, not infinite)


#: default ``track_pri_bins`` (module docstring, "Confirmed-tracking PRIs") [bins]
DEFAULT_TRACK_PRI_BINS = "157,128"
#: at most this many confirmed-tracking PRIs
MAX_TRACK_PRIS = 4


def parse_track_pri_bins(text: str, acq_bins: tuple[int, ...] = ()) -> tuple[int, ...]:
    """The confirmed-tracking PRIs [bins] of ``text`` (integers separated by commas or
    spaces; empty: none). ValueError (naming ``track_pri_bins``) for a value that is not an
    integer in [2·``MIN_MARGIN_BINS`` + N_BINS = 32 … 20000] (the 16-bin gate with the eclipse
    margin on both sides fits in Ru; 20000: the acquisition PRIs' bound), a repeated value, one of
    the acquisition PRIs ``acq_bins`` or more than ``MAX_TRACK_PRIS`` values."""
    parts = str(text).replace(",", " ").split()
    lo = 2 * MIN_MARGIN_BINS + N_BINS
    try:
        ks = tuple(int(p) for p in parts)
    except ValueError:
        raise ValueError(f"RadarManager: track_pri_bins = {text!r}: integers [bins] separated "
                         "by commas expected") from None
    if len(ks) > MAX_TRACK_PRIS:
        raise ValueError(f"RadarManager: track_pri_bins = {text!r}: at most {MAX_TRACK_PRIS}")
    for k in ks:
        if not lo <= k <= 20000:
            raise ValueError(f"RadarManager: track_pri_bins = {text!r}: {k} outside "
                             f"[{lo}, 20000] bins")
    if len(set(ks)) != len(ks) or set(ks) & set(acq_bins):
        raise ValueError(f"RadarManager: track_pri_bins = {text!r}: values must differ from "
                         f"each other and from the acquisition PRIs {tuple(acq_bins)}")
    return ks


def predicted_loss_db(doppler: float, pri: float, mti_order: int) -> float:
    """Predicted canceller loss [dB] of a target of Doppler ``doppler`` [Hz] at ``pri`` [s]:
    −10·log10 |H(ν)|², ν = doppler·pri (module docstring; 0 for ``mti_order`` 0)."""
    nu = (doppler * pri) % 1.0
    g = float(mti_power_gain(nu, mti_order))
    return -10.0 * math.log10(max(g, _FLOOR))


def eclipse_margin(b: int, k: int) -> int:
    """Bins between the apparent range of true bin ``b`` at a PRI of ``k`` bins and 0 / Ru."""
    return int(min(b % k, k - b % k))


def choose_confirm_pri(b: int, ks: list[int], pris: list[float], doppler: float,
                       blind: set[int], max_loss_db: float, mti_order: int) -> int:
    """Index of the PRI kept for M of N and confirmed tracking (module docstring): true range
    bin ``b``, PRIs ``ks`` [bins] / ``pris`` [s], resolved Doppler [Hz], the blind PRI indices
    (never kept unless every PRI is blind), ``max_loss_db`` (≤ 0: the eclipse margin alone)."""
    margins = [eclipse_margin(b, k) if i not in blind else -1 for i, k in enumerate(ks)]
    ci = int(np.argmax(margins))
    if max_loss_db <= 0.0 or mti_order <= 0:
        return ci
    losses = [predicted_loss_db(doppler, p, mti_order) for p in pris]
    if losses[ci] <= max_loss_db:
        return ci
    ok = [i for i, mg in enumerate(margins) if mg >= MIN_MARGIN_BINS]
    if not ok:
        return ci
    best = min(ok, key=lambda i: (losses[i], -margins[i]))
    return best if losses[best] < losses[ci] else ci


def switch_confirmed_pri(b: int, ks: list[int], pris: list[float], doppler: float, cur: int,
                         max_loss_db: float, margin_db: float, mti_order: int) -> int:
    """Index of the PRI confirmed tracking continues on (``cur``: no switch), for the tracked
    unfolded Doppler ``doppler`` [Hz] and true range bin ``b`` (module docstring, "In confirmed
    tracking"): when the current PRI's predicted loss exceeds ``max_loss_db``, the PRI of least
    predicted loss among those with an eclipse margin ≥ ``MIN_MARGIN_BINS``, if its loss is at
    least ``margin_db`` smaller (the hysteresis: no switching back and forth); ``margin_db``,
    ``max_loss_db`` or ``mti_order`` ≤ 0: ``cur``."""
    if margin_db <= 0.0 or max_loss_db <= 0.0 or mti_order <= 0 or not math.isfinite(doppler):
        return cur
    losses = [predicted_loss_db(doppler, p, mti_order) for p in pris]
    if losses[cur] <= max_loss_db:
        return cur
    ok = [i for i, k in enumerate(ks) if i != cur and eclipse_margin(b, k) >= MIN_MARGIN_BINS]
    if not ok:
        return cur
    best = min(ok, key=lambda i: (losses[i], -eclipse_margin(b, ks[i])))
    return best if losses[best] <= losses[cur] - margin_db else cur


def return_acquisition_pri(b: int, ks: list[int], pris: list[float], doppler: float,
                           max_loss_db: float, margin_db: float, mti_order: int) -> int:
    """Index (into ``ks`` / ``pris``, the acquisition PRIs) of the acquisition PRI a track on a
    confirmed-tracking PRI returns to (module docstring, "Return to the acquisition PRIs"):
    the one of least predicted loss at the tracked unfolded Doppler ``doppler`` [Hz] among
    those with an eclipse margin ≥ ``MIN_MARGIN_BINS`` at true range bin ``b``, if that loss
    is ≤ ``max_loss_db`` − ``margin_db``; −1: stay (also when the prediction is off, as
    :func:`switch_confirmed_pri`)."""
    if margin_db <= 0.0 or max_loss_db <= 0.0 or mti_order <= 0 or not math.isfinite(doppler):
        return -1
    ok = [i for i, k in enumerate(ks) if eclipse_margin(b, k) >= MIN_MARGIN_BINS]
    if not ok:
        return -1
    losses = {i: predicted_loss_db(doppler, pris[i], mti_order) for i in ok}
    best = min(ok, key=lambda i: (losses[i], -eclipse_margin(b, ks[i])))
    return best if losses[best] <= max_loss_db - margin_db else -1


def next_confirmed_pri(b: int, ks: list[int], pris: list[float], n_acq: int, doppler: float,
                       cur: int, max_loss_db: float, margin_db: float, mti_order: int,
                       back: bool = True) -> int:
    """Index of the PRI confirmed tracking continues on (``cur``: no change) when ``ks`` /
    ``pris`` are the ``n_acq`` acquisition PRIs followed by the confirmed-tracking PRIs
    (module docstring): with ``back`` and tracking PRIs present, a track on a tracking PRI, or
    on an acquisition PRI predicting more than ``max_loss_db``, goes to the acquisition PRI of
    :func:`return_acquisition_pri` when there is one (the acquisition PRIs first: fewer steps,
    and no return right after the switch); otherwise :func:`switch_confirmed_pri` over all."""
    if (back and len(ks) > n_acq and margin_db > 0.0 and max_loss_db > 0.0 and mti_order > 0
            and math.isfinite(doppler)
            and (cur >= n_acq or predicted_loss_db(doppler, pris[cur], mti_order) > max_loss_db)):
        j = return_acquisition_pri(b, ks[:n_acq], pris[:n_acq], doppler, max_loss_db,
                                   margin_db, mti_order)
        if j >= 0:
            return j
    return switch_confirmed_pri(b, ks, pris, doppler, cur, max_loss_db, margin_db, mti_order)
