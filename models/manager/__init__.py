"""Adaptive Radar Manager (AXIR_C, seed 000): the RadarManager unit and its parts.

- :mod:`.machine`: the state machine (acquisition → tentative → confirmed), the
  :class:`RadarManager` unit, with :mod:`.acquisition`, :mod:`.tentative` and :mod:`.schedule`
  (servo bandwidth and α-β gains) as mixins;
- :mod:`.doppler_search`: Doppler steps (coverage) and unfolded Doppler candidates (coherence);
- :mod:`.params`, :mod:`.ports`: its parameters and its inputs/outputs, declared once;
- :mod:`.thresholds`: threshold statistics (Th1/Th2 factors of the dwell sums);
- :mod:`.doppler`: the Doppler discriminator of confirmed tracking;
- :mod:`.ambiguity`: PRI set and range-ambiguity resolution;
- :mod:`.state`: the state machine's state, grouped by concern.

**Integration contract** (what the other units must do):

- ``gate.command`` [m] is the *gate start* (range of bin 1, as models/tracker.py reads it) in
  apparent range for the current PRI, on the 75 m grid: the gate centre (bin 7) is
  ``gate.command + 6·75 m`` and its true range ``gate.command + 6·75 m + range.offset``. In
  modes 0 and 1 the Tracker sets ``gate.start = gate.command``; in mode 2 it gates on its own
  prediction, ``gate.start = R_pred − range.offset − 6·75 m`` (models/tracker.py), and the
  manager reports ``gate.command`` = ``track.range − range.offset − 6·75 m`` for information.
  ``range.offset`` = N·Ru of the current PRI at all times and is constant while confirmed.
- ``pri`` is the master's communication step; ``doppler.centre`` and ``pri`` go to the
  TargetGenerator, ``bandwidth`` to the Pedestal, ``mode``/``alpha``/``beta``/``range.offset``/
  ``gate.command`` to the Tracker; the Tracker's ``sum``, ``gate.start``, ``track.range``,
  ``track.range_rate`` and ``maneuver`` come back.
- Set ``doppler_pole`` = TargetGenerator ``pole``, ``wavelength`` = the generator's λ, and
  ``designation_range`` = the scenario's designated range.
- Declarations of the unit's ports: :data:`.ports.INPUTS`, :data:`.ports.OUTPUTS`.
"""

from __future__ import annotations

from .machine import RadarManager
from .ports import INPUTS, OUTPUTS

__all__ = ["INPUTS", "OUTPUTS", "RadarManager"]
