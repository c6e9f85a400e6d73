"""Test harness: three α-β axis filters (X, Y, Z) driven as the Tracker's beams mode drives them
(same steady gains on every axis, one measurement vector per update)."""

from __future__ import annotations

from axir.models.filters.alphabeta import AlphaBetaAxis
from axir.models.filters.base import FilterConfig

Vec3 = tuple[float, float, float]


class ThreeAxes:
    """Three :class:`AlphaBetaAxis` with the per-vector interface the α-β tests use."""

    def __init__(self, n_max: int = 0) -> None:
        self.axes = [AlphaBetaAxis(FilterConfig(n_max=n_max)) for _ in range(3)]

    def update(self, z: Vec3, T: float, alpha_ss: float = 0.0, beta_ss: float = 0.0) -> Vec3:
        nu = []
        for f, zi in zip(self.axes, z, strict=True):
            f.set_steady_gains(alpha_ss, beta_ss)
            nu.append(f.update(float(zi), T))
        return nu[0], nu[1], nu[2]

    def coast(self, T: float) -> None:
        for f in self.axes:
            f.coast(T)

    def predict(self, T: float) -> Vec3:
        p = [f.predict(T)[0] for f in self.axes]
        return p[0], p[1], p[2]

    @property
    def x(self) -> list[float]:
        return [f.x[0] for f in self.axes]

    @property
    def v(self) -> list[float]:
        return [f.x[1] for f in self.axes]

    @property
    def n(self) -> int:
        return self.axes[0].n

    @property
    def alpha(self) -> float:
        return self.axes[0].alpha

    @property
    def beta(self) -> float:
        return self.axes[0].beta

    def innovation_factor(self) -> float:
        return self.axes[0].innovation_factor()
