"""The master's macro step walked in C (issue 14): :class:`CStepPlan`.

:meth:`Master._raw_plan <axir.orchestrator.master.Master._raw_plan>` lists a step's FMI calls
in parts — fmpy's C function pointers, the components, the value-reference arrays and the
buffers the master reads into and writes from. :class:`CStepPlan` lays that list out as one
int64 buffer and :mod:`axir.orchestrator._stepper` (a small C extension, built by ``pip
install``) makes the calls, the buffer copies between them and the epoch bookkeeping of
:func:`~axir.orchestrator.master._send_raw` in C: the same FMI calls with the same arguments in
the same order, without a ctypes call and a Python loop iteration per call (≈ 16 calls per PRI
of the closed loop). Nothing is known of the FMUs beyond what fmpy loaded.

Differences from the Python path, none visible in the values: every read is made at most once
per source instance change *within* the step (the Python path also reuses a read made before
the step, e.g. the step size the master read; here every read slot is stale when a step
starts), and the instances' Python ``epoch`` counters are advanced once per step after it
(every instance the step wrote or stepped), which makes every Python-side read stale as the
Python path's per-call increments do. The output that gives the next step size is read at the
end of the step, so :meth:`Master.next_step_ns` finds it fresh.

When the extension is not built (no C compiler at install time), :func:`available` is False
and the master keeps its Python path; ``AXIR_NO_CSTEP=1`` forces that path (for comparisons).
"""

from __future__ import annotations

import ctypes
import os
from collections.abc import Sequence
from typing import Any

from .fmi import RawCall, RawDoStep

try:  # built by setuptools from orchestrator/_stepper.c (optional extension)
    from . import _stepper
except ImportError:  # pragma: no cover - installed without a C compiler
    _stepper = None  # type: ignore[assignment]

_WORDS = 8
_READ, _COPY, _WRITE, _STEP = 0, 1, 2, 3


def available() -> bool:
    """True when the C step can be used (the extension imported, not disabled)."""
    return _stepper is not None and os.environ.get("AXIR_NO_CSTEP", "") in ("", "0")


def _address(obj: Any) -> int:
    """The address of a ctypes object, or of a writable buffer (a memoryview slice)."""
    if isinstance(obj, ctypes._SimpleCData | ctypes.Array | ctypes.Structure):
        return ctypes.addressof(obj)
    return ctypes.addressof(ctypes.c_char.from_buffer(obj))


def _fn(f: Any) -> int:
    """The address of a C function pointer (TypeError for anything else: a Python callable
    stands in for it, and the master then steps in Python)."""
    if not isinstance(f, ctypes._CFuncPtr) or not ctypes.cast(f, ctypes.c_void_p).value:
        raise TypeError(f"not a C function pointer: {f!r}")
    return ctypes.cast(f, ctypes.c_void_p).value


class CStepPlan:
    """One macro step of a :meth:`Master._raw_plan` as a C op list (TypeError when a call
    of the plan is not a C function: the caller then keeps the Python path).

    ``raw``: the raw plan (instances, (t, h) C doubles, per-unit (writes, doStep));
    ``jacobi``: every unit's inputs are written before any unit steps (else Gauss-Seidel:
    each unit's inputs written just before its doStep); ``step_source``: the master's
    ``_step_read`` source, read at the end of every step (or None).
    """

    def __init__(self, raw: tuple[Any, ...], jacobi: bool, step_source: Any | None) -> None:
        insts, _, plan = raw
        self.instances: tuple[Any, ...] = tuple(insts)
        inst_ix = {id(inst): i for i, inst in enumerate(self.instances)}
        reads: dict[int, int] = {}
        ops: list[tuple[int, int, int, int, int, int, int, int]] = []
        #: per op: (instance, FMI function name) for the error of a failed call
        self._where: list[tuple[Any, str]] = []

        def read(src: Any, rr: Any) -> None:
            comp, vr, n, buf = rr.args
            slot = reads.setdefault(id(src), len(reads))
            ops.append((_READ, inst_ix[id(rr.inst)], slot, n.value, _fn(rr.fn), comp.value,
                        _address(vr), _address(buf)))
            self._where.append((rr.inst, rr.function))

        def write(writes: Sequence[Any]) -> None:
            for sources, wr in writes:
                for src, _, copies, rr in sources:
                    read(src, _raw_call(rr))
                    for dst, s in copies:
                        ops.append((_COPY, 0, 0, dst.nbytes, 0, 0, _address(dst), _address(s)))
                        self._where.append((None, "copy"))
                w = _raw_call(wr)
                comp, vr, n, buf = w.args
                ops.append((_WRITE, inst_ix[id(w.inst)], 0, n.value, _fn(w.fn), comp.value,
                            _address(vr), _address(buf)))
                self._where.append((w.inst, w.function))

        def step(raw_step: Any) -> None:
            d = RawDoStep(*raw_step)
            ops.append((_STEP, inst_ix[id(d.inst)], 0, d.no_set_prior.value, _fn(d.fn),
                        d.component.value, 0, 0))
            self._where.append((d.inst, "fmi2DoStep"))

        if jacobi:
            for writes, _ in plan:
                write(writes)
            for _, d in plan:
                step(d)
        else:
            for writes, d in plan:
                write(writes)
                step(d)
        self.step_source = step_source
        if step_source is not None:
            read(step_source, step_source.read.raw)
        n = 3 + _WORDS * len(ops) + len(self.instances) + len(reads)
        self._buf = (ctypes.c_int64 * n)(len(ops), len(self.instances), len(reads))
        for i, op in enumerate(ops):
            self._buf[3 + _WORDS * i: 3 + _WORDS * (i + 1)] = [ctypes.c_int64(v).value
                                                               for v in op]
        self.address = ctypes.addressof(self._buf)
        self.ops = len(ops)

    def step(self, t: float, h: float) -> None:
        """Make the step's calls at time ``t`` with step ``h`` [s]; a call answering worse
        than fmi2Warning raises its instance's :class:`~axir.orchestrator.errors.FmiError`
        (nothing after it is called), as the Python path does. The instances must not be
        freed (the caller checks, as :meth:`Master._advance_raw` does)."""
        code = _stepper.step(self.address, t, h)
        for inst in self.instances:
            inst.epoch += 1
        if code >= 0:
            inst, function = self._where[code >> 8]
            inst.fail(function, code & 0xFF)
        src = self.step_source
        if src is not None:
            src.epoch = src.inst.epoch


def _raw_call(r: Any) -> RawCall:
    """A :class:`~axir.orchestrator.fmi.RawCall` from its tuple form in a raw plan."""
    return r if isinstance(r, RawCall) else RawCall(*r)
