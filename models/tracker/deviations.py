"""DIF/SUM deviations of the digital tracker (seed 000; equations restated in SYSTEM.md).

The Tracker (:mod:`.beams`) uses :func:`dif_sum` and :func:`early_late` (and :func:`gate_cells`,
written out inline in its step);
the array helpers below them also read the TargetGenerator's beams in its tests.

Beam array layout everywhere: ``beams[b, r, f]`` with b = 0..3 for up (B1), right (B2),
down (B3), left (B4), r = 0..15 for range bins 1..16, f = 0..2 for Doppler filters 1..3.
"""

from __future__ import annotations

import numpy as np

from ..radar.conventions import BIN_M, GATE_BIN

_C = GATE_BIN - 1  # 0-based index of the gate-centre bin (bin 7)
_add_reduce = np.add.reduce


def gate_cells(beams: np.ndarray, central_only: bool) -> np.ndarray:
    """Beam magnitudes of range bins 6, 7, 8, shape (4, 3): Σ over the 3 Doppler filters
    (tentative) or the central filter alone (confirmed).  # seed 000, SYSTEM.md"""
    if central_only:
        return beams[:, _C - 1 : _C + 2, 1]
    return _add_reduce(beams[:, _C - 1 : _C + 2, :], 2)  # = .sum(axis=2), without the wrapper


def dif_sum(a: float, b: float) -> float:
    """Monopulse ratio (a − b)/(a + b) of two beam magnitudes [1] (a + b > 0).

    ε_el = dif_sum(B1, B3), ε_lat = dif_sum(B2, B4)  # SYSTEM.md (seed 000 lost eqs.)
    """
    return (a - b) / (a + b)


def early_late(s6: float, s7: float, s8: float) -> float:
    """Early/late range ratio ε_R = (S8 − S6)/(S6 + S7 + S8) [1] (denominator > 0).

    # SYSTEM.md (seed 000 lost eqs.). For the triangular matched-filter response of a
    # 75 m rectangular pulse sampled every 75 m, ε_R equals the target offset from the
    # bin-7 sample in bins exactly, so the deviation in metres is ε_R · 75 m.
    """
    return (s8 - s6) / (s6 + s7 + s8)


def angle_ratios(cells: np.ndarray) -> tuple[float, float]:
    """Monopulse ratios at the gate-centre bin from :func:`gate_cells` output.

    ε_lat = (B2 − B4)/(B2 + B4), ε_el = (B1 − B3)/(B1 + B3)  # SYSTEM.md (seed 000 lost eqs.)
    Returns (ε_lat, ε_el) [1]; NaN when a denominator is zero.
    """
    b1, b2, b3, b4 = cells[:, 1].tolist()
    nan = float("nan")
    return (dif_sum(b2, b4) if b2 + b4 > 0.0 else nan,
            dif_sum(b1, b3) if b1 + b3 > 0.0 else nan)


def range_ratio(cells: np.ndarray) -> float:
    """:func:`early_late` on the beam sums of :func:`gate_cells` output (NaN if no signal)."""
    s6, s7, s8 = cells.sum(axis=0).tolist()
    return early_late(s6, s7, s8) if s6 + s7 + s8 > 0.0 else float("nan")


def range_deviation_m(cells: np.ndarray) -> float:
    """Range deviation [m] (> 0: target farther than the gate centre)."""
    return range_ratio(cells) * BIN_M
