"""Common contract of the four radar units (TargetGenerator, Tracker, Pedestal, RadarManager).

Every unit:
- declares its parameters once in ``PARAMS`` (see :mod:`axir.models.radar.params`) and its
  inputs and outputs once in ``INPUTS`` / ``OUTPUTS`` (see :mod:`axir.models.radar.ports`);
- keeps explicit state, built by :meth:`reset` (called by ``__init__``);
- reports its outputs at the current state with :meth:`outputs` (no step: the initial
  outputs after :meth:`reset`);
- advances with ``step(dt, inputs) -> outputs``: ``dt`` [s] is the communication step,
  ``inputs``/``outputs`` are mappings keyed by the public variable names of SYSTEM.md
  (e.g. ``"dev.az"``); array variables are numpy arrays (beams: shape (4, 16, 3) ordered
  up, right, down, left × range bin × Doppler filter; ``"sum"``: shape (16, 3));
- exposes its whole internal state (filter states, servo state, RNG state) through
  :meth:`get_state` / :meth:`set_state`, so an FMU can save, restore and serialise it and a
  restored unit continues bit-identically.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

import numpy as np

from .params import Configurable
from .ports import Port


class Unit(Configurable):
    """Base class: parameters + explicit state + ``step``.

    ``INPUTS`` / ``OUTPUTS`` declare the keys of the ``step`` mappings once
    (:class:`~.ports.Port`: name, Python type, unit, shape, description, start value).
    """

    INPUTS: ClassVar[tuple[Port, ...]] = ()
    OUTPUTS: ClassVar[tuple[Port, ...]] = ()
    #: Python packages some parameter values need beyond what every unit imports (numpy,
    #: scipy): ``{parameter name: {value: (package, ...)}}``; e.g. the Tracker's IMM filter.
    PACKAGES_BY_PARAM: ClassVar[Mapping[str, Mapping[str, tuple[str, ...]]]] = {}

    def __init__(self, **overrides: Any) -> None:
        super().__init__(**overrides)
        self.reset()

    def reset(self) -> None:
        """(Re)build the initial state from the parameters."""

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:  # pragma: no cover
        raise NotImplementedError

    def run_step(self) -> Callable[[float, Mapping[str, Any]], dict[str, Any]]:
        """What a run loop that steps only by Python floats [s] may call in place of
        :meth:`step` until it returns (:func:`axir.models.loop.gs_step`): the same outputs and
        state as ``step`` for a float ``dt``. Default: ``step`` itself (bound); units whose
        ``step`` only converts ``dt`` and delegates return the delegate (one frame fewer per
        call, issue 14, round 10)."""
        return self.step

    #: the input keys whose values ``step(dt, None, *values)`` takes positionally, in this
    #: order, in place of the mapping (issue 14, round 11: the run loop builds no input dict);
    #: () when ``step`` takes a mapping only. Declared by the class that defines ``step``.
    STEP_ARGS: ClassVar[tuple[str, ...]] = ()

    def run_step_args(self) -> tuple[Callable[..., dict[str, Any]], tuple[str, ...]] | None:
        """``(f, keys)``: what a run loop stepping by Python floats [s] may call as
        ``f(dt, None, *values)`` with the values of every input in ``keys`` order, in place of
        ``step(dt, {key: value, …})`` (the same outputs, state and exceptions: the step reads
        the mapping into the same names first); None when it cannot (no :attr:`STEP_ARGS`
        declared by the class defining ``step``, or ``step`` replaced on this instance: a
        wrapper takes the mapping). Default: :meth:`run_step` with the class's keys."""
        owner = next(c for c in type(self).__mro__ if "step" in c.__dict__)
        keys = owner.__dict__.get("STEP_ARGS", ())
        if not keys or "step" in self.__dict__:
            return None
        return self.run_step(), keys

    def note_invalid_inputs(self, names: list[str]) -> None:
        """The caller replaced the out-of-domain inputs ``names`` (scalar names, e.g.
        ``"beam.up[3,2]"``) of the coming step by their last valid (or start) value; see
        :class:`~.ports.Port` ``low``/``high``/``invalid``. Default: nothing; units with an
        ``input.invalid`` output count it."""

    def outputs(self) -> dict[str, Any]:
        """The outputs at the current state without advancing (after :meth:`reset`: the
        initial outputs, the values an FMU reports after initialization). Default: every
        port's start value (arrays filled with it); units override it with their own."""
        return {p.name: (np.full(p.shape, p.initial, dtype=p.kind) if p.shape else p.initial)
                for p in self.OUTPUTS}

    def get_state(self) -> dict[str, Any]:
        """Deep copy of the complete internal state (parameters included)."""
        return copy.deepcopy(self.__dict__)

    def set_state(self, state: Mapping[str, Any]) -> None:
        """Restore a state returned by :meth:`get_state`."""
        self.__dict__.clear()
        self.__dict__.update(copy.deepcopy(dict(state)))
