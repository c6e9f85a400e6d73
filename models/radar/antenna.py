"""Four-beam squinted amplitude-comparison monopulse antenna (seed 000; pattern is an assumption).

The seed names four squinted receive beams B1..B4 (up, right, down, left) but gives no pattern
(its figures are lost). We use a Gaussian voltage pattern per beam, a documented assumption:

    v(θ) = exp(−2 ln2 · (θ/θ3)²)        (power pattern −3 dB at θ = ±θ3/2)

each beam squinted by θs along its own axis (up/down in elevation, right/left laterally):

    B_up = v(lat) v(el − θs), B_down = v(lat) v(el + θs),
    B_right = v(lat − θs) v(el), B_left = v(lat + θs) v(el).

For this pattern the noise-free monopulse ratio is exactly
    ε = (B1 − B3)/(B1 + B3) = tanh(k_m · el),  k_m = 4 ln2 · θs / θ3²  [1/rad]
(and likewise laterally with B2, B4), so the deviation is zero on boresight, odd and monotonic.
k_m is the monopulse slope of SYSTEM.md (angle = ε / k_m near boresight); ``atanh(ε)/k_m``
inverts the law exactly. The tracker and the generator both take k_m from here, so the slope is
calibrated from the very pattern the generator uses.
"""

from __future__ import annotations

import math
from math import exp

import numpy as np

from .params import Configurable, Param

FOUR_LN2 = 4.0 * math.log(2.0)


class MonopulseAntenna(Configurable):
    """Beam pattern and monopulse slope of the 4-beam squinted antenna."""

    PARAMS = (
        Param("beamwidth", math.radians(2.5), "rad", "3 dB beamwidth of each squinted beam",
              low=1e-4, high=0.5),
        Param("squint", math.radians(1.25), "rad", "squint of each beam from boresight",
              low=0.0, high=0.5, low_open=True),
    )

    def _check(self) -> None:
        self._a = 0.5 * FOUR_LN2 / self.beamwidth**2  # v(θ) = exp(−a θ²)

    @property
    def slope(self) -> float:
        """Monopulse slope k_m [1/rad]: dε/dθ at boresight (ε = tanh(k_m θ))."""
        return 2.0 * self._a * self.squint

    def voltage(self, theta: float | np.ndarray) -> float | np.ndarray:
        """One-axis voltage pattern v(θ) [1] (peak 1)."""
        return np.exp(-self._a * np.square(theta))

    def gains(self, lat: float, el: float) -> np.ndarray:
        """Voltage gains (up, right, down, left) for a target at (lat, el) off boresight [rad]."""
        return np.array(self.gains_tuple(lat, el))

    def gains_tuple(self, lat: float, el: float) -> tuple[float, float, float, float]:
        """:meth:`gains` as a tuple of Python floats (no array: per-pulse scalar paths)."""
        a, s = self._a, self.squint
        vl = exp(-a * lat * lat)
        ve = exp(-a * el * el)
        return (
            vl * exp(-a * (el - s) ** 2),
            ve * exp(-a * (lat - s) ** 2),
            vl * exp(-a * (el + s) ** 2),
            ve * exp(-a * (lat + s) ** 2),
        )

    def gains_array(self, lat: np.ndarray, el: np.ndarray) -> np.ndarray:
        """:meth:`gains` for arrays of offsets: shape (n, 4) (up, right, down, left)."""
        v, s = self.voltage, self.squint
        vl, ve = v(lat), v(el)
        return np.stack([vl * v(el - s), ve * v(lat - s), vl * v(el + s), ve * v(lat + s)],
                        axis=-1)

    def ratio(self, theta: float | np.ndarray) -> float | np.ndarray:
        """Noise-free monopulse ratio ε(θ) = tanh(k_m θ) [1]."""
        return np.tanh(self.slope * np.asarray(theta))

    def angle_linear(self, eps: float) -> float:
        """Angle from ratio with the linear law of SYSTEM.md: θ = ε / k_m [rad]."""
        return eps / self.slope

    def angle_exact(self, eps: float) -> float:
        """Angle from ratio by inverting the pattern exactly: θ = atanh(ε)/k_m [rad]."""
        e = max(-0.999999, min(0.999999, eps))
        return math.atanh(e) / self.slope
