"""Servo-bandwidth and α-β gain scheduling of the radar manager (seed 000: "The bandwidths of
the servo-loops are progressively reduced up to a certain limit"; "The Radar Manager is
responsible for updating the Alpha-Beta coefficients"), a mixin of
:class:`~axir.models.manager.machine.RadarManager` (the laws are described in its module
docstring, *Confirmed*)."""

from __future__ import annotations

from ..filters.gains import kalata_gains
from ..radar.conventions import CONFIRMED


class ScheduleMixin:
    """Bandwidth and steady-gain updates, called once per step by the state machine."""

    def _update_schedule(self) -> None:
        """The servo bandwidth, then the steady gains, of this step (one call per step, issue
        14 round 7: formerly ``_update_bandwidth`` and ``_update_gains``, the same bodies)."""
        confirmed = self.mode == CONFIRMED
        # bandwidth: bw_start → bw_floor exponentially over bw_decay_time of confirmed tracking
        if not confirmed:
            self._bw = self.bw_start
        else:
            decay = self.bw_decay_time
            conf_time = self._track.conf_time
            if decay <= 0.0 or conf_time >= decay:
                self._bw = self.bw_floor
            else:
                x = conf_time / decay
                self._bw = self.bw_start * (self.bw_floor / self.bw_start) ** x
        # steady gains: Kalata's for the tracking index of σm (opened after a maneuver) and T
        opened = self._track.since_maneuver <= self.maneuver_hold
        sigma_m = self.sigma_man_high if opened else self.sigma_man
        t = self._pris[self._pri_idx]  # the current PRI [s]
        key = (sigma_m, t)
        if key != self._gains_key:
            self._gains_key = key
            self._lambda = sigma_m * t * t / self.sigma_meas
            self._gains = kalata_gains(self._lambda)
        # SYSTEM.md: evolutive gains until the manager's steady gains take over. The Tracker
        # (filters.gains.scheduled_gains) uses max(evolutive(n), steady) per gain, so the steady
        # gains are sent throughout confirmed tracking and the tracker hands over itself when
        # its α(n) falls below them; 0 in acquisition / tentative (evolutive only, seed 000:
        # "Alpha-Beta filters with a short time constant").
        if not confirmed:
            self._alpha = self._beta = 0.0
        else:
            self._alpha, self._beta = self._gains
