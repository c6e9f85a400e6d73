"""The AXIR_B digital tracker (seed 000) and its parts.

- :mod:`.unit`: :class:`Tracker`, the unit (parameters, dispatch on ``input_mode``);
- :mod:`.ports`: its inputs and outputs; :mod:`.outputs`: the record that fills them;
- :mod:`.beams`: the seed-000 tracker on the monopulse beams (default);
- :mod:`.measurement`: the filters on measurements (seed-002 experiments);
- :mod:`.deviations`: SUM and DIF/SUM ratios; :mod:`.ddre`: the seed-001 range estimator;
- :mod:`.maneuver`: the 3-D NIS test and the per-axis detector summary.

The per-axis filters are in :mod:`axir.models.filters`.
"""

from .unit import Tracker

__all__ = ["Tracker"]
