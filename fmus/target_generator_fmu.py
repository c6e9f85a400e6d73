"""TargetGenerator.fmu declaration: target, clutter, noise and the radar front end
(:mod:`axir.models.frontend`, AXIR_A role).

Everything else (FMI variables, modelDescription, slave, bundle) is derived by
:mod:`axir.fmus._base` and :mod:`axir.fmus.build`. Relative imports only (bundled code).
"""

from __future__ import annotations

from ..models.frontend import INPUTS, OUTPUTS, TargetGenerator
from ..models.radar import BEAMS, N_BINS, N_DOPPLER
from ._base import FmuSpec, Var

SPEC = FmuSpec(
    name="TargetGenerator",
    model=TargetGenerator,
    description="AXIR_A target trajectory, clutter, noise and monopulse front end: 4 squinted "
                "beams x 16 range bins x 3 IIR Doppler filters with range/Doppler folding",
    inputs=tuple(Var(n, "Real", u, d, start=s) for n, (s, u, d) in INPUTS.items()),
    outputs=(
        Var("beam", "Real", "1", "beam magnitude (Doppler filter output) per range bin r and "
            "Doppler filter f", shape=(4, N_BINS, N_DOPPLER), labels=BEAMS),
        *(Var(n, "Real", u or "1", d) for n, (u, d) in OUTPUTS.items()),
    ),
    default_step=1e-4,
)
