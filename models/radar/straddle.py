"""Pulse straddle of a point target in the 16-bin range window (scalar, per-pulse path).

The matched-filter response of the 0.5 µs rectangular pulse is the triangle
Λ(u) = max(0, 1 − |u|), half-width Δ = 75 m (radar.py, pulse straddle; SYSTEM.md). Bin r
samples gate.start + r·75 m (r = 0..15); the target is seen at its range modulo
Ru = c·PRI/2 (radar.py, range folding), so only the apparent delay
d1 = (R − gate.start) mod Ru and d1 − Ru can fall within one bin of a sample.
"""

from __future__ import annotations

from math import floor

from .conventions import BIN_M, N_BINS


def straddle_bins(r: float, gate_start: float, ru: float) -> list[tuple[int, float]]:
    """The non-zero straddle weights (bin index, Λ) of a target at range ``r`` [m] for the
    window starting at ``gate_start`` [m] and the unambiguous range ``ru`` [m] (≥ 16 bins)."""
    out: list[tuple[int, float]] = []
    d1 = (r - gate_start) % ru
    # the bins k, k + 1 around q = d/Δ for d = d1, then d1 − Ru; loops unrolled (issue 14:
    # the same operations, in the same order, without the per-pulse loop overhead)
    for q in (d1 / BIN_M, (d1 - ru) / BIN_M):
        k = floor(q)
        if 0 <= k < N_BINS:
            w = 1.0 - abs(q - k)
            if w > 0.0:
                out.append((k, w))
        k += 1
        if 0 <= k < N_BINS:
            w = 1.0 - abs(q - k)
            if w > 0.0:
                out.append((k, w))
    return out
