"""The TargetGenerator's inputs (ports, domains, starts and the pri floor of its input
rule), moved out of ``models/target_generator.py`` for room (issue 14, round 11) and
re-exported there under the same names.
"""

from __future__ import annotations

from .conventions import BIN_S, N_BINS
from .ports import Port

ANGLE_MAX = 1.0e6  # [rad] largest |angle| input (continuous angles may wind up)
RANGE_MAX = 1.0e7  # [m] largest |range| input or parameter (10 000 km)
DOPPLER_MAX = 1.0e7  # [Hz] largest |Doppler| input: 2·v/λ for v ≤ 10 km/s, λ ≥ 2 mm

#: Public inputs (absent ones take their ``start``).
#: Domains (out of domain: the last valid value is held): angles ±ANGLE_MAX (continuous
#: pedestal angles may wind up, but not beyond a million radians); gate.start ±RANGE_MAX;
#: doppler.centre ±DOPPLER_MAX (2·v/λ for v ≤ 10 km/s, λ ≥ 2 mm); pri from the 16-bin window
#: (8 µs, shorter cannot hold the window) to 1 s (PRF 1 Hz).
INPUTS: tuple[Port, ...] = (
    Port("antenna.az", float, "rad", "antenna boresight azimuth (from North toward East)",
         low=-ANGLE_MAX, high=ANGLE_MAX),
    Port("antenna.el", float, "rad", "antenna boresight elevation",
         low=-ANGLE_MAX, high=ANGLE_MAX),
    Port("gate.start", float, "m", "range of bin 1 (the window samples it modulo Ru)",
         low=-RANGE_MAX, high=RANGE_MAX),
    Port("doppler.centre", float, "Hz", "centre frequency of Doppler filter 2",
         low=-DOPPLER_MAX, high=DOPPLER_MAX),
    Port("pri", float, "s", "pulse repetition interval (must hold the 16-bin window)",
         start=100e-6, low=N_BINS * BIN_S, high=1.0),
)

#: (name, start) of the inputs, for the per-step fast path of ``_hold_valid``
_IN_DEFAULTS = tuple((p.name, p.initial) for p in INPUTS)
_IN_FLOORS = {"pri": N_BINS * BIN_S}  # the 16-bin window must fit in a PRI
#: the starts and the pri floor of the usual case of the input rule, written out in ``step``
_IN_NAMES = ("antenna.az", "antenna.el", "gate.start", "doppler.centre", "pri")
assert tuple(n for n, _ in _IN_DEFAULTS) == _IN_NAMES and tuple(_IN_FLOORS) == ("pri",)
_PRI_MIN = _IN_FLOORS["pri"]
