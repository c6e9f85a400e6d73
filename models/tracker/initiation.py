"""Track initiation and hand-over to confirmed tracking (issue 11, designer's choices;
docs/filters.md "No-track report and track initiation").

- :func:`no_track_report`: what the Tracker reports while it has no track to report (modes
  1-2): where the radar looks.
- :func:`handover_mismatch`: the test of the tentative track against the first confirmed
  measurement (the confirmed cells differ from the tentative ones: the central Doppler filter
  instead of Σ over the three); on a mismatch the Tracker re-centres the track's position on
  that measurement, keeping its velocity and gain schedule (a full restart, n = 1, made
  young confirmed tracks that the manager dropped: 8 drops in 64 plane runs at 30-42 km).
- :func:`reading_angle_variance`: the monopulse angle accuracy of one reading from its
  gate-cell SNR (session 9): the track initiation counts a weak reading (gate cell 2-3× the
  background: σθ ≈ 0.4-0.6°) for what it is worth, not as the high-SNR ``sigma_angle``
  (0.057°), also after a re-centre on one reading.
"""

from __future__ import annotations

import math

from ..filters.base import AxisFilter
from ..filters.gains import innovation_factor
from .maneuver import nis_cs
from .outputs import GATE_CENTRE_M

#: E|n|² / (E|n|)² of a Rayleigh magnitude (4/π): noise power from a mean noise magnitude
_RAYLEIGH_POWER = 4.0 / math.pi
#: floor of the estimated per-beam SNR [1] (a reading at or below the noise)
SNR_FLOOR = 0.1


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


def reading_angle_variance(ratio: float, inv_slope: float) -> float:
    """Variance [rad²] of one monopulse angle reading (lateral or elevation) from its gate-cell
    ``ratio`` = strongest gate-cell SUM / mean background SUM (magnitudes) and ``inv_slope``
    = 1/k_m [rad] (angle = ε/k_m).

    Assumption (derived here; the seeds give no angle-noise law): for a pair of beams u, d
    with signal amplitude A each near boresight and independent complex noise of power N
    each, ε = (u − d)/(u + d) has, to first order in the noise, σε² = N/(4A²) (the noise
    component in phase with the signal, N/2 per beam, over (2A)²), so
    σθ² = 1/(4·k_m²·SNR), SNR = A²/N per beam: the thermal-noise monopulse error, in the
    textbook form σθ = θ3/(k'·√(2·SNR)) with the normalised slope k' = √2·k_m·θ3 (≈ 1.96
    here; Barton & Ward, Handbook of Radar Measurement, 1969, ch. 2; Sherman, Monopulse
    Principles and Techniques, ch. 8). The SNR comes from the magnitudes: the background's
    mean magnitude m gives the noise power (4/π)·m² (Rayleigh), the gate cell's power
    (ratio·m)² ≈ A² + N (Rice second moment), so SNR = (π/4)·ratio² − 1, floored at
    ``SNR_FLOOR``; the four beams' SUM scales the signal and the noise mean alike. Clutter
    in the background bins counts as noise (its bias on the angle is not modelled). An
    infinite ratio (no noise) gives 0."""
    if not ratio < math.inf:
        return 0.0
    snr = max(ratio * ratio / _RAYLEIGH_POWER - 1.0, SNR_FLOOR)
    return inv_slope * inv_slope / (4.0 * snr)
