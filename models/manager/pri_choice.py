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
"""

from __future__ import annotations

import math

import numpy as np

from ..radar.conventions import N_BINS
from ..radar.mti import mti_power_gain

#: smallest eclipse margin [bins] of a PRI chosen by loss: the 16-bin gate stays inside one Ru
MIN_MARGIN_BINS = N_BINS // 2
_FLOOR = 1e-12  # |H|² floor (a Doppler exactly on the clutter line: 120 dB, not infinite)


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
