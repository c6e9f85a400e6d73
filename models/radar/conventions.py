"""Radar-wide constants and conventions shared by every unit (SYSTEM.md).

Range window: 16 range bins of 75 m (seed 000); bin r (1-based) samples the range
``gate_start + (r − 1)·BIN_M``; the gate is centred on bin 7 (bins 6, 7, 8 form the
early/centre/late gates). A 0.5 µs rectangular pulse gives a triangular matched-filter
response of half-width one bin (pulse straddle).

Range folding: a target at true range R is seen at apparent range R mod Ru with
Ru = c·PRI/2; the window is placed at apparent range ``gate_start mod Ru``.
Ambiguity convention: true range = apparent range + ``range.offset`` (the manager's N·Ru).

Doppler: f_d = −2·ṙ/λ (closing target → positive Doppler), folded modulo PRF = 1/PRI.
The three Doppler filters are centred at ``doppler_centre + (f − 2)·spacing``, f = 1..3.
"""

from __future__ import annotations

C = 299_792_458.0  # speed of light [m/s]
N_BINS = 16  # range bins (seed 000)
N_DOPPLER = 3  # Doppler filters (seed 000)
N_BEAMS = 4  # up (B1), right (B2), down (B3), left (B4) (seed 000 eq. 1)
BEAMS = ("up", "right", "down", "left")
BIN_M = 75.0  # range bin size [m] (seed 000)
BIN_S = 2.0 * BIN_M / C  # range bin duration [s] (≈ 0.5 µs)
GATE_BIN = 7  # the gate is centred on bin 7 (1-based; bins 6, 7, 8) (SYSTEM.md)
CENTRE_FILTER = 2  # central Doppler filter (1-based)
DEFAULT_FREQ_HZ = 9.4e9  # X band carrier (assumption, SYSTEM.md)
DEFAULT_WAVELENGTH = C / DEFAULT_FREQ_HZ  # [m]
#: defaults of the parameters the Tracker and the RadarManager both declare (a scenario sets
#: both to the same value): designated true range [m], instrumented range [m] and the
#: physical speed bound of a track [m/s] (designer's choice, issue 11: 1.5 × the fastest
#: radial speed of the engagement envelope, 1000 m/s)
DEFAULT_DESIGNATION_RANGE = 10_000.0
DEFAULT_MAX_RANGE = 150_000.0
DEFAULT_MAX_SPEED = 1_500.0
#: the coast through the clutter notch (Tracker notch_coast_speed, RadarManager
#: notch_coast_time; models/tracker/notch.py): it ends once the Doppler is this × the notch's
#: speed away from 0 (designer's choice, session 30)
NOTCH_EXIT = 1.5

# Modes (RadarManager.mode)
ACQUISITION = 0
TENTATIVE = 1
CONFIRMED = 2


def unambiguous_range(pri: float) -> float:
    """Ru = c·PRI/2 [m] for a PRI [s]."""
    return 0.5 * C * pri


def apparent_range(r: float, pri: float) -> float:
    """Range folded into [0, Ru) [m]."""
    return r % unambiguous_range(pri)


def doppler_hz(range_rate: float, wavelength: float = DEFAULT_WAVELENGTH) -> float:
    """Doppler frequency f_d = −2 ṙ/λ [Hz] of a target with range rate ṙ [m/s]."""
    return -2.0 * range_rate / wavelength


def fold_doppler(f: float, pri: float) -> float:
    """Doppler folded into [−PRF/2, PRF/2) [Hz]."""
    prf = 1.0 / pri
    return (f + 0.5 * prf) % prf - 0.5 * prf


def gate_start_for(range_centre: float) -> float:
    """Gate start [m] that puts ``range_centre`` on the sample of bin 7."""
    return range_centre - (GATE_BIN - 1) * BIN_M
