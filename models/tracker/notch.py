"""A confirmed track's coast through the clutter notch (issue 11, session 30; designer's choice,
the seeds are silent; docs/clutter.md "Through the clutter notch").

**Why.** A target whose radial speed passes through 0 — every target flying past the radar,
at its closest point, and a turn across the line of sight — has its Doppler in the clutter
notch for 2·v_n/a_r (a_r = |v_t|²/r the radial acceleration of straight flight, v_t the
speed across the line of sight: 1.6 s for ±5 m/s at 10 km and 250 m/s). Below ≈ 4.5° the
confirmed cell then holds the ground clutter's residue, not the target: measured (10 km, 2°,
10 m², 250 m/s across), the readings walked the track 0.66° toward the ground within 0.2 s
of the radial speed reaching −1.7 m/s, and the manager dropped the track; it was found again
0.3-2 s later (every such crossing cell of the sweep in docs/clutter.md was dropped).

**Design.** While the manager's Doppler (``doppler.range_rate``, measured to 1-2 m/s by its
Doppler loop, against 4-12 m/s for the filter's range rate) is within ``notch_coast_speed``
of 0 (the manager's ``clutter_notch_speed``), the antenna below ``notch_coast_max_el``, the
track old enough (:data:`MIN_N` readings) and its averaged velocity (:data:`TAU`) says that
straight flight carries the range rate from where it is (≤ 0: constant-velocity motion only
raises the range rate, so a receding target in the band is leaving it, or sits beside the
notch at a slow radial speed) to +``notch_coast_speed`` within ``notch_cross_time``, the
track coasts: its readings are not used. On entering, its range rate is set to the manager's
Doppler; the coast goes on while the Doppler is within ``NOTCH_EXIT`` × the speed (once the
manager misses the target it predicts that Doppler from the coasting range rate:
RadarManager ``notch_coast_time``), for at most :data:`MAX_COASTS` × ``notch_cross_time``.
The averaged velocity, not the filter's, decides: the
velocity of a young track, or of one pulled by clutter, is angle noise × range (10²-10³ m/s
across the line of sight) and averages out; the filter's own covariance does not show it
(√tr P_vv = 72 m/s where the error was 480 m/s).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from ..radar.conventions import NOTCH_EXIT as EXIT  # the band's exit, shared with the manager

#: a coast needs a track of this many readings (≈ 0.3 s)
MIN_N = 3000
#: time constant [s] of the averaged velocity, averaged from MIN_N/2 readings on
TAU = 0.2
#: a coast longer than this × notch_cross_time is not a crossing (a target turning to fly
#: across the line of sight, or hovering): it ends, and starts again only after the Doppler
#: has left the band
MAX_COASTS = 2.0
#: the average must hold this × TAU of steps (Σ dᵏ·dt) before it decides: it holds ≥ 0.38 ×
#: TAU when a track first reaches MIN_N readings (≥ MIN_N/2 steps, at the shortest PRI, 64 µs)
MIN_AVERAGE = 0.3


class NotchCoast:
    """The notch-coast decision of one Tracker: speed [m/s] (0: off), maximum antenna
    elevation [rad], crossing time [s]; its state: coasting, and the averaged velocity."""

    def __init__(self, speed: float, max_el: float, cross_time: float) -> None:
        self.speed, self.max_el, self.cross_time = speed, max_el, cross_time
        self._dt, self._d = 0.0, 1.0  # the last step [s] and its decay e^(−dt/TAU)
        self.reset()

    def reset(self) -> None:
        """A new track: no coast, no average."""
        self.on = False
        self.t_on = 0.0  # time coasting [s] (kept after a time-out until the band is left)
        self.vbar = [0.0, 0.0, 0.0, 0.0]  # Σ dᵏ·v (x, y, z) [m/s], Σ dᵏ

    def __call__(self, axes: Sequence[Any], rate: float, el: float, dt: float) -> bool:
        """One confirmed step of ``dt`` [s] of the track filtered by ``axes`` (x, y, z with
        ``pos``, ``vel``, ``n``; filters with a velocity state only): True while it coasts
        (module docstring); ``rate`` [m/s]: the manager's Doppler as a range rate (NaN: none),
        ``el`` [rad]: the antenna elevation (above ``max_el`` nothing is averaged: the
        average restarts below it; a non-finite velocity is left out of it). Sets the axes'
        velocity on entering."""
        if not (self.speed > 0.0 and el <= self.max_el):  # (also False for a NaN elevation)
            if self.vbar[3]:  # above the clutter regime: no coast, the average restarts
                self.reset()
            self.on = False
            return False
        fx, fy, fz = axes
        vb = self.vbar
        if fx.n >= MIN_N // 2 and math.isfinite(fx.vel + fy.vel + fz.vel):
            if dt != self._dt:  # e^(−dt/τ), computed again only when the PRI changes
                self._dt, self._d = dt, math.exp(-dt / TAU) if dt > 0.0 else 1.0
            d = self._d
            vb[0], vb[1], vb[2], vb[3] = (d * vb[0] + fx.vel, d * vb[1] + fy.vel,
                                          d * vb[2] + fz.vel, d * vb[3] + 1.0)
        v_n = self.speed
        if not (-v_n * EXIT <= rate <= v_n * EXIT and fx.n >= MIN_N):
            if rate == rate:  # a Doppler outside the band (NaN: none this step, latch kept)
                self.t_on = 0.0
            self.on = False
            return False
        if self.on:  # a coast ends after MAX_COASTS × notch_cross_time: not a crossing
            if dt > 0.0:
                self.t_on += dt
            self.on = self.t_on <= MAX_COASTS * self.cross_time
            return self.on
        if self.t_on > 0.0 or not -v_n <= rate <= 0.0:  # (timed out: not again in this band)
            return False
        px, py, pz = fx.pos, fy.pos, fz.pos
        r2 = px * px + py * py + pz * pz
        if not (r2 > 0.0 and vb[3] * dt >= MIN_AVERAGE * TAU):  # (an average restarted
            return False  # after the antenna rose above max_el: not yet one)
        w = 1.0 / vb[3]
        vx, vy, vz = vb[0] * w, vb[1] * w, vb[2] * w
        r = math.sqrt(r2)
        vr = (px * vx + py * vy + pz * vz) / r
        t2 = vx * vx + vy * vy + vz * vz - vr * vr  # |v_t|² of the average [m²/s²]
        if not t2 * self.cross_time >= (v_n - rate) * r:  # a_r·t ≥ Δṙ, a_r = |v_t|²/r
            return False
        # the filter's range rate onto the manager's (only the line-of-sight part moves)
        k = (rate - (px * fx.vel + py * fy.vel + pz * fz.vel) / r) / r
        fx.vel += k * px
        fy.vel += k * py
        fz.vel += k * pz
        self.on, self.t_on = True, 0.0
        return True
