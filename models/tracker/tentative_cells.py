"""The tentative gate cells' two corrections of session 24 (issue 11; designer's choices:
SYSTEM.md reads the tentative deviations on the Σ over the 3 Doppler filters, seed 000 says no
more). Pure functions of arrays and floats, called from
:class:`~.beam_helpers.BeamHelpers` at tentative PRIs only.

- :func:`clutter_free_filters`: a side filter that holds clutter is left out of the angle
  readings' Σ (``Tracker.tentative_clutter_ratio``);
- :func:`tentative_edge`: a reading beyond the beam's edge is read on the centre filter's cell
  across the other pair (``Tracker.tentative_edge_fraction``, :func:`.cells.edge_reading`).
"""

from __future__ import annotations

import numpy as np

from .cells import _BACKGROUND_BINS, _N_BACKGROUND, background_sum, edge_reading
from .deviations import dif_sum

_add_reduce = np.add.reduce


def clutter_free_filters(beams: np.ndarray, sums: np.ndarray, ratio: float
                         ) -> tuple[np.ndarray, np.ndarray, int]:
    """The beams (4, 16, F) and SUMs (16, F) of the filters the tentative angle readings
    keep, and F.

    A side filter (the first or the third: the manager centres the tentative bank on the
    detected filter, so the target is in the second) whose mean background SUM (bins 1-4,
    10-16) exceeds ``ratio`` × the quietest filter's holds clutter, not the target, and is left
    out of the angle readings' Σ (and of the tentative report's noise correction); the range
    profile, the weak-signal check and the noise level stay SYSTEM.md's Σ over the 3 filters
    (leaving it out of those as well changed the tentative histories of 20-60 km cells: two
    late locks and a false sample in a not-detectable cell, session 24). The centre filter is
    always kept (at a blind PRI it holds the clutter with the target). ``ratio`` ≤ 0,
    or a non-finite background: all three. Traced (42 km, −857.14 m/s, 5°, 10 m², seed 1):
    the third filter on the clutter line held the down beam's clutter at 2.2 × the
    background, every tentative elevation reading was −0.5° to −0.7° with the target 0.34°
    above the boresight, and the confirming PRI reported it 1.35° off. With ratio 2 the mean
    of 11 bins of thermal noise (σ/mean ≈ 0.08) never reaches it: only clutter ≥ 4.8 dB above
    the noise does."""
    if ratio > 0.0:
        b0, b1, b2 = _add_reduce(sums[_BACKGROUND_BINS], 0).tolist()
        lo = min(b0, b1, b2) * ratio
        if (b0 > lo or b2 > lo) and b0 + b1 + b2 < np.inf:  # (none for NaN or inf)
            keep = [not b0 > lo, True, not b2 > lo]
            return beams[:, :, keep], sums[:, keep], 1 + keep[0] + keep[2]
    return beams, sums, 3


def tentative_edge(cell: list[float], centre_sums: list[float], inv_slope: float,
                   edge: tuple[float, float, float], dev_el: float, dev_lat: float
                   ) -> tuple[float, float, tuple[bool, bool]]:
    """(dev_el, dev_lat) [rad] of a tentative reading whose Σ deviation is beyond the trigger
    on an axis, and which axes took the edge reading.

    ``cell`` = (u, r, d, l) of the centre filter in the strongest gate bin, ``centre_sums`` the
    centre filter's SUM column (16, its background bins give the noise level); ``inv_slope`` =
    1/k_m [rad], ``edge`` as :func:`.cells.edge_reading`'s. The cell is read as a confirmed
    one: an axis beyond the edge there takes the edge reading; the other axis, and an axis
    the edge reading leaves alone, keep the Σ's deviation. Traced (10 km, −53 m/s, 5°, 1 m²,
    designation (0, −2.5°), seed 2): the Σ over three filters holds two filters' noise in
    both beams of a pair, so a target 2.8° off the boresight read +1.0° to +1.4° in every
    tentative reading and the confirming PRI reported it 1.33° off; the centre filter's edge
    reading reads ≈ 1.65-1.75° (the linear law's noise-free value of 2.8° is 1.69°)."""
    u, r, d, lf = cell
    c_el = dif_sum(u, d) * inv_slope if u + d > 0.0 else 0.0  # the linear law, ε/k_m
    c_lat = dif_sum(r, lf) * inv_slope if r + lf > 0.0 else 0.0
    noise = background_sum(centre_sums) / _N_BACKGROUND
    e_el, e_lat = edge_reading(u, r, d, lf, noise, c_el, c_lat, edge)
    used = (e_el != c_el, e_lat != c_lat)
    return (e_el if used[0] else dev_el), (e_lat if used[1] else dev_lat), used
