"""Angular acquisition search around the designation (issue 11, session 15).

The seeds acquire at the designated direction only: seed 000's acquisition searches the 16
range gates and 3 Doppler filters of one beam position. A designation more than about a
beamwidth off the target (a cue from another sensor) then never finds it: at 3.5-5° off
the boresight the SUM of the four beams is 16-35 dB down (``radar/antenna.py``).

Designer's choice (the seeds are silent): the radar alternates a dwell on the designation
with one lap of a circle around it.

- Dwell: ``dwell`` seconds on the designation.
- Lap: one turn, taking ``period`` seconds, of a circle of angular radius ``radius`` around
  the designation. It starts straight above it and runs toward increasing azimuth. The
  lateral offset is radius·sin φ and the elevation offset radius·cos φ, with
  φ = 2π·t/period.
- The pattern repeats for as long as the manager stays in acquisition.

An option, off by default (``Tracker.search_radius`` 0): a moving beam raises the
acquisition false-alarm rate in clutter and across the MTI canceller's switching elevation,
and the manager has no input telling it that the beam moves (docs/filters.md "Acquisition
search around the designation").

A radius of one 3 dB beamwidth (2.5°, the value to turn it on) puts every direction within
1.25-3.75° of the designation inside the beam's 3 dB contour at some point of the lap, and
the dwell covers the centre. The pedestal follows the moving direction with the Tracker's
position loop plus the pattern's angular rate (a feed-forward). At the default 1.5 s lap the
boresight moves at 2π·2.5°/1.5 s ≈ 10.5°/s and accelerates at ≈ 0.77 rad/s² in elevation,
within the Pedestal's 1 rad/s and 2 rad/s² limits.

The lap never looks below ``min(designation elevation, min_el)``: a circle around a
low designation would otherwise put the main beam into the ground clutter.

At high elevation the look direction's azimuth moves by the lateral offset / cos el, so the
Tracker lengthens the lap to at least 2π·√(radius/(accel·cos el)) (``Tracker.search_accel``,
1 rad/s²: half the Pedestal's default limit; el the designation's): 1.5 s up to ≈ 40°,
1.86 s at 60°, 3.15 s at 80°. Found on two random engagements at 60° and 80°, where the
1.5 s lap asked the pedestal for up to 4.4 rad/s² in azimuth and the distorted path ended in
short false confirmations.
"""

from __future__ import annotations

from math import cos, inf, sin, sqrt

from ..radar.geometry import TWO_PI


def lap_period(period: float, radius: float, accel: float, cos_el: float) -> float:
    """Duration of one lap [s]: ``period``, or longer where the look direction's azimuth
    acceleration radius·ω²/cos el would exceed ``accel`` [rad/s²] (module docstring;
    ``cos_el`` > 0 the cosine of the designation's elevation): at least
    2π·√(radius/(accel·cos el))."""
    return max(period, TWO_PI * sqrt(radius / (accel * cos_el)))


def search_offset(clock: float, dwell: float, period: float,
                  radius: float) -> tuple[float, float, float, float]:
    """(lateral, elevation) offset of the look direction from the designation [rad] and
    their rates [rad/s], ``clock`` [s] after the acquisition began: (0, 0, 0, 0) during a
    dwell, on the lap's circle otherwise (module docstring). ``radius`` ≤ 0 or ``period``
    ≤ 0: no search (always 0)."""
    if not (radius > 0.0 and period > 0.0 and clock >= dwell):
        return 0.0, 0.0, 0.0, 0.0
    u = (clock - dwell) % (dwell + period)  # time into the current lap (or the next dwell)
    if u >= period:
        return 0.0, 0.0, 0.0, 0.0
    w = TWO_PI / period  # [rad/s]
    phi = w * u
    s, c = sin(phi), cos(phi)
    return radius * s, radius * c, radius * w * c, -radius * w * s


def velocity_known(n: int, info: float, info_req: float, pri: float, horizon: float) -> bool:
    """A lost track's velocity carries its direction over ``horizon`` [s] within the
    initiation accuracy σ = 1/√``info_req`` (session 25, issue 11; ``reacquire_time``).

    A line fitted to n readings over a span D has a slope of variance 12 σθ²/(n D²), σθ² the
    variance of one reading; with the track's angle information J = n/σθ² that is 12/(J D²).
    Over the horizon the extrapolated direction then errs by √12·horizon/(√J·D), within σ
    when D·√(J/info_req) ≥ √12·horizon. D is taken as n × ``pri`` (readings at most one per
    PRI: never longer than the true span). Traced (random draw 13, 38.9 km / 1.8 m²,
    not detectable): a track confirmed for 0.09 s had an azimuth rate of 2.1°/s for a
    target moving at 0.2°/s; the reacquisition followed it and left the target 1.5-1.9°
    off the boresight, where the next confirmation's young report was off the target.
    False for a NaN, a non-positive argument or an infinite span; J = ∞ (noise-free
    readings): known."""
    span = n * pri
    if not (span > 0.0 and info > 0.0 and info_req > 0.0 and span < inf):
        return False
    return span * sqrt(info / info_req) >= sqrt(12.0) * horizon
