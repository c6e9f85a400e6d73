"""RadarManager.fmu declaration: the AXIR_C adaptive radar manager (:mod:`axir.models.manager`).

Everything else (FMI variables, modelDescription, slave, bundle) is derived by
:mod:`axir.fmus._base` and :mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.manager import INPUTS, OUTPUTS, RadarManager
from ._base import FmuSpec, Var


def _start(type_: str) -> float | int | bool:
    return {"Real": 0.0, "Integer": 0, "Boolean": False}[type_]


SPEC = FmuSpec(
    name="RadarManager",
    model=RadarManager,
    description="AXIR_C adaptive radar manager: acquisition/tentative/confirmed modes, "
                "thresholds, PRI switching and range-ambiguity resolution, alpha-beta and "
                "servo-bandwidth scheduling (seed 000)",
    inputs=tuple(Var(n, t, u or "1", d, start=_start(t), shape=shape)
                 for n, t, u, shape, d in INPUTS),
    outputs=tuple(Var(n, t, u or "1", d, start=_start(t)) for n, t, u, d in OUTPUTS),
    calculated_outputs=True,  # RadarManager.outputs(): mode 0, first PRI, search gate …
    default_step=1e-4,
)
