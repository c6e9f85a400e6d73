"""Ports of the radar manager: its public inputs and outputs, declared once
(:class:`~axir.models.radar.ports.Port`; the FMU variables, the interface docs and the direct
loop derive from them), and the readers that turn an input into a usable value or None.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..radar.conventions import N_BINS, N_DOPPLER
from ..radar.ports import Port

#: Input domains (out of domain: the last valid value is held). BEAM_MAX: beam magnitudes are
#: noise-normalised amplitudes, ≤ 1e30 for any valid TargetGenerator parameters (SNR ≤ 200 dB,
#: R⁻² amplitude law down to 1 m); RANGE_MAX: 10 000 km; SPEED_MAX: 100 km/s.
BEAM_MAX = 1.0e30
RANGE_MAX = 1.0e7  # [m]
SPEED_MAX = 1.0e5  # [m/s]

#: Public inputs of ``step``.
INPUTS: tuple[Port, ...] = (
    Port("sum", float, "1", "SUM(R, f) = B1 + B2 + B3 + B4 from the Tracker (seed 000 eq. 1)",
         shape=(N_BINS, N_DOPPLER), low=0.0, high=4 * BEAM_MAX),
    Port("gate.start", float, "m", "range of bin 1 of the gate the Tracker uses (optional)",
         low=-RANGE_MAX, high=RANGE_MAX),
    Port("track.range", float, "m", "Tracker's filtered true range",
         low=-RANGE_MAX, high=RANGE_MAX),
    Port("track.range_rate", float, "m/s", "Tracker's filtered range rate",
         low=-SPEED_MAX, high=SPEED_MAX),
    Port("maneuver", bool, "1", "Tracker's maneuver flag"),
)

#: Public outputs of ``step``.
OUTPUTS: tuple[Port, ...] = (
    Port("mode", int, "1", "0 acquisition, 1 tentative, 2 confirmed"),
    Port("pri", float, "s", "pulse repetition interval (master communication step)"),
    Port("alpha", float, "1", "steady α gain (0 in modes 0-1: evolutive gains)"),
    Port("beta", float, "1", "steady β gain (0 in modes 0-1: evolutive gains)"),
    Port("bandwidth", float, "Hz", "pedestal servo bandwidth"),
    Port("range.offset", float, "m", "N·Ru: true range = apparent range + range.offset"),
    Port("gate.command", float, "m", "gate start (range of bin 1), apparent range"),
    Port("doppler.centre", float, "Hz", "centre of Doppler filter 2"),
    Port("threshold", float, "1", "last threshold (Th1 in mode 0, Th2 in modes 1-2), NaN before"),
    Port("noise.level", float, "1", "last noise estimate the threshold was scaled on, NaN before"),
    Port("detection", bool, "1", "a dwell ended in this step with a threshold crossing"),
    Port("dwell.done", bool, "1", "a dwell ended in this step"),
    Port("ambiguity.resolved", bool, "1", "the true range has been resolved"),
    Port("range.resolved", float, "m", "resolved true range (R0 + N·Ru, 75 m bins), NaN before"),
    Port("tracking.index", float, "1", "tracking index Λ = σ_m·T²/σ_n in use"),
    Port("doppler.range_rate", float, "m/s",
         "radial speed −λ·f/2 of the unfolded track Doppler f the manager tracks (confirmed "
         "mode: the tentative resolution carried along by the Doppler centre); 0 when "
         "doppler.resolved is false"),
    Port("doppler.resolved", bool, "1", "the manager tracks an unfolded Doppler (confirmed mode)"),
)


_F64 = np.dtype(np.float64)
_SUM_SHAPE = (N_BINS, N_DOPPLER)
_add_reduce = np.add.reduce


def read_sum(s: Any) -> np.ndarray | None:
    """The ``sum`` input as a (16, 3) float array, or None if absent, misshaped or non-finite."""
    if type(s) is np.ndarray and s.shape == _SUM_SHAPE and s.dtype == _F64:
        # issue 14, the common case: np.asarray would return ``s`` itself and ``s.sum()`` is
        # np.add.reduce(s, None) (the same pairwise sum, without the Python wrapper)
        return s if math.isfinite(_add_reduce(s, None)) else None
    if s is None:
        return None
    try:
        a = np.asarray(s, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    if a.size != N_BINS * N_DOPPLER:
        return None
    if a.shape != (N_BINS, N_DOPPLER):
        a = a.reshape(N_BINS, N_DOPPLER)
    if not math.isfinite(float(a.sum())):
        return None
    return a


def finite_or_none(x: Any) -> float | None:
    """``float(x)`` if it is finite, else None (also for values that are not numbers)."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None
