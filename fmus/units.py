"""SI units of the FMI variables: base-unit exponents for the modelDescription's
``UnitDefinitions`` (build time only; not bundled into the FMUs)."""

from __future__ import annotations

#: SI base-unit exponents (kg, m, s, A, K, mol, cd, rad) of the units we know.
BASE_UNITS: dict[str, dict[str, int]] = {
    "1": {},
    "m": {"m": 1},
    "m2": {"m": 2},
    "m2/s": {"m": 2, "s": -1},
    "m2/s2": {"m": 2, "s": -2},
    "m2/s4": {"m": 2, "s": -4},
    "s": {"s": 1},
    "Hz": {"s": -1},
    "1/s": {"s": -1},
    "rad": {"rad": 1},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "rad/s": {"rad": 1, "s": -1},
    "rad/s2": {"rad": 1, "s": -2},
    "V": {"kg": 1, "m": 2, "s": -3, "A": -1},
    "V/rad": {"kg": 1, "m": 2, "s": -3, "A": -1, "rad": -1},
    "rad/(s.V)": {"kg": -1, "m": -2, "s": 2, "A": 1, "rad": 1},
    "W": {"kg": 1, "m": 2, "s": -3},
    "dB": {},
}
