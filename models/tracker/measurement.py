"""The Tracker on measurements (``input_mode = "measurement"``, seed-002 experiments).

The chosen filter per spherical axis (range, az, el) on ``meas.range/az/el`` (seed 002: filters
"applied with spherical coordinate"). A new measurement (``meas.new`` = 1, ``meas.valid`` = 1,
finite values) updates the three filters with T = the time since the previous measurement;
otherwise the outputs are the estimates extrapolated to the current time (state unchanged) and
``coasting`` is true. The three filters start on the first valid measurement. The azimuth
measurement is unwrapped around the predicted azimuth; the angle axes scale the metric noise
parameters by 1/ρ̂ (elevation) and 1/(ρ̂ cos Êl) (azimuth). Beams, pedestal angles and the mode
are ignored: no pedestal command (``cmd.*`` = 0), ``dev.*`` and ``innovation.*`` = 0,
``gate.start`` = track range − 6·75 m; ``maneuver`` from the per-axis detectors
(:func:`.maneuver.axis_summary`); the range-axis outputs are the range filter's.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from ..filters.base import AxisFilter, FilterConfig
from ..filters.fixedpoint import TableQuantiser
from ..filters.registry import make_axis_filter
from ..radar.geometry import wrap_pi
from ..radar.params import Configurable
from .maneuver import axis_summary
from .outputs import GATE_CENTRE_M, MIN_COS_EL, TrackerOutputs

Vec3 = tuple[float, float, float]


class MeasurementTracker:
    """State and step of the measurement input mode (module docstring).

    Args:
        p: the Tracker's parameters (attributes named as in ``Tracker.PARAMS``).
        cfg: tuning of the axis filters; α-β axes take Kalata's steady gains here (no manager).
    """

    def __init__(self, p: Configurable, cfg: FilterConfig) -> None:
        self.sigma_range = p.sigma_range
        self.sigma_angle = p.sigma_angle
        cfg_sph = replace(cfg, auto_gains=True)
        cfg_range = replace(cfg_sph, quant=TableQuantiser()) if p.fixed_point else cfg_sph
        #: spherical axis filters: range, azimuth, elevation
        self.sph: list[AxisFilter] = [make_axis_filter(p.filter_range, cfg_range),
                                      make_axis_filter(p.filter_az, cfg_sph),
                                      make_axis_filter(p.filter_el, cfg_sph)]
        self.since = 0.0  # time since the last measurement [s]

    def step(self, T: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """Advance by T [s]; keys and units: :data:`~.ports.INPUTS`/``OUTPUTS``."""
        beam = inputs.get("beam")
        sums = np.asarray(beam, dtype=float).sum(axis=0) if beam is not None else \
            np.zeros((16, 3))
        z_r = float(inputs.get("meas.range", math.nan))
        z_a = float(inputs.get("meas.az", math.nan))
        z_e = float(inputs.get("meas.el", math.nan))
        valid = float(inputs.get("meas.valid", 0.0)) > 0.5
        new = float(inputs.get("meas.new", 0.0)) > 0.5
        if T > 0.0 and math.isfinite(T):
            self.since += T
        fr, fa, fe = self.sph
        used = (valid and new and math.isfinite(z_r) and math.isfinite(z_a)
                and math.isfinite(z_e))
        if used and not fr.initialised:
            var_a = self.sigma_angle ** 2
            fr.update(z_r, 0.0, self.sigma_range ** 2)
            fa.update(z_a, 0.0, var_a)
            fe.update(z_e, 0.0, var_a)
            self.since = 0.0
        elif used and self.since > 0.0:
            ts = self.since
            var_a = self.sigma_angle ** 2
            fr.update(z_r, ts, self.sigma_range ** 2)
            rho = max(fr.x[0], 1.0)
            e_hat = fe.predict(ts)[0]
            ce = max(abs(math.cos(e_hat)), MIN_COS_EL)
            a_hat = fa.predict(ts)[0]
            fa.update(a_hat + wrap_pi(z_a - a_hat), ts, var_a, 1.0 / (rho * ce))
            fe.update(z_e, ts, var_a, 1.0 / rho)
            self.since = 0.0
        else:
            used = False
        flag, stat, thr = axis_summary(self.sph)
        if not fr.initialised:
            return TrackerOutputs(sum=sums, maneuver_statistic=stat, maneuver_threshold=thr,
                                  n=fr.n, coasting=True).as_dict()
        ts = self.since
        (r, rd, rdd), (a, ad, add), (e, ed, edd) = (
            (f.predict(ts) if ts > 0.0 else f.x) for f in self.sph)
        pos, vel, acc = sph_to_cart_kinematics((r, a, e), (rd, ad, ed), (rdd, add, edd))
        return TrackerOutputs(
            sum=sums, pos=pos, vel=vel, range=r, range_rate=rd, az=a % (2 * math.pi), el=e,
            gate_start=r - GATE_CENTRE_M, maneuver=flag, maneuver_statistic=stat,
            maneuver_threshold=thr, n=fr.n, valid=True, coasting=not used, range_acc=rdd,
            acc=acc, P=fr.P,
        ).as_dict()


def sph_to_cart_kinematics(s: Vec3, sd: Vec3, sdd: Vec3) -> tuple[Vec3, Vec3, Vec3]:
    """Position [m], velocity [m/s], acceleration [m/s²] in ENU from (ρ, θ, φ) and their first
    and second time derivatives (X = ρ cosφ sinθ, Y = ρ cosφ cosθ, Z = ρ sinφ, differentiated
    twice)."""
    rho, az, el = s
    r1, a1, e1 = sd
    r2, a2, e2 = sdd
    ca, sa, ce, se = math.cos(az), math.sin(az), math.cos(el), math.sin(el)
    # horizontal range h = ρ cosφ and its derivatives
    h = rho * ce
    h1 = r1 * ce - rho * se * e1
    h2 = r2 * ce - 2.0 * r1 * se * e1 - rho * (ce * e1 * e1 + se * e2)
    pos = (h * sa, h * ca, rho * se)
    vel = (h1 * sa + h * ca * a1, h1 * ca - h * sa * a1, r1 * se + rho * ce * e1)
    acc = (
        h2 * sa + 2.0 * h1 * ca * a1 + h * (ca * a2 - sa * a1 * a1),
        h2 * ca - 2.0 * h1 * sa * a1 - h * (sa * a2 + ca * a1 * a1),
        r2 * se + 2.0 * r1 * ce * e1 + rho * (ce * e2 - se * e1 * e1),
    )
    return pos, vel, acc
