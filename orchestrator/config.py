"""Defaults shared by the orchestrator's layers (read from here, never redefined)."""

from __future__ import annotations

import os

from axir.models.system import STEP_SOURCE

#: where the FMUs are built and looked up (``$AXIR_FMU_DIR``, else ``dist``)
DEFAULT_FMU_DIR = os.environ.get("AXIR_FMU_DIR", "dist")
#: the output giving the next communication step [s] of a variable-step run
DEFAULT_STEP_FROM = ".".join(STEP_SOURCE)
#: [s] first step of a variable-step run before the step source has a value (a scenario
#: states its own, e.g. the closed loop's PRI 1)
DEFAULT_INITIAL_STEP = 1e-4
