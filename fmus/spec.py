"""Declaration of an axir FMU and its FMI variable layout (build time and run time).

An FMU is *declared* (one short file per FMU, e.g. :mod:`axir.fmus.pedestal_fmu`) as an
:class:`FmuSpec`: the model class, whose ``PARAMS``, ``INPUTS`` and ``OUTPUTS`` give the FMI
variables (:class:`Var` from each :class:`~axir.models.radar.ports.Port` by :func:`var_of`).
:func:`layout` lists every FMI scalar variable (:class:`Scalar`): parameters from the model's
``PARAMS``, then inputs, then outputs, arrays expanded to FMI 2.0 structured names, 1-based, C
order (``beam.up[3,2]``); value reference = position in that list. The runtime slave
(:mod:`axir.fmus.slave`) and the modelDescription writer (:mod:`axir.fmus.model_description`)
both read this layout.

Bundled into every FMU: relative imports only.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from itertools import product
from typing import Any

import numpy as np

INT32_MIN = -(2**31)
INT32_MAX = 2**31 - 1
#: FMI log categories of every axir FMU (name → description).
LOG_CATEGORIES: dict[str, str] = {
    "logStatusWarning": "Log messages with fmi2Warning status.",
    "logStatusDiscard": "Log messages with fmi2Discard status.",
    "logStatusError": "Log messages with fmi2Error status.",
    "logStatusFatal": "Log messages with fmi2Fatal status.",
    "logAll": "Log all messages.",
}


@dataclass(frozen=True)
class Var:
    """One public input or output of a unit (possibly an array).

    Attributes:
        name: public FMI base name (``"az"``, ``"beam"``, ``"sum"``).
        type: ``"Real"``, ``"Integer"`` or ``"Boolean"``.
        unit: SI unit of a Real (``"1"`` for dimensionless; ignored for Integer/Boolean).
        description: one line, goes into the modelDescription.
        start: start value of an input (outputs are calculated: ``model.outputs()``).
        shape: () for a scalar, else the array shape as the model sees it.
        labels: optional names for the first axis: ``("up", "right", "down", "left")`` turns a
            (4, 16, 3) array into ``beam.up[r,f]`` … ``beam.left[r,f]``.
    """

    name: str
    type: str = "Real"
    unit: str = "1"
    description: str = ""
    start: float | int | bool = 0.0
    shape: tuple[int, ...] = ()
    labels: tuple[str, ...] | None = None
    vmin: float | int | None = None
    vmax: float | int | None = None

    @property
    def size(self) -> int:
        """Number of FMI scalar variables."""
        return int(np.prod(self.shape)) if self.shape else 1

    def scalar_names(self) -> list[str]:
        """FMI 2.0 structured names, C order, 1-based indices."""
        if self.type not in ("Real", "Integer", "Boolean"):
            raise ValueError(f"variable {self.name}: type {self.type!r} not Real/Integer/Boolean")
        if not self.shape:
            return [self.name]
        if self.labels is not None:
            if len(self.labels) != self.shape[0]:
                raise ValueError(f"variable {self.name}: {len(self.labels)} labels for axis "
                                 f"of length {self.shape[0]}")
            rest = self.shape[1:]
            names = []
            for lab in self.labels:
                base = f"{self.name}.{lab}"
                if not rest:
                    names.append(base)
                else:
                    names += [f"{base}[{','.join(str(i + 1) for i in idx)}]"
                              for idx in product(*(range(n) for n in rest))]
            return names
        return [f"{self.name}[{','.join(str(i + 1) for i in idx)}]"
                for idx in product(*(range(n) for n in self.shape))]


@dataclass(frozen=True)
class FmuSpec:
    """Declaration of one FMU (see the module docstring).

    Attributes:
        name: model identifier, also the FMU file name (``Pedestal`` → ``Pedestal.fmu``).
        model: the :class:`Unit` subclass (with ``PARAMS``, ``INPUTS`` and ``OUTPUTS``).
        description: FMU description.
        tunable: parameter names that may change between steps (``model.configure``).
        param_names: FMI names overriding ``Param.fmi_name or Param.name`` (e.g. to avoid a
            clash between a parameter and an input of the same name).
        default_step: DefaultExperiment stepSize [s] (None: none).
    """

    name: str
    model: type
    description: str = ""
    tunable: frozenset[str] = field(default_factory=frozenset)
    param_names: Mapping[str, str] = field(default_factory=dict)
    default_step: float | None = None

    @property
    def inputs(self) -> tuple[Var, ...]:
        """FMI inputs, derived from the model's ``INPUTS`` ports."""
        return tuple(var_of(p) for p in self.model.INPUTS)

    @property
    def outputs(self) -> tuple[Var, ...]:
        """FMI outputs, derived from the model's ``OUTPUTS`` ports."""
        return tuple(var_of(p) for p in self.model.OUTPUTS)


#: FMI type of a port's Python type.
FMI_TYPES = {float: "Real", int: "Integer", bool: "Boolean"}


def var_of(port: Any) -> Var:
    """The FMI variable of a model :class:`~axir.models.radar.ports.Port`."""
    kind = FMI_TYPES[port.kind]
    vmin = vmax = None
    if kind == "Integer" or (kind == "Real" and port.low is not None):
        vmin = port.bounds()[0]
    if kind == "Integer" or (kind == "Real" and port.high is not None):
        vmax = port.bounds()[1]
    return Var(port.name, kind, port.unit, port.doc, start=port.initial, shape=port.shape,
               labels=port.labels, vmin=vmin, vmax=vmax)


@dataclass(frozen=True)
class Scalar:
    """One FMI scalar variable (row of the modelDescription)."""

    name: str
    kind: str  # Real/Integer/Boolean/String
    causality: str  # parameter/input/output
    variability: str
    initial: str | None
    start: Any
    unit: str | None
    description: str
    vmin: float | int | None = None
    vmax: float | int | None = None


def _param_scalar(p: Any, name: str, tunable: bool) -> Scalar:
    """FMI variable of a declared :class:`Param`."""
    k = p.kind
    kind = {float: "Real", int: "Integer", bool: "Boolean"}.get(k, "String")
    desc = p.doc or p.name
    vmin = vmax = None
    unit = None
    if kind == "Real":
        unit = p.unit or "1"
        vmin = None if p.low is None else float(p.low)
        vmax = None if p.high is None else float(p.high)
        if p.choices is not None:
            vmin, vmax = float(min(p.choices)), float(max(p.choices))
    elif kind == "Integer":
        lo = p.low if p.choices is None else min(p.choices)
        hi = p.high if p.choices is None else max(p.choices)
        if (lo is not None and lo < INT32_MIN) or (hi is not None and hi > INT32_MAX):
            raise ValueError(f"parameter {p.name}: range {p.range_text()} exceeds an FMI "
                             "Integer (32-bit): declare a range that fits")
        vmin = INT32_MIN if lo is None else math.ceil(lo)
        vmax = INT32_MAX if hi is None else math.floor(hi)
        if not INT32_MIN <= p.default <= INT32_MAX:
            raise ValueError(f"parameter {p.name}: default {p.default} exceeds FMI Integer")
        if p.unit and p.unit != "1":
            desc += f" [{p.unit}]"
    desc += f"; valid {p.range_text()}"
    return Scalar(name, kind, "parameter", "tunable" if tunable else "fixed", "exact",
                  p.default, unit, desc, vmin, vmax)


def layout(spec: FmuSpec) -> list[Scalar]:
    """All FMI scalar variables of ``spec`` in value-reference order."""
    rows: list[Scalar] = []
    unknown = set(spec.tunable) - {p.name for p in spec.model.PARAMS}
    unknown |= set(spec.param_names) - {p.name for p in spec.model.PARAMS}
    if unknown:
        raise ValueError(f"{spec.name}: unknown parameter(s) {sorted(unknown)}")
    for p in spec.model.PARAMS:
        name = spec.param_names.get(p.name, p.variable_name)
        rows.append(_param_scalar(p, name, p.name in spec.tunable))
    for causality, vars_ in (("input", spec.inputs), ("output", spec.outputs)):
        for v in vars_:
            var_kind = "continuous" if v.type == "Real" else "discrete"
            initial = None
            start: Any = v.start
            if causality == "output":  # every output: from model.outputs() at initialization
                initial, start = "calculated", None
            unit = (v.unit or "1") if v.type == "Real" else None
            desc = v.description or v.name
            if v.type != "Real" and v.unit and v.unit != "1":
                desc += f" [{v.unit}]"
            vmin, vmax = (v.vmin, v.vmax) if causality == "input" else (None, None)
            rows += [Scalar(n, v.type, causality, var_kind, initial, start, unit, desc,
                            vmin, vmax) for n in v.scalar_names()]
    seen: set[str] = set()
    for r in rows:
        if r.name in seen:
            raise ValueError(f"{spec.name}: FMI variable name {r.name!r} is used twice (rename "
                             "the parameter with FmuSpec.param_names or Param.fmi_name)")
        seen.add(r.name)
    return rows
