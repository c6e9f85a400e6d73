"""Monopulse antenna pattern (models/radar/antenna.py): analytic properties of the beams."""

import math

import numpy as np
import pytest

from axir.models.radar.antenna import MonopulseAntenna


def test_half_power_at_half_beamwidth():
    a = MonopulseAntenna()
    assert a.voltage(a.beamwidth / 2) ** 2 == pytest.approx(0.5, rel=1e-12)


def test_ratio_zero_on_boresight_odd_and_monotonic():
    a = MonopulseAntenna()
    th = np.linspace(-a.beamwidth, a.beamwidth, 401)
    eps_el, eps_lat = [], []
    for t in th:
        b1, b2, b3, b4 = a.gains(0.0, t)
        eps_el.append((b1 - b3) / (b1 + b3))
        b1, b2, b3, b4 = a.gains(t, 0.0)
        eps_lat.append((b2 - b4) / (b2 + b4))
    eps_el, eps_lat = np.array(eps_el), np.array(eps_lat)
    assert eps_el[200] == 0.0 and eps_lat[200] == 0.0
    np.testing.assert_allclose(eps_el, -eps_el[::-1], atol=1e-15)
    assert np.all(np.diff(eps_el) > 0) and np.all(np.diff(eps_lat) > 0)
    np.testing.assert_allclose(eps_el, eps_lat, atol=1e-15)  # same law on both axes


def test_slope_matches_finite_difference_and_inverse():
    a = MonopulseAntenna(beamwidth=math.radians(3.0), squint=math.radians(1.0))
    h = 1e-7
    b_plus, b_minus = a.gains(0.0, h), a.gains(0.0, -h)
    eps = lambda b: (b[0] - b[2]) / (b[0] + b[2])  # noqa: E731
    assert (eps(b_plus) - eps(b_minus)) / (2 * h) == pytest.approx(a.slope, rel=1e-6)
    for t in (-0.02, -0.005, 0.0, 0.011):
        b = a.gains(0.0, t)
        assert a.angle_exact(eps(b)) == pytest.approx(t, abs=1e-12)
    # linear law is first-order exact near boresight
    assert a.angle_linear(a.ratio(1e-5)) == pytest.approx(1e-5, rel=1e-6)


def test_invalid_parameters():
    with pytest.raises(ValueError, match="beamwidth"):
        MonopulseAntenna(beamwidth=0.0)
    with pytest.raises(ValueError, match="squint"):
        MonopulseAntenna(squint=0.0)


def test_array_forms_equal_scalar_forms():
    from axir.models.radar.geometry import boresight_offsets, boresight_offsets_array

    a = MonopulseAntenna()
    rng = np.random.default_rng(4)
    az_t, el_t = rng.uniform(0, 2 * math.pi, 50), rng.uniform(-1.2, 1.2, 50)
    lat, el = boresight_offsets_array(az_t, el_t, 1.0, 0.3)
    for i in range(50):
        assert (lat[i], el[i]) == pytest.approx(boresight_offsets(az_t[i], el_t[i], 1.0, 0.3),
                                                abs=1e-12)
    g = a.gains_array(lat, el)
    for i in range(50):
        np.testing.assert_allclose(g[i], a.gains(lat[i], el[i]), rtol=1e-12, atol=1e-300)
