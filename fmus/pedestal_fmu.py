"""Pedestal.fmu declaration: the 2-axis servo pedestal (:mod:`axir.models.pedestal`).

Everything else (FMI variables from the model's ``PARAMS``/``INPUTS``/``OUTPUTS``,
modelDescription, slave, bundle) is derived by :mod:`axir.fmus.spec` and
:mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.pedestal import Pedestal
from .spec import FmuSpec

SPEC = FmuSpec(
    name="Pedestal",
    model=Pedestal,
    description="AXIR 2-axis servo pedestal with double potentiometers (seed 000 Figs 6-7)",
    default_step=1e-3,
)
