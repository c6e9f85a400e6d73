"""Threshold factors and the range-cell spread estimate of the radar manager's dwell ends, a
mixin of :class:`~axir.models.manager.machine.RadarManager` (seed 000: Th1 in acquisition, Th2
in tentative and confirmed tracking; the statistics are in :mod:`.thresholds`, the beam-common
clutter residue in :mod:`.residue`)."""

from __future__ import annotations

import numpy as np

from .hotpath import clutter_flags, ema_at
from .residue import residue_floors
from .thresholds import spread_estimate, threshold_factors, update_spread


class ThresholdsMixin:
    """Per-filter threshold factors of the current dwell and the spread estimate's update."""

    def _factors(self, pfa: float, which: int) -> np.ndarray:
        """Threshold factors per Doppler filter for the current dwell (``which``: 0 = /median,
        1 = /mean; :func:`.thresholds.threshold_factors`, clutter-aware with
        ``adaptive_looks``)."""
        if not self.adaptive_looks:
            return threshold_factors(self.looks_per_pri, self._dwell_length(),
                                     self.doppler_pole, pfa, which, None, None, None)
        self._positions()
        pos = self._pos_list
        # level above the thermal floor (the quietest position class): partly clutter, and
        # the clutter residue after the MTI canceller (issue 11): a level far above the
        # calibrated thermal level (hotpath.clutter_flags; issue 14: in Python floats)
        excess, common = clutter_flags(self._noise_pos, pos, self._thermal_level,
                                       self.residue_level_ratio)
        spread = [self._spread_pos.item(p) for p in pos]
        k = self._dwell_length()
        out = threshold_factors(self.looks_per_pri, k, self.doppler_pole, pfa, which, spread,
                                excess, common)
        if self.residue_share_looks:  # the beam-common residue share's looks (residue.py)
            np.maximum(out, residue_floors(self._class_shares, pos, self.looks_per_pri, k,
                                           self.doppler_pole, pfa, which), out=out)
        return out

    def _update_shape(self, cells: np.ndarray) -> None:
        """Update the per-filter spread estimate from ``cells`` (m, 3) of this dwell
        (:func:`.thresholds.update_spread`; only with ``adaptive_looks``)."""
        if not self.adaptive_looks:
            return
        pos = self._positions()
        n = self.looks_per_pri * self._dwell_length()
        est = spread_estimate(cells, n)  # one percentile for both updates
        seen = self._spread_seen
        if all([seen.item(p) for p in self._pos_list]):  # issue 14: the EMA everywhere
            ema_at(self._spread_pos, self._pos_list, est, self.noise_avg_dwells)
            return
        ema = self._spread_pos[pos]
        seen = seen[pos]
        fresh = ema.copy()
        update_spread(ema, cells, n, self.noise_avg_dwells, est)
        update_spread(fresh, cells, n, 1.0, est)  # a class's first dwell: its own estimate
        self._spread_pos[pos] = np.where(seen, ema, fresh)
        self._spread_seen[pos] = True
