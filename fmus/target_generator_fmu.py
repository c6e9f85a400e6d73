"""TargetGenerator.fmu declaration: target, clutter, noise and the radar front end
(:mod:`axir.models.target_generator`, AXIR_A role).

Everything else (FMI variables from the model's ``PARAMS``/``INPUTS``/``OUTPUTS``,
modelDescription, slave, bundle) is derived by :mod:`axir.fmus.spec` and
:mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.target_generator import TargetGenerator
from .spec import FmuSpec

SPEC = FmuSpec(
    name="TargetGenerator",
    model=TargetGenerator,
    description="AXIR_A target trajectory, clutter, noise and monopulse front end: 4 squinted "
                "beams x 16 range bins x 3 IIR Doppler filters with range/Doppler folding",
    default_step=1e-4,
)
