"""Defaults shared by the orchestrator's layers (read from here, never redefined)."""

from __future__ import annotations

import os

from axir.models.system import STEP_SOURCE, initial_pri

#: where the FMUs are built and looked up (``$AXIR_FMU_DIR``, else ``dist``)
DEFAULT_FMU_DIR = os.environ.get("AXIR_FMU_DIR", "dist")
#: the output giving the next communication step [s] of a variable-step run
DEFAULT_STEP_FROM = ".".join(STEP_SOURCE)
#: [s] first step of a variable-step run while the step source has no valid value yet (the
#: radar's step source, the manager's PRI, is computed at initialization, so this is a
#: fallback): the manager's initial PRI, from the PRI definition (models/system.py)
DEFAULT_INITIAL_STEP = initial_pri()
#: [µs] wall time of one macro step of the closed loop through the four FMUs, measured with
#: ./scripts/demo.sh on an idle 2-core machine (README: 299 µs per PRI step); used to estimate
#: a run's wall time before it starts
US_PER_STEP = 300.0
#: [s] a run estimated to take longer than this (one day) needs an explicit --long
LONG_RUN_S = 86400.0
