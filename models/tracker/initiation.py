"""Track initiation and hand-over to confirmed tracking (issue 11, designer's choices;
docs/filters.md "No-track report and track initiation").

- :func:`no_track_report`: what the Tracker reports while it has no track to report (modes
  1-2): where the radar looks.
- :func:`handover_mismatch`: the test of the tentative track against the first confirmed
  measurement (the confirmed cells differ from the tentative ones: the central Doppler filter
  instead of Σ over the three); on a mismatch the Tracker re-centres the track's position on
  that measurement, keeping its velocity and gain schedule (a full restart, n = 1, made
  young confirmed tracks that the manager dropped: 8 drops in 64 plane runs at 30-42 km).
"""

from __future__ import annotations

import math

from ..filters.base import AxisFilter
from ..filters.gains import innovation_factor
from .maneuver import nis_cs
from .outputs import GATE_CENTRE_M


def no_track_report(designation: tuple[float, float, float], gate_true: float, ped_az: float,
                    ped_el: float, ped_ok: bool) -> tuple[float, float, float]:
    """(range [m], az [rad], el [rad]) the Tracker reports in modes 1-2 without a reportable
    track (``track.valid`` false): where the radar looks — the true gate centre of the
    manager's current range hypothesis (``gate_true`` = gate.command + range.offset [m], plus
    the 6 bins to bin 7) and the antenna boresight (pedestal angles) — instead of the
    designation of t = 0, which the target has left (at 42 km the designated range was
    270-560 m off the target when the manager confirmed). Falls back to the designation
    where a value is not finite."""
    des_az, des_el, des_range = designation
    r = gate_true + GATE_CENTRE_M
    rng = r if math.isfinite(r) and r >= 0.0 else des_range
    if ped_ok:
        return rng, ped_az % (2.0 * math.pi), ped_el
    return rng, des_az, des_el


def handover_mismatch(nu: tuple[float, float, float], cs: tuple[float, float, float, float],
                      rho: float, sigma_range: float, sigma_angle: float, fx: AxisFilter,
                      threshold: float) -> bool:
    """True when the first confirmed measurement does not belong to the tentative track: its
    normalised innovation squared (:func:`.maneuver.nis_cs`, innovations ``nu`` [m] of the
    update just made with gains fx.alpha/fx.beta, measurement at range ``rho`` [m] with the
    cos/sin of its azimuth and elevation ``cs``, accuracies σr [m] and σθ [rad]) exceeds
    ``threshold`` (0: always). A track of ≤ 2 points (infinite innovation variance) passes."""
    if threshold <= 0.0:
        return True
    ca, sa, ce, se = cs
    f = innovation_factor(fx.alpha, fx.beta, fx.evolutive)
    return nis_cs(nu, ca, sa, ce, se, rho, sigma_range, sigma_angle, f) > threshold
