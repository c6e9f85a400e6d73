"""The TargetGenerator's output mapping per step (issue 14, round 4: moved out of
``models/target_generator.py``, which was full).

No equation of its own beyond the truth quantities documented in the TargetGenerator's
``OUTPUTS`` (range rate ṙ = p·v/ρ, range acceleration ρ̈ = (|v|² + p·a − ṙ²)/ρ, apparent range
R mod Ru with Ru = c·PRI/2, Doppler −2ṙ/λ (radar.py), SNR law of ``snr_ref_db``).

Speed (issue 14): the mapping is a copy of a template holding every output name in the
declared order, then filled by item assignment: a 24-entry dict display costs ≈ 1.36 µs per
step on this machine, a template copy plus 24 assignments ≈ 0.7 µs (``timeit``).
"""

from __future__ import annotations

from math import log10, sqrt
from typing import Any

import numpy as np

from .conventions import BEAMS, N_BEAMS, N_BINS, N_DOPPLER, C
from .geometry import cart_to_sph
from .ports import Port

#: The TargetGenerator's public outputs (its ``OUTPUTS``; moved here for room, issue 14,
#: round 10); ``beam`` is a (4, 16, 3) array [1].
OUTPUTS: tuple[Port, ...] = (
    Port("beam", float, "1", "beam magnitude (Doppler filter output) per range bin r and "
         "Doppler filter f", shape=(N_BEAMS, N_BINS, N_DOPPLER), labels=BEAMS),
    Port("truth.x", float, "m", "target East position"),
    Port("truth.y", float, "m", "target North position"),
    Port("truth.z", float, "m", "target Up position"),
    Port("truth.vx", float, "m/s", "target East velocity"),
    Port("truth.vy", float, "m/s", "target North velocity"),
    Port("truth.vz", float, "m/s", "target Up velocity"),
    Port("truth.accel", float, "m/s2", "magnitude of the target acceleration"),
    Port("truth.range", float, "m", "target range"),
    Port("truth.az", float, "rad", "target azimuth in [0, 2π)"),
    Port("truth.el", float, "rad", "target elevation"),
    Port("truth.range_rate", float, "m/s", "target range rate"),
    Port("truth.range_acc", float, "m/s2", "second derivative of the target range "
         "(|v|² + p·a − ṙ²)/ρ"),
    Port("truth.apparent_range", float, "m", "range folded modulo Ru = c·pri/2"),
    Port("truth.doppler", float, "Hz", "unfolded Doppler −2·ṙ/λ"),
    Port("truth.snr_db", float, "dB", "mean single-pulse SNR of one beam at peak gain "
         "(snr_ref_db law)"),
    Port("truth.rcs", float, "m2", "instantaneous RCS (Swerling draw of the current dwell)"),
    Port("meas.range", float, "m", "measured range (measurement fidelity), held"),
    Port("meas.az", float, "rad", "measured azimuth in [0, 2π) (measurement fidelity), held"),
    Port("meas.el", float, "rad", "measured elevation (measurement fidelity), held"),
    Port("meas.valid", float, "1", "1 once a measurement exists (measurement fidelity)"),
    Port("meas.new", float, "1", "1 in the step that took a new measurement"),
    Port("input.invalid", bool, "1", "true when an input was not a finite number or pri was "
         "too short (its last valid value was held this step)"),
    Port("input.invalid.count", int, "1", "number of steps with an invalid input so far"),
)

MIN_RANGE = 1.0  # [m] # assumption: radar equation range floor (no singularity at R = 0)
_HALF_C = 0.5 * C  # Ru = c·PRI/2 (conventions.unambiguous_range: the same product)


def output_template(outputs: tuple[Port, ...]) -> dict[str, Any]:
    """A dict of every output name of ``outputs`` (declared order), values None: the mapping
    :func:`outputs` copies and fills (its key order is the declaration's)."""
    return dict.fromkeys(p.name for p in outputs)


def outputs(gen: Any, t: float, pri: float) -> dict[str, Any]:
    """The outputs of the TargetGenerator ``gen`` at time ``t`` [s] for the PRI ``pri`` [s]
    (``TargetGenerator._outputs``; ``OUTPUTS`` there documents every entry and unit).

    The truth of the last pulse is reused when it was computed at ``t`` for the same
    trajectory (``gen._truth``); otherwise it is evaluated here (geometry.cart_to_sph)."""
    t0, traj, st, r, az, el = gen._truth
    if t0 != t or traj is not gen._traj:  # not the last pulse's truth (issue 14)
        st = gen._traj.state_tuple(t)
        r, az, el = cart_to_sph(*st[0])
    (x, y, z), (vx, vy, vz), (ax, ay, az_) = st
    rr = MIN_RANGE if r < MIN_RANGE else r  # max(r, MIN_RANGE), NaN kept as max keeps it
    rdot = (x * vx + y * vy + z * vz) / rr
    # ρ̈ = d/dt (p·v/ρ) = (|v|² + p·a − ṙ²)/ρ   (range acceleration along the line of sight,
    # the quantity the seed-002 range-axis filters estimate; differentiated analytically)
    rddot = (vx * vx + vy * vy + vz * vz + x * ax + y * ay + z * az_ - rdot * rdot) / rr
    snr = (gen._a0 / (rr * rr)) ** 2
    meas = gen.fidelity == "measurement"
    o = gen._otemplate.copy()
    o["beam"] = np.abs(gen._y) if not meas else np.zeros((N_BEAMS, N_BINS, N_DOPPLER))
    o["truth.x"] = x
    o["truth.y"] = y
    o["truth.z"] = z
    o["truth.vx"] = vx
    o["truth.vy"] = vy
    o["truth.vz"] = vz
    o["truth.accel"] = sqrt(ax * ax + ay * ay + az_ * az_)
    o["truth.range"] = r
    o["truth.az"] = az
    o["truth.el"] = el
    o["truth.range_rate"] = rdot
    o["truth.range_acc"] = rddot
    o["truth.apparent_range"] = r % (_HALF_C * pri)
    o["truth.doppler"] = -2.0 * rdot / gen.wavelength  # radar.py doppler_hz
    # max(snr, 1e-30) as a comparison (NaN kept as max keeps it): floor −300 dB (rcs = 0)
    o["truth.snr_db"] = 10.0 * log10(1e-30 if snr < 1e-30 else snr)
    o["truth.rcs"] = gen.rcs * abs(gen._fluct) ** 2 if gen.swerling == 1 else gen.rcs * 1.0
    m = gen._meas
    o["meas.range"] = m[0]
    o["meas.az"] = m[1]
    o["meas.el"] = m[2]
    o["meas.valid"] = gen._meas_valid
    o["meas.new"] = bool(meas and gen._meas_new)
    o["input.invalid"] = gen._invalid
    o["input.invalid.count"] = gen._invalid_count
    return o
