"""Tracker.fmu declaration: the AXIR_B digital tracker (:mod:`axir.models.tracker`).

Everything else (FMI variables from the model's ``PARAMS``/``INPUTS``/``OUTPUTS``,
modelDescription, slave, bundle) is derived by :mod:`axir.fmus.spec` and
:mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.tracker import Tracker
from .spec import FmuSpec

SPEC = FmuSpec(
    name="Tracker",
    model=Tracker,
    description="AXIR_B digital tracker: monopulse deviations, Cartesian alpha-beta tracking, "
                "pedestal rate commands, range gate (seed 000), DDRE (seed 001), Kalman/SVD/VD/"
                "IMM filters and measurement input mode (seed 002)",
    default_step=1e-4,
)
