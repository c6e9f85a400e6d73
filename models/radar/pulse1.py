"""Helpers of the TargetGenerator's one-pulse path (issue 14: per-PRI overhead).

No equation of their own: they prepare operands of the front-end equations of
``models/target_generator.py`` (module docstring: target echo, AR(1) clutter, Doppler
filters y = p·y + (1 − ρ)·x) so that numpy forms the same products with fewer or cheaper calls.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .antenna import FOUR_LN2, MonopulseAntenna
from .conventions import N_BEAMS, N_BINS


def complex0d(v: float) -> np.ndarray:
    """``v`` as a 0-d complex array. numpy casts a Python float that multiplies a complex array
    to exactly this (v + 0j) and forms the same products; a 0-d array skips the per-call
    conversion of the Python scalar (≈ 1 µs per operation on a (4, 16) array)."""
    return np.array(complex(v))


def draw_views(blk: np.ndarray, n_noise: int) -> tuple[Any, ...]:
    """Views of the draw block ``blk`` (pulses, 162) [normals × √½] and the scratch of the
    one-pulse path: (complex pairs (pulses, 80), thermal noise (pulses, 4, 16), clutter
    innovation u (pulses, 16), MTI output and product buffers (4, 16), b·u (pulses, 16) and a
    one-item list holding the b [1] it was formed with (None: to form)); ``n_noise`` = 128
    normals of noise per pulse."""
    cx = blk[:, : n_noise + 2 * N_BINS].view(complex)  # CN(0, 1) pairs
    return (cx, cx[:, : n_noise // 2].reshape(blk.shape[0], N_BEAMS, N_BINS),
            cx[:, n_noise // 2 :], np.empty((N_BEAMS, N_BINS), dtype=complex),
            np.empty((N_BEAMS, N_BINS), dtype=complex),
            np.empty((blk.shape[0], N_BINS), dtype=complex), [None])


def clutter_gains_tuple(antenna: MonopulseAntenna, el_a: float, floor: float
                        ) -> tuple[float, float, float, float]:
    """Voltage gains (up, right, down, left) [1] of ``antenna`` toward the horizon at the
    antenna azimuth for antenna elevation ``el_a`` [rad], floored at ``floor`` [1] (sidelobes;
    TargetGenerator module docstring, ground clutter).

    geometry.boresight_offsets(az_a, 0, az_a, el_a) reduces exactly to lateral = 0 (π if the
    antenna is flipped past the zenith, cos el_a < 0) and elevation = asin(−sin el_a) (tested
    equal). max(g, floor) of Python floats: np.maximum's values, NaN kept.
    """
    lat_c = 0.0 if math.cos(el_a) >= 0.0 else math.pi
    el_c = math.asin(-math.sin(el_a))
    g0, g1, g2, g3 = (g if g >= floor or g != g else floor
                      for g in antenna.gains_tuple(lat_c, el_c))
    return g0, g1, g2, g3


#: upper end [rad] of the elevations where :func:`clutter_floor_elevation` applies (cos > 0)
FLOOR_EL_MAX = 1.5


def clutter_floor_elevation(antenna: MonopulseAntenna, floor: float) -> float:
    """Antenna elevation el_lo [rad] above which (up to :data:`FLOOR_EL_MAX`) every gain of
    :func:`clutter_gains_tuple` is the ``floor`` [1] (0 < floor ≤ 1).

    For 0 < s < el_a < π/2 the horizon is at elevation offset −el_a, and of the four gains
    (antenna.py) exp(−a(el_a + s)²) (up), exp(−a(el_a − s)²) (down), exp(−a(el_a² + s²))
    (right, left), the down beam's is the largest, decreasing in el_a; it equals the floor at
    s + √(−ln(floor)/a). A margin of 1e-6 rad (a relative gain margin ≈ 2a·1e-6·√(−ln(floor)/a),
    far above rounding) makes every gain strictly below the floor beyond el_lo.
    """
    a = 0.5 * FOUR_LN2 / antenna.beamwidth**2  # v(θ) = exp(−a θ²) (antenna.py)
    return antenna.squint + math.sqrt(-math.log(floor) / a) + 1e-6
