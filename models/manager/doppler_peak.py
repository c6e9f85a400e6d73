"""Doppler peak search of a weak detection (issue 11, acquisition and tentative), a mixin of
:class:`~axir.models.manager.machine.RadarManager`.

Seed 000 (acquisition): "Each channel is compared to a threshold. If one result is trespassing
this level, the target is declared present in the cell providing the largest number." With
the Doppler steps of :mod:`.doppler_search` the Doppler cells of one range window are spread
over ``n`` dwells (the 3·n filter positions of the grid PRF/(3·n)), so the first dwell whose
cell crosses the threshold need not hold the largest one: acquisition visits the steps in
ascending order and a target is first seen on its filter's lower skirt (traced, docs/clutter.md
"Doppler peak search": 30 km / −785.71 m/s, three attempts detected 0.04-0.09·PRF below the
target). The three-filter discriminator (:func:`.doppler.doppler_offset`) cannot correct it:
its side filters are PRF/3 away (≈ −24 dB) and read ≈ 0 offset for a weak target anywhere
within ±0.05·PRF of the centre, so the reading falls outside the coherence tolerance
``doppler_tol_fraction`` (0.03·PRF) and tentative loses the true Doppler candidate.

**Peak search** (designer's choice; the seed is silent on Doppler steps). After a weak
detection (excess (A − N)/N below ``doppler_peak_excess``) the manager dwells on grid
positions around the detecting filter (same range window, same PRI), up to
``doppler_peak_dwells`` extra dwells: each time on the unmeasured position nearest to the
offset that best fits the measured responses to the resonator profile
(:meth:`DopplerPeakMixin._peak_fit`), or on a neighbour of it, so that the fit brackets the
peak. The response at a position is the detected range cell's amplitude in that filter less
the median over the 16 range cells (robust to the one target). The reading is the fitted
position (traced: within 0.001-0.002·PRF of the truth, far inside the coherence tolerance).
The search starts from the cell that crossed the threshold (not the largest excess: a
clutter filter's fluctuation can exceed a target's skirt below its higher threshold). The
detection's range bin is kept. A strong detection (excess ≥ ``doppler_peak_excess``) is read
at once (its side filters carry the offset; the default scenario's path is unchanged), unless
its side filters hold only noise (``doppler_peak_side``: at the 2nd and 3rd tentative PRI, and
with ``acq_peak_side`` at an acquisition detection in the clutter filter).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..radar.conventions import CENTRE_FILTER, N_DOPPLER, fold_doppler
from .doppler import resonator_gain

_CF = CENTRE_FILTER - 1  # 0-based central Doppler filter
#: half-width [grid positions] of the offset search of the profile fit (designer's choice: a
#: strong target's skirt was detected 3-4 positions from its peak, traced)
PEAK_REACH = 6


@dataclass
class Peak:
    """A peak search in progress (plain data)."""

    active: bool = False
    row: int = 0  # 0-based range bin of the detected cell in the gate
    m: int = 0  # apparent range bin of the detection at its PRI
    resp: dict[int, float] = field(default_factory=dict)  # grid position → response
    pending: int = 0  # grid position being measured
    extra: int = 0  # extra dwells spent
    pri_idx: int = 0
    gate_bin: int = 0
    offset_bins: int = 0
    excess: float = 0.0  # excess of the detecting dwell
    then: str = ""  # "acq" or "tent": where the reading goes


class DopplerPeakMixin:
    """Doppler peak search over the grid positions of the Doppler steps."""

    def _peak_wanted(self, excess: float, side: float = math.inf) -> bool:
        """A detection of excess ``excess`` gets a peak search (``doppler_peak_dwells`` > 0,
        Doppler selectivity, excess below ``doppler_peak_excess``, or its largest side-filter
        excess ``side`` below ``doppler_peak_side`` > 0: the discriminator has nothing to read;
        a side excess is negative when a side filter reads below its noise level, so 0 must
        switch the side test off explicitly)."""
        ps = self.doppler_peak_side
        return (self.doppler_peak_dwells > 0 and self.doppler_pole > 0.0 and self._n_steps > 1
                and (excess < self.doppler_peak_excess or (ps > 0.0 and side < ps)))

    @staticmethod
    def _side_excess(acc_row: np.ndarray, noise: np.ndarray) -> float:
        """Largest excess (A − N)/N of a detected cell ``acc_row`` (3,) over the noise levels
        ``noise`` (3,) in the two filters beside the one where its excess is largest (inf when
        a level is not positive)."""
        ex = acc_row - noise
        f = int(np.argmax(ex))
        out = -math.inf
        for i in range(N_DOPPLER):
            if i != f:
                n = float(noise[i])
                out = max(out, float(ex[i]) / n if n > 0.0 else math.inf)
        return out

    def _grid_pos(self, step: int, f: int) -> int:
        """Grid position (0 … 3·n − 1) of filter ``f`` (0-based) at Doppler step ``step``."""
        n = self._n_steps
        return (step + n * (f - _CF)) % (N_DOPPLER * n)

    def _pos_step_filter(self, q: int) -> tuple[int, int]:
        """(Doppler step, 0-based filter) holding grid position ``q``."""
        n = self._n_steps
        q %= N_DOPPLER * n
        s = q % n
        return s, ((q - s) // n + _CF) % N_DOPPLER

    def _peak_response(self, row: int, f: int) -> float:
        """Response of the current dwell's cell (``row``, filter ``f``): its amplitude less the
        median of the filter's 16 range cells."""
        acc = self._dwell.acc
        return float(acc[row, f] - np.median(acc[:, f]))

    def _start_peak(self, row: int, f: int, m: int, step: int, gate_bin: int,
                    offset_bins: int, excess: float, then: str) -> None:
        """Begin the peak search of a detection in cell (``row``, ``f``; apparent bin ``m``)
        at Doppler step ``step`` of the gate ``gate_bin`` / ``offset_bins`` [bins] of the
        current PRI; ``then``: "acq" (enter tentative with the reading) or "tent" (a tentative
        measurement)."""
        p = self._peak
        q = self._grid_pos(step, f)
        p.active = True
        p.row = row
        p.m = m
        p.resp = {q: self._peak_response(row, f)}
        p.extra = 0
        p.pri_idx = self._pri_idx
        p.gate_bin = gate_bin
        p.offset_bins = offset_bins
        p.excess = excess
        p.then = then
        self._peak_visit(q + 1)

    def _peak_visit(self, q: int) -> None:
        p = self._peak
        p.pending = q % (N_DOPPLER * self._n_steps)
        s, _ = self._pos_step_filter(q)
        p.extra += 1
        self._set_step(s, p.pri_idx)
        self._command(p.gate_bin, p.pri_idx, p.offset_bins)

    def _peak_fit(self) -> float:
        """Offset [grid positions] of the target from the best measured position: the offset
        whose resonator-gain profile best fits the measured responses in least squares over
        the unknown scale (the maximum of (Σ a·h)/√(Σ h²), as :func:`.doppler.doppler_offset`
        but over the close grid positions), searched within ``PEAK_REACH`` positions on a
        1/20-position grid and refined by a parabola."""
        p = self._peak
        n_pos = N_DOPPLER * self._n_steps
        best = max(p.resp, key=lambda q: p.resp[q])
        qs = [q for q in p.resp if math.isfinite(p.resp[q])]
        rel = np.array([((q - best + n_pos // 2) % n_pos) - n_pos // 2 for q in qs], float)
        a = np.array([max(p.resp[q], 0.0) for q in qs])
        grid = self.doppler_spacing_fraction / self._n_steps  # [cycles] between positions
        x = np.arange(-PEAK_REACH * 20, PEAK_REACH * 20 + 1) / 20.0
        h = resonator_gain((rel[None, :] - x[:, None]) * grid, self.doppler_pole)
        score = (h @ a) / np.sqrt(np.einsum("ij,ij->i", h, h))
        i = int(np.argmax(score))
        d = float(x[i])
        if 0 < i < len(x) - 1:
            s0, s1, s2 = score[i - 1], score[i], score[i + 1]
            den = s0 - 2.0 * s1 + s2
            if den < 0.0:
                d += 0.5 * (s0 - s2) / den / 20.0
        return best + d

    def _peak_dwell(self, ok: bool) -> None:
        """A dwell of the peak search ended: record the response; while dwells are left, visit
        the unmeasured position nearest to the fitted peak (:meth:`_peak_fit`), or a
        neighbour of it, so that the fit brackets it; then hand the reading to acquisition /
        tentative."""
        p = self._peak
        n_pos = N_DOPPLER * self._n_steps
        _, f = self._pos_step_filter(p.pending)
        p.resp[p.pending] = self._peak_response(p.row, f) if ok else -math.inf
        centre = self._peak_fit()
        if p.extra < self.doppler_peak_dwells:
            c = round(centre)
            for q in (c, c + 1 if centre >= c else c - 1, c - 1 if centre >= c else c + 1):
                if q % n_pos not in p.resp:
                    self._peak_visit(q)
                    return
        prf = 1.0 / self._pris[p.pri_idx]
        grid = self.doppler_spacing_fraction * prf / self._n_steps
        fd = fold_doppler(self.doppler_search_centre + centre * grid, self._pris[p.pri_idx])
        p.active = False
        if p.then == "acq":
            self._enter_tentative(p.m, fd)
        else:
            self._tent_reading(p.m, fd, self._weak(p.excess))
