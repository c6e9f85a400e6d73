"""MTI clutter canceller of the front end (AXIR_A), switched by antenna elevation (issue 11).

Seed 000 is silent on clutter rejection: it names the front end only by its outputs (4 beams ×
16 range bins × 3 IIR Doppler filters). Designer's choices, documented in docs/clutter.md:

- **Canceller.** A binomial canceller of order m before the Doppler filters,
  x'[n] = Σ_i h_i x[n − i], h = (1, −1)/√2 (m = 1, two-pulse) or (1, −2, 1)/√6 (m = 2,
  three-pulse), scaled to unit white-noise power gain: |H(ν)|² = (2 sin πν)^(2m)/C(2m, m),
  ν = f·PRI. It removes the slow part of the ground clutter (the AR(1) peak at 0 Hz that the
  one-pole Doppler filters' skirts let through, −24 dB at PRF/3), and notches targets whose
  folded Doppler is near 0 Hz (2 sin² πν: −13 dB at 0.036·PRF; the PRI stagger of the manager
  covers a notch at one PRI).
- **Elevation switch** (a classic low-elevation MTI sector). The canceller is applied while the
  antenna elevation is below ``mti_max_el`` (where the beams see the ground through their main
  lobe) and switched off above ``mti_max_el + mti_hysteresis`` (the hysteresis keeps a
  boresight dithering around the limit from toggling it every pulse); in between the last state
  is kept. Above the limit the clutter enters only through the sidelobes and the canceller's
  notch and coloured noise would cost more than the clutter (docs/doppler_coverage.md).
- The canceller's memory (the last m raw pulses) is updated whether it is applied or not, so
  switching it on needs no refill.

Pure functions on numpy arrays (the caller keeps the state: arrays and a bool, which
``get_state``/``set_state`` copy).
"""

from __future__ import annotations

import math

import numpy as np

#: binomial canceller taps (current pulse first), scaled to unit white-noise power gain
MTI_TAPS: dict[int, np.ndarray] = {1: np.array([1.0, -1.0]) / math.sqrt(2.0),
                                   2: np.array([1.0, -2.0, 1.0]) / math.sqrt(6.0)}
#: the same taps as 0-d complex arrays for :func:`cancel_pulse_into` (issue 14): numpy casts a
#: float tap multiplying a complex array to exactly this (h + 0j), without a per-call cast
MTI_TAPS_0D: dict[int, tuple[np.ndarray, ...]] = {
    m: tuple(np.array(complex(h)) for h in taps) for m, taps in MTI_TAPS.items()}


def mti_switch(active: bool, el_a: float, max_el: float, hysteresis: float) -> bool:
    """Canceller state for antenna elevation ``el_a`` [rad]: on below ``max_el`` [rad], off
    above ``max_el + hysteresis`` [rad], else the previous state ``active``."""
    if el_a < max_el:
        return True
    if el_a > max_el + hysteresis:
        return False
    return active


def mti_power_gain(nu: np.ndarray | float, order: int) -> np.ndarray:
    """|H(ν)|² of the canceller of ``order`` (0: none → 1) at ν = f·PRI [cycles per pulse]:
    (2 sin πν)^(2m)/C(2m, m) (unit mean over a PRF).

    A Python float ν and ``order`` ≥ 1 (the manager's predicted loss, every few PRIs): the
    same numpy operations on the scalar without making a 0-d array first (π·ν a Python
    product, the IEEE one numpy forms; ``np.sin`` of it the same float64 loop), the same
    numpy float64 result (issue 14, round 10: two array operations fewer); otherwise
    :func:`mti_power_gain_array`, the general form."""
    if type(nu) is float and order > 0:
        return (2.0 * np.sin(np.pi * nu)) ** (2 * order) / math.comb(2 * order, order)
    return mti_power_gain_array(nu, order)


def mti_power_gain_array(nu: np.ndarray | float, order: int) -> np.ndarray:
    """:func:`mti_power_gain` for any ``nu`` [cycles per pulse] (array or scalar), through a
    float64 array (the general form; the reference of its scalar case, tested)."""
    nu = np.asarray(nu, dtype=np.float64)
    if order <= 0:
        return np.ones_like(nu)
    return (2.0 * np.sin(np.pi * nu)) ** (2 * order) / math.comb(2 * order, order)


def cancel_pulse(raw: np.ndarray, hist: np.ndarray, taps: np.ndarray,
                 apply: bool) -> tuple[np.ndarray, np.ndarray]:
    """One pulse: ``raw`` (4, 16) complex samples, ``hist`` (m, 4, 16) the last m raw pulses
    (newest first). Returns (the samples for the Doppler filters, the new history): the
    canceller output when ``apply``, else ``raw`` itself."""
    out = raw
    if apply:
        out = taps[0] * raw
        for i in range(1, taps.size):
            out = out + taps[i] * hist[i - 1]
    new = raw[None].copy() if hist.shape[0] == 1 else np.concatenate((raw[None], hist[:-1]))
    return out, new


def cancel_chunk(x: np.ndarray, hist: np.ndarray, taps: np.ndarray,
                 apply: bool) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised :func:`cancel_pulse` over pulses ``x`` (n, 4, 16) (oldest first); the
    switch state is the same for the whole chunk (a step has one antenna input)."""
    o = taps.size - 1
    n = x.shape[0]
    ext = np.concatenate((hist[::-1], x))  # oldest first
    new = ext[::-1][:o].copy()
    if not apply:
        return x, new
    out = sum(taps[i] * ext[o - i : o - i + n] for i in range(taps.size))
    return out, new


def cancel_pulse_into(raw: np.ndarray, hist: np.ndarray,
                      taps: np.ndarray | tuple[np.ndarray, ...], apply: bool,
                      out: np.ndarray, tmp: np.ndarray) -> np.ndarray:
    """In-place :func:`cancel_pulse` (issue 14, per-PRI path): same products and sums in the
    same order, written into the preallocated ``out`` / ``tmp`` (4, 16) buffers; ``hist``
    (m, 4, 16) is updated in place (newest first). Returns ``out`` when ``apply``, else
    ``raw`` (the samples for the Doppler filters; ``raw`` itself is not modified)."""
    res = raw
    if apply:
        np.multiply(raw, taps[0], out=out)
        for i in range(1, len(taps)):
            np.multiply(hist[i - 1], taps[i], out=tmp)
            out += tmp
        res = out
    if hist.shape[0] > 1:
        hist[1:] = hist[:-1].copy()
    hist[0] = raw
    return res
