"""Pedestal.fmu declaration: the 2-axis servo pedestal (:mod:`axir.models.pedestal`).

Everything else (FMI variables, modelDescription, slave, bundle) is derived by
:mod:`axir.fmus._base` and :mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.pedestal import INPUTS, OUTPUTS, Pedestal
from ._base import FmuSpec, Var

#: Non-Real outputs of the Pedestal (all others are Real).
_TYPES = {"input.invalid": "Boolean", "input.invalid.count": "Integer"}

SPEC = FmuSpec(
    name="Pedestal",
    model=Pedestal,
    description="AXIR 2-axis servo pedestal with double potentiometers (seed 000 Figs 6-7)",
    inputs=tuple(
        Var(n, unit=u or "1", description=d,
            start=Pedestal.param_map()["bandwidth"].default if n == "bandwidth" else 0.0)
        for n, u, d in INPUTS
    ),
    outputs=tuple(
        Var(n, type=_TYPES.get(n, "Real"), unit=u or "1", description=d,
            start=False if _TYPES.get(n) == "Boolean" else 0 if n in _TYPES else 0.0)
        for n, u, d in OUTPUTS
    ),
    # the parameter `bandwidth` (initial value) would clash with the input `bandwidth`
    param_names={"bandwidth": "bandwidth0"},
    calculated_outputs=True,  # Pedestal.outputs() gives the outputs at the initial state
    default_step=1e-3,
)
