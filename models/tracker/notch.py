"""A confirmed track's coast through the clutter notch (issue 11, sessions 30-31; designer's
choice, the seeds are silent; docs/clutter.md "Through the clutter notch").

**Why.** A target whose radial speed passes through 0 — every target flying past the radar,
at its closest point, and a turn across the line of sight — has its Doppler in the clutter
notch for 2·v_n/a_r (a_r = |v_t|²/r the radial acceleration of straight flight, v_t the
speed across the line of sight: 1.6 s for ±5 m/s at 10 km and 250 m/s, 10 s at 12 km and
110 m/s). Below ≈ 4.5° the confirmed cell then holds the ground clutter's residue, not the
target: measured (10 km, 2°, 10 m², 250 m/s across), the readings walked the track 0.66°
toward the ground within 0.2 s of the radial speed reaching −1.7 m/s, and the manager dropped
the track; it was found again 0.3-2 s later (every such crossing cell of the sweep in
docs/clutter.md was dropped).

**Design.** While the manager's Doppler (``doppler.range_rate``, measured to 1-2 m/s by its
Doppler loop, against 4-12 m/s for the filter's range rate) is within ``notch_coast_speed``
of 0 (the manager's ``clutter_notch_speed``), the antenna below ``notch_coast_max_el``, the
track old enough (:data:`MIN_N` readings) and straight flight at its fitted velocity
(:class:`LineFit`) carries the range rate from where it is (≤ 0: constant-velocity motion only
raises the range rate, so a receding target in the band is leaving it, or sits beside the
notch at a slow radial speed) to +``notch_coast_speed`` within ``notch_cross_time``, the
track coasts: its readings are not used. On entering, its velocity is set to the fitted one
across the line of sight and to the manager's Doppler along it; the coast goes on while the
Doppler is within ``NOTCH_EXIT`` × the speed (once the manager misses the target it predicts
that Doppler from the coasting range rate: RadarManager ``notch_coast_time``), for at most
:data:`MAX_COASTS` × ``notch_cross_time``.

**The fitted velocity, not the filter's** (session 31). The velocity of a young track, or of
one pulled by clutter, is angle noise × range (10²-10³ m/s across the line of sight; the
filter's √tr P_vv said 72 m/s where the error was 480 m/s), and a coast of seconds carries its
error into the position: measured, 100 m/s of vertical velocity error at 12 km walked a coast
2.4° off within 5 s. A straight line fitted to the track's positions over :data:`TAU_FIT` (a
fading-memory least-squares fit) measures a straight flight's velocity from a baseline of a
second instead of the filter's few milliseconds: the same coast stayed within 0.12° for 7 s.
Session 30 decided on the filter velocity's 0.2 s average and kept the filter's velocity for
the coast.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from ..radar.conventions import NOTCH_EXIT as EXIT  # the band's exit, shared with the manager

_INF = math.inf
#: a coast needs a track of this many readings (≈ 0.3 s; with MIN_FIT_SPAN the first entry
#: comes ≥ MIN_N/2 readings + ≈ 0.29 s into a track)
MIN_N = 3000
#: time constant [s] of the line fit's fading memory (weights e^(−age/TAU_FIT)), fitted from
#: MIN_N/2 readings on
TAU_FIT = 1.0
#: the fit decides once it holds this much time [s] (Σ weights × PRI; 0.25 s ≈ 0.29 s of
#: readings): the slope's error from correlated angle noise falls as span^(−3/2). In
#: tests/test_notch_coast.py a slow radial target's positions with σ 10 m of noise across the
#: line of sight (1 mrad at 10 km, correlated over 10 ms) fake a crossing with 0.06 s, not
#: with 0.25 s (σ 15 m still does: a limit, docs/clutter.md)
MIN_FIT_SPAN = 0.25
#: a coast longer than this × notch_cross_time is not a crossing (a target turning to fly
#: across the line of sight, or hovering): it ends, and starts again only after the Doppler
#: has left the band
MAX_COASTS = 2.0


class LineFit:
    """A fading-memory least-squares straight line through 3-D positions: sample k of age
    a_k [s] weighs e^(−a_k/τ); its slope is the velocity [m/s]. Kept as the weighted sums of
    1, t, t², p and t·p with t = −age relative to the newest sample (each step shifts them
    by its ``dt``: O(1) per step, for any PRI schedule), p relative to the first position (no
    cancellation at ranges of 10⁴-10⁵ m)."""

    def __init__(self, tau: float) -> None:
        self.tau = tau
        self._dt, self._d = 0.0, 1.0  # the last step [s] and its decay e^(−dt/τ)
        self.s = [0.0] * 9  # Σw, Σw·t, Σw·t², Σw·x, Σw·t·x, Σw·y, Σw·t·y, Σw·z, Σw·t·z
        self.p0 = (0.0, 0.0, 0.0)

    def reset(self) -> None:
        """No sample (the sums zeroed in place)."""
        self.s[:] = (0.0,) * 9

    def add(self, x: float, y: float, z: float, dt: float) -> None:
        """A new position [m], ``dt`` [s] after the previous one (a negative or non-finite
        ``dt`` leaves the sample out: it would corrupt the sums for good)."""
        if not 0.0 <= dt < _INF:
            return
        s = self.s
        if not s[0]:
            self.p0 = (x, y, z)
        if dt != self._dt:  # e^(−dt/τ), computed again only when the PRI changes
            self._dt, self._d = dt, math.exp(-dt / self.tau) if dt > 0.0 else 1.0
        d = self._d
        p0 = self.p0
        s0, s1 = s[0], s[1]  # the older samples' t moves by −dt: Σw(t−dt)ⁿ, then × d
        s[2] = d * (s[2] - 2.0 * dt * s1 + dt * dt * s0)
        s[1] = d * (s1 - dt * s0)
        s[0] = d * s0 + 1.0
        s[4] = d * (s[4] - dt * s[3])
        s[3] = d * s[3] + (x - p0[0])
        s[6] = d * (s[6] - dt * s[5])
        s[5] = d * s[5] + (y - p0[1])
        s[8] = d * (s[8] - dt * s[7])
        s[7] = d * s[7] + (z - p0[2])

    def span(self) -> float:
        """Σ weights × the last step [s]: ≈ the time the fit holds (at most τ + dt/2)."""
        return self.s[0] * self._dt

    def velocity(self) -> tuple[float, float, float] | None:
        """The fitted line's slope (vx, vy, vz) [m/s]; None before two distinct times."""
        s = self.s
        den = s[0] * s[2] - s[1] * s[1]
        if not den > 0.0:
            return None
        return ((s[0] * s[4] - s[1] * s[3]) / den, (s[0] * s[6] - s[1] * s[5]) / den,
                (s[0] * s[8] - s[1] * s[7]) / den)


class NotchCoast:
    """The notch-coast decision of one Tracker: speed [m/s] (0: off), maximum antenna
    elevation [rad], crossing time [s]; its state: coasting, and the line fit."""

    def __init__(self, speed: float, max_el: float, cross_time: float) -> None:
        self.speed, self.max_el, self.cross_time = speed, max_el, cross_time
        self.fit = LineFit(TAU_FIT)
        self._s = self.fit.s  # (the fit's sums: one list for its lifetime)
        self.reset()

    def reset(self) -> None:
        """A new track: no coast, no fit."""
        self.on = False
        self.t_on = 0.0  # time coasting [s] (kept after a time-out until the band is left)
        self.fit.reset()

    def __call__(self, axes: Sequence[Any], rate: float, el: float, dt: float) -> bool:
        """One confirmed step of ``dt`` [s] of the track filtered by ``axes`` (x, y, z with
        ``pos``, ``vel``, ``n``; filters with a velocity state only): True while it coasts
        (module docstring); ``rate`` [m/s]: the manager's Doppler as a range rate (NaN: none),
        ``el`` [rad]: the antenna elevation (above ``max_el`` nothing is fitted: the fit
        restarts below it; a non-finite position is left out of it). Sets the axes'
        velocity on entering."""
        if not (self.speed > 0.0 and el <= self.max_el):  # (also False for a NaN elevation)
            if self._s[0]:  # above the clutter regime: no coast, the fit restarts
                self.reset()
            self.on = False
            return False
        fit = self.fit
        fx, fy, fz = axes
        px, py, pz = fx.pos, fy.pos, fz.pos
        if fx.n >= MIN_N // 2 and math.isfinite(px + py + pz):
            fit.add(px, py, pz, dt)
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
        r2 = px * px + py * py + pz * pz
        v = fit.velocity() if fit.span() >= MIN_FIT_SPAN else None  # (a fit restarted
        if not (r2 > 0.0 and v is not None):  # after the antenna rose above max_el: not yet)
            return False
        vx, vy, vz = v
        r = math.sqrt(r2)
        vr = (px * vx + py * vy + pz * vz) / r
        t2 = vx * vx + vy * vy + vz * vz - vr * vr  # |v_t|² of the fit [m²/s²]
        if not t2 * self.cross_time >= (v_n - rate) * r:  # a_r·t ≥ Δṙ, a_r = |v_t|²/r
            return False
        # the fit's velocity across the line of sight, the manager's Doppler along it
        k = (rate - vr) / r
        fx.vel, fy.vel, fz.vel = vx + k * px, vy + k * py, vz + k * pz
        self.on, self.t_on = True, 0.0
        return True
