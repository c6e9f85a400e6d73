"""Declare a unit's parameters once; derive validation, documentation and FMU variables from it.

Stone Soup style: every model class lists its parameters as :class:`Param` entries in a
``PARAMS`` tuple (name, default, unit, doc, valid range). :class:`Configurable` turns that
declaration into keyword validation (``ValueError`` naming the parameter, the value and the
valid range) and attributes; the FMU adapters turn the very same declaration into FMI
parameter variables, so a parameter is declared in exactly one place.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar


@dataclass(frozen=True)
class Param:
    """One declared parameter of a model.

    Attributes:
        name: attribute name, also the FMI variable name (dots allowed in ``fmi_name``).
        default: default value; its Python type (float, int, bool, str) is the parameter type.
        unit: SI unit string ("m", "s", "rad", "Hz", "1" for dimensionless, "" for none).
        doc: one-line description (goes into the modelDescription).
        low, high: valid closed range bounds (None = unbounded).
        low_open, high_open: make the corresponding bound strict.
        choices: allowed values for enumerations (ints or strings).
        fmi_name: name of the FMI variable (defaults to ``name``).
    """

    name: str
    default: Any
    unit: str = ""
    doc: str = ""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple[Any, ...] | None = None
    fmi_name: str | None = None

    @property
    def kind(self) -> type:
        """Python type of the parameter (bool checked before int)."""
        d = self.default
        if isinstance(d, bool):
            return bool
        if isinstance(d, int):
            return int
        if isinstance(d, float):
            return float
        return str

    @property
    def variable_name(self) -> str:
        return self.fmi_name or self.name

    def range_text(self) -> str:
        """Human-readable valid range, used in error messages and docs."""
        if self.choices is not None:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind is bool:
            return "true or false"
        lo = "-inf" if self.low is None else repr(self.low)
        hi = "inf" if self.high is None else repr(self.high)
        return f"{'(' if self.low_open or self.low is None else '['}{lo}, {hi}" + (
            ")" if self.high_open or self.high is None else "]"
        )

    def validate(self, value: Any, owner: str = "") -> Any:
        """Return ``value`` coerced to the parameter type, or raise ``ValueError``."""
        name = self.variable_name if self.fmi_name is None else (
            f"{self.fmi_name} (argument {self.name})")
        where = f"{owner}.{name}" if owner else name
        kind = self.kind
        try:
            if kind is bool:
                if isinstance(value, str):
                    if value.lower() not in ("true", "false", "1", "0"):
                        raise TypeError
                    value = value.lower() in ("true", "1")
                elif not isinstance(value, (bool, int)) or value not in (0, 1):
                    raise TypeError
                value = bool(value)
            elif kind is int:
                if isinstance(value, bool) or (isinstance(value, float) and not value.is_integer()):
                    raise TypeError
                value = int(value)
            elif kind is float:
                if isinstance(value, bool):
                    raise TypeError
                value = float(value)
            else:
                value = str(value)
        except (TypeError, ValueError, OverflowError):
            raise ValueError(
                f"parameter {where} = {value!r} has the wrong type: expected {kind.__name__}, "
                f"valid range {self.range_text()}"
            ) from None
        if self.choices is not None:
            if value not in self.choices:
                raise ValueError(
                    f"parameter {where} = {value!r} is invalid: valid values {self.range_text()}"
                )
            return value
        if kind in (int, float):
            bad = isinstance(value, float) and not math.isfinite(value)
            if self.low is not None:
                bad |= value < self.low or (self.low_open and value == self.low)
            if self.high is not None:
                bad |= value > self.high or (self.high_open and value == self.high)
            if bad:
                raise ValueError(
                    f"parameter {where} = {value!r} is out of range: "
                    f"valid range {self.range_text()}"
                    + (f" [{self.unit}]" if self.unit and self.unit != "1" else "")
                )
        return value


class Configurable:
    """Base for models whose parameters are declared in ``PARAMS``.

    ``Model(**overrides)`` validates every override against its declaration, rejects unknown
    names, and stores all parameters as attributes. Subclasses may add cross-parameter checks
    in :meth:`_check` (raise ``ValueError`` naming the parameters).
    """

    PARAMS: ClassVar[tuple[Param, ...]] = ()

    def __init__(self, **overrides: Any) -> None:
        self.configure(overrides)

    @classmethod
    def param_map(cls) -> dict[str, Param]:
        return {p.name: p for p in cls.PARAMS}

    @classmethod
    def defaults(cls) -> dict[str, Any]:
        return {p.name: p.default for p in cls.PARAMS}

    def configure(self, overrides: Mapping[str, Any]) -> None:
        """Validate ``overrides`` and (re)set all parameters; unknown names raise ``ValueError``."""
        pmap = self.param_map()
        unknown = sorted(set(overrides) - set(pmap))
        if unknown:
            raise ValueError(
                f"{type(self).__name__}: unknown parameter(s) {', '.join(unknown)}; "
                f"known: {', '.join(sorted(pmap))}"
            )
        values = self.defaults()
        for name, value in overrides.items():
            values[name] = pmap[name].validate(value, type(self).__name__)
        for name, value in values.items():
            setattr(self, name, value)
        self._check()

    def params(self) -> dict[str, Any]:
        """Current parameter values."""
        return {p.name: getattr(self, p.name) for p in self.PARAMS}

    def _check(self) -> None:
        """Cross-parameter validation hook."""

