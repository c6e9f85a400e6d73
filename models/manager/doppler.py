"""Doppler discriminator of the radar manager (confirmed mode): the response of the
generator's Doppler filters and the target's offset from the centre filter.

Seed 000: "the Doppler frequency is calculated by the Radar Manager and only the central Doppler
filter is used". Assumption (the seed gives no method): an amplitude-comparison discriminator
across the three Doppler filters (:func:`doppler_offset`), the frequency-domain analogue of the
monopulse deviation, fitted to the filters' resonator gain (:func:`resonator_gain`).
"""

from __future__ import annotations

import numpy as np

from ..radar.conventions import CENTRE_FILTER, N_DOPPLER

_CF = CENTRE_FILTER - 1  # 0-based central Doppler filter


def resonator_gain(offset_cycles: np.ndarray | float, pole: float) -> np.ndarray:
    """|H| of the generator's Doppler filter, a first-order complex resonator with unit gain at
    its centre (models/target_generator.py): |H(δ)| = (1 − ρ) / |1 − ρ·e^{j2πδ·PRI}|, with the
    frequency offset δ·PRI from the filter centre given in cycles per PRI (fraction of the PRF).
    """
    w = 2.0 * np.pi * np.asarray(offset_cycles, dtype=np.float64)
    return (1.0 - pole) / np.sqrt(1.0 - 2.0 * pole * np.cos(w) + pole * pole)


_DISC_STEP = 1.0 / 720.0  # search grid of the discriminator [cycles per PRI]


def doppler_offset(excess: np.ndarray, spacing: float, pole: float,
                   weights: np.ndarray | None = None) -> float:
    """Doppler discriminator: offset of the target from the centre filter's centre, as a
    fraction of the PRF in [−spacing/2, spacing/2], from the target's excess amplitude in the
    three Doppler filters.

    ``excess[f]`` (f = 0, 1, 2; centre filter 1) is the target's mean SUM amplitude in filter
    f after that filter's noise/clutter level is removed; filter f is centred (f − 1)·``spacing``
    [cycles per PRI] from the centre filter. Across the filters the amplitude follows each
    filter's resonator gain (:func:`resonator_gain`) up to an unknown scale: the offset δ is the
    one whose gain profile h(δ) best fits the measured profile in weighted least squares over
    the scale, i.e. it maximises (Σ w·e·h)/√(Σ w·h²) (``weights`` w, default equal; a weight 0
    drops a filter) on a 1/720-PRF grid, refined by a parabola. The search is limited to the
    centre filter's own half-spacing: the target was detected in the filter nearest to it.
    Assumption (the seed only says the manager computes the Doppler frequency): an
    amplitude-comparison discriminator across the filters, the frequency-domain analogue of the
    monopulse deviation.
    """
    e = np.maximum(np.asarray(excess, dtype=np.float64), 0.0)
    w = np.ones(N_DOPPLER) if weights is None else np.asarray(weights, dtype=np.float64)
    n_half = int(0.5 * spacing / _DISC_STEP)
    grid = np.arange(-n_half, n_half + 1) * _DISC_STEP
    h = resonator_gain(grid[:, None] - spacing * (np.arange(N_DOPPLER) - _CF)[None, :], pole)
    score = (h @ (w * e)) / np.sqrt((h * h) @ w)
    i = int(np.argmax(score))
    d = grid[i]
    if 0 < i < len(grid) - 1:
        s0, s1, s2 = score[i - 1], score[i], score[i + 1]
        den = s0 - 2.0 * s1 + s2
        if den < 0.0:
            d += 0.5 * (s0 - s2) / den * _DISC_STEP
    return float(d)
