"""Adaptive Radar Manager (AXIR_C, seed 000): the RadarManager unit and its parts.

- :mod:`.machine`: the state machine (acquisition → tentative → confirmed), the
  :class:`RadarManager` unit;
- :mod:`.params`, :mod:`.ports`: its parameters and its inputs/outputs, declared once;
- :mod:`.thresholds`: threshold statistics (Th1/Th2 factors of the dwell sums);
- :mod:`.doppler`: the Doppler discriminator of confirmed tracking;
- :mod:`.ambiguity`: PRI set and range-ambiguity resolution.
"""

from __future__ import annotations

from .machine import RadarManager
from .ports import INPUTS, OUTPUTS

__all__ = ["INPUTS", "OUTPUTS", "RadarManager"]
