"""RadarManager.fmu declaration: the AXIR_C adaptive radar manager (:mod:`axir.models.manager`).

Everything else (FMI variables from the model's ``PARAMS``/``INPUTS``/``OUTPUTS``,
modelDescription, slave, bundle) is derived by :mod:`axir.fmus.spec` and
:mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.manager import RadarManager
from .spec import FmuSpec

SPEC = FmuSpec(
    name="RadarManager",
    model=RadarManager,
    description="AXIR_C adaptive radar manager: acquisition/tentative/confirmed modes, "
                "thresholds, PRI switching and range-ambiguity resolution, alpha-beta and "
                "servo-bandwidth scheduling (seed 000)",
    default_step=1e-4,
)
