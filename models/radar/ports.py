"""Declare a unit's inputs and outputs once, next to the model, as plain Python.

A :class:`Port` is to a unit's ``step`` mappings what :class:`~.params.Param` is to its
parameters: the single declaration (name, Python type, unit, shape, description, start
value) from which everything else is derived — the FMU adapters' variables
(:mod:`axir.fmus`), the generated interface docs, the direct loop's initial values. A unit
class lists them in ``INPUTS`` and ``OUTPUTS`` (see :class:`~.unit.Unit`).

Arrays: ``shape`` is the array shape the model sees (e.g. ``(4, 16, 3)`` for the beams);
``labels`` names the entries of the first axis (``("up", "right", "down", "left")``).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from itertools import product
from math import prod

#: Python types a port may carry (float: real value, int: integer, bool: flag).
PORT_KINDS = (float, int, bool)
#: Largest finite float: the default domain of a ``float`` port is [−FLOAT_MAX, FLOAT_MAX].
FLOAT_MAX = sys.float_info.max
#: Range of a 32-bit integer (an ``int`` port travels as one).
INT32_MIN, INT32_MAX = -(2**31), 2**31 - 1


@dataclass(frozen=True)
class Port:
    """One input or output of a unit (possibly an array).

    Attributes:
        name: public variable name (``"dev.az"``; an array's base name, ``"beam"``).
        kind: Python type of the value: ``float``, ``int`` or ``bool``.
        unit: SI unit of a ``float`` ("m", "rad", "Hz", "1" for dimensionless).
        doc: one-line description.
        shape: () for a scalar, else the array shape as the model sees it.
        labels: optional names for the entries of the first axis of an array.
        start: value before the first step (inputs: used when absent; outputs: initial
            value of a unit that has no computed initial outputs). None: zero of ``kind``.
        low, high: domain of an input, closed bounds (None: the largest finite ``float``, or
            the 32-bit range of an ``int``). A value outside it (NaN, ±inf, out of range) is
            *out of domain*: the FMU adapter logs a warning naming the variable and the value
            and hands the unit a replacement (``invalid``) instead. Outputs: informative.
        invalid: replacement of an out-of-domain input value: ``"hold"`` the last valid value
            (default), or ``"start"``: the start value (e.g. a rate command → 0 V).
    """

    name: str
    kind: type = float
    unit: str = "1"
    doc: str = ""
    shape: tuple[int, ...] = ()
    labels: tuple[str, ...] | None = None
    start: float | int | bool | None = None
    low: float | None = None
    high: float | None = None
    invalid: str = "hold"

    def __post_init__(self) -> None:
        if self.kind not in PORT_KINDS:
            raise ValueError(f"port {self.name}: kind {self.kind!r} is not float, int or bool")
        if self.invalid not in ("hold", "start"):
            raise ValueError(f"port {self.name}: invalid = {self.invalid!r}, not hold or start")
        lo, hi = self.bounds()
        if not lo <= self.initial <= hi:
            raise ValueError(f"port {self.name}: start {self.initial!r} outside [{lo}, {hi}]")
        if self.labels is not None and (not self.shape or len(self.labels) != self.shape[0]):
            raise ValueError(f"port {self.name}: {len(self.labels)} labels for shape "
                             f"{self.shape}")

    @property
    def initial(self) -> float | int | bool:
        """Start value, or the zero of the port's type."""
        return self.kind() if self.start is None else self.kind(self.start)

    def bounds(self) -> tuple[float, float]:
        """Closed domain [low, high] of a value: the declared bounds, else the largest finite
        float (a ``float`` port: any finite value) or the 32-bit range (``int``: an FMI
        Integer); (0, 1) for ``bool``."""
        if self.kind is bool:
            return 0, 1
        if self.kind is int:
            lo = INT32_MIN if self.low is None else max(INT32_MIN, math.ceil(self.low))
            hi = INT32_MAX if self.high is None else min(INT32_MAX, math.floor(self.high))
            return lo, hi
        return (-FLOAT_MAX if self.low is None else float(self.low),
                FLOAT_MAX if self.high is None else float(self.high))

    def admits(self, value: float | int | bool) -> bool:
        """``value`` is inside the port's domain (:meth:`bounds`; NaN never is)."""
        lo, hi = self.bounds()
        return bool(lo <= value <= hi)

    @property
    def size(self) -> int:
        """Number of scalar values."""
        return prod(self.shape) if self.shape else 1

    def scalar_names(self) -> list[str]:
        """Names of the scalar elements, structured, 1-based, C order: ``beam.up[3,2]``,
        ``sum[16,3]``; a scalar port's own name."""
        if not self.shape:
            return [self.name]
        heads = ([f"{self.name}.{lab}" for lab in self.labels] if self.labels is not None
                 else [self.name])
        rest = self.shape[1:] if self.labels is not None else self.shape
        if not rest:
            return heads
        idx = [",".join(str(i + 1) for i in ix) for ix in product(*(range(n) for n in rest))]
        return [f"{h}[{i}]" for h in heads for i in idx]


def port_map(ports: tuple[Port, ...]) -> dict[str, Port]:
    """Ports by name; raises ``ValueError`` on a name declared twice."""
    out: dict[str, Port] = {}
    for p in ports:
        if p.name in out:
            raise ValueError(f"port {p.name} is declared twice")
        out[p.name] = p
    return out
