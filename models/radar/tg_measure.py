"""The TargetGenerator's measurement fidelity per step (issue 14, round 5: moved out of
``models/target_generator.py``, which was full).

Equations: the module docstring of ``models/target_generator.py`` ("Measurement fidelity"):
at t = k·T_s (k ≥ 0, T_s = ``meas_interval``) range, azimuth and elevation are measured as
truth + N(0, σ²) (σ_range on range, σ_angle on both angles) and held between samples; 3
normals per sample time (a fixed layout of the generator's stream).
"""

from __future__ import annotations

import math
from typing import Any

from .geometry import TWO_PI, cart_to_sph


def measure(gen: Any, t_new: float) -> None:
    """Take the samples at k·T_s ≤ ``t_new`` [s] that the TargetGenerator ``gen`` has not taken
    yet (the last one kept: ``gen._meas`` = (range [m], az [rad] in [0, 2π), el [rad])); sets
    ``gen._meas_new`` (a sample taken in this step), ``_meas_valid`` and ``_k_next``."""
    k_last = math.floor(t_new / gen.meas_interval + 1e-9)
    n = k_last - gen._k_next + 1
    gen._meas_new = n > 0
    if n <= 0:
        return
    z = gen._rng.standard_normal((n, 3))[-1]  # 3 normals per sample time (fixed layout)
    ts = k_last * gen.meas_interval
    p, _v, _a = gen._traj.state_tuple(ts)
    r, az, el = cart_to_sph(*p)
    gen._meas = (
        r + gen.meas_sigma_range * float(z[0]),
        (az + gen.meas_sigma_angle * float(z[1])) % TWO_PI,
        el + gen.meas_sigma_angle * float(z[2]),
    )
    gen._meas_valid = True
    gen._k_next = k_last + 1
