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

from dataclasses import dataclass
from itertools import product
from math import prod

#: Python types a port may carry (float: real value, int: integer, bool: flag).
PORT_KINDS = (float, int, bool)


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
    """

    name: str
    kind: type = float
    unit: str = "1"
    doc: str = ""
    shape: tuple[int, ...] = ()
    labels: tuple[str, ...] | None = None
    start: float | int | bool | None = None

    def __post_init__(self) -> None:
        if self.kind not in PORT_KINDS:
            raise ValueError(f"port {self.name}: kind {self.kind!r} is not float, int or bool")
        if self.labels is not None and (not self.shape or len(self.labels) != self.shape[0]):
            raise ValueError(f"port {self.name}: {len(self.labels)} labels for shape "
                             f"{self.shape}")

    @property
    def initial(self) -> float | int | bool:
        """Start value, or the zero of the port's type."""
        return self.kind() if self.start is None else self.kind(self.start)

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
