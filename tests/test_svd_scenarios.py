"""Built-in scenarios svd-1 and svd-2 (seed 002 §7): the documented maneuver profiles, the
TargetGenerator → Tracker measurement system through the FMUs, and short campaigns.

The truth is checked against the piecewise constant-acceleration motion written out here from
the values stated in the scenario files (independent of models/trajectory.py).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from axir.models.frontend import TargetGenerator
from axir.orchestrator.scenario import load_scenario

#: the documented profiles: (onset [s], offset [s], radial acceleration [m/s²])
PROFILES = {
    "svd-1": [(30.0, 50.0, 20.0)],
    "svd-2": [(30.0, 40.0, 50.0), (60.0, 70.0, -50.0)],
}
SIGMA_M = {"svd-1": 5.0, "svd-2": 20.0}  # seed 002: σm1, σm2 [m/s²]
R0, V0, T, SIGMA_R = 1000.0, 250.0, 1.0, 100.0  # seed 002 §7


def radial_truth(t: np.ndarray, profile: list[tuple[float, float, float]]):
    """Range, range rate, range acceleration of a target receding radially from R0 at V0 with
    acceleration steps ``profile``."""
    r, v, a = R0 + V0 * t, np.full_like(t, V0), np.zeros_like(t)
    for on, off, acc in profile:
        d = off - on
        inside = (t >= on) & (t < off)
        tau = np.clip(t - on, 0.0, d)  # time spent accelerating so far
        a += np.where(inside, acc, 0.0)
        v += acc * tau
        r += acc * tau * tau / 2 + acc * d * np.clip(t - off, 0.0, None)
    return r, v, a


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_scenario_values_and_truth_profile(name: str) -> None:
    sc = load_scenario(name)
    assert sc.step == T and sc.duration == 100.0 and sc.order == ["TargetGenerator", "Tracker"]
    tg = sc.units["TargetGenerator"]["parameters"]
    tr = sc.units["Tracker"]["parameters"]
    assert tg["fidelity"] == "measurement" and tg["meas_interval"] == T
    assert tg["meas_sigma_range"] == SIGMA_R == tr["sigma_range"]
    assert tr["input_mode"] == "measurement" and tr["filter_sigma_m"] == SIGMA_M[name]
    conns = {(c.src_unit, c.src_var, c.dst_unit, c.dst_var) for c in sc.connections}
    assert conns == {("TargetGenerator", f"meas.{v}", "Tracker", f"meas.{v}")
                     for v in ("range", "az", "el", "valid", "new")}
    gen = TargetGenerator(**tg)
    t = np.arange(1.0, 101.0)
    out = [gen.step(T, {}) for _ in t]
    r, v, a = radial_truth(t, PROFILES[name])
    np.testing.assert_allclose([o["truth.range"] for o in out], r, rtol=1e-12)
    np.testing.assert_allclose([o["truth.range_rate"] for o in out], v, rtol=1e-12)
    np.testing.assert_allclose([o["truth.range_acc"] for o in out], a, atol=1e-9)
    # along the line of sight: azimuth 90° (East), elevation 0, whatever the range
    np.testing.assert_allclose([o["truth.az"] for o in out], np.pi / 2, atol=1e-12)
    np.testing.assert_allclose([o["truth.el"] for o in out], 0.0, atol=1e-12)
    assert json.loads(tg["trajectory"])["position"] == [R0, 0.0, 0.0]
