"""The one place where the master talks FMI 2.0 (through fmpy's low-level ``FMU2Slave``).

- :class:`FmuInstance` wraps one co-simulation instance: every FMI call goes through
  :meth:`FmuInstance.call`, which maps a non-OK status to :class:`FmiError` naming the instance,
  the function and the FMU's last log messages.
- Teardown is explicit and idempotent: ``fmi2FreeInstance`` then ``freeLibrary`` (the pythonfmu
  exit-crash trap, see README); instances are context managers, and :class:`FmuInstance.close`
  is safe to call twice.
- :class:`Port` is a block of value references of one type with a preallocated ctypes buffer,
  so a connection moves many values with two C calls and no Python lists.
- Speed (see docs/performance.md): :meth:`FmuInstance.call` calls the library's ctypes function
  pointers directly (fmpy's per-call wrapper costs a ``getattr``, a dict lookup and a Python
  frame per call); :meth:`FmuInstance.bind` pre-binds a call's arguments for the master's hot
  path. Both check the status in :meth:`FmuInstance._check` (the one place that raises
  :class:`FmiError`). ``FmuInstance.epoch`` counts the calls that may change the instance
  (everything but ``fmi2Get*``), so the master can reuse outputs read since the last change.
"""

from __future__ import annotations

import contextlib
import ctypes
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2Boolean,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2Integer,
    fmi2Real,
    fmi2ValueReference,
)
from fmpy.model_description import ModelDescription, ScalarVariable

from .archive import extract_once
from .errors import AxirError, FmiError

_CTYPE = {"Real": fmi2Real, "Integer": fmi2Integer, "Boolean": fmi2Boolean}
_STATUS = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"]
_WARNING = 1  # statuses above this raise (as fmpy does)


class RawCall(NamedTuple):
    """A call bound by :meth:`FmuInstance.bind` in parts, for a caller that inlines it (the
    master's stepping loop, issue 14): if ``inst.freed``: ``inst.fail(function, None)``; if
    ``mutates``: ``inst.epoch += 1``; ``status = fn(*args)``; if ``status > _WARNING``:
    ``inst.fail(function, status)``."""

    inst: FmuInstance
    fn: Any
    args: tuple[Any, ...]
    mutates: bool
    function: str


class RawDoStep(NamedTuple):
    """:meth:`FmuInstance.bind_do_step` in parts (see :class:`RawCall`): freed check,
    ``inst.epoch += 1``, ``t_arg.value = t``, ``h_arg.value = h``,
    ``status = fn(component, t_arg, h_arg, no_set_prior)``, status check."""

    inst: FmuInstance
    fn: Any
    component: Any
    t_arg: Any
    h_arg: Any
    no_set_prior: Any


_libc = ctypes.CDLL(None)
_libc.calloc.restype = ctypes.c_void_p
_libc.calloc.argtypes = [ctypes.c_size_t, ctypes.c_size_t]
_libc.free.argtypes = [ctypes.c_void_p]

#: log lists of live instances, keyed by the integer each passes as componentEnvironment
_LOGS: dict[int, list[str]] = {}
_NEXT_LOG_KEY = 0


def _route_log(env, instance_name, status, category, message) -> None:
    """The one FMI logger of the process. fmpy's native variadic proxy keeps a single global
    Python logger, so a per-instance logger would receive every instance's messages (and a
    freed per-instance thunk could be called at exit): messages are routed by the
    componentEnvironment key instead."""
    log = _LOGS.get(env or 0)
    if log is None:
        return
    text = message.decode("utf-8", "replace") if message else ""
    label = _STATUS[status] if 0 <= status < len(_STATUS) else str(status)
    log.append(f"[{label}] {text}")
    if len(log) > 200:
        del log[:100]


# Module-level ctypes thunks: alive until the interpreter ends, so a library calling a callback
# late (fmi2FreeInstance, library unload, process exit) never reaches freed memory.
_LOGGER = fmi2CallbackLoggerTYPE(_route_log)
_ALLOCATE = fmi2CallbackAllocateMemoryTYPE(_libc.calloc)
_FREE = fmi2CallbackFreeMemoryTYPE(_libc.free)
try:
    from fmpy import logging as _fmpy_logging

    _add_logger_proxy = _fmpy_logging.addLoggerProxy
except Exception:  # pragma: no cover - fmpy without the variadic proxy
    _add_logger_proxy = None


def extract(path: Path) -> Path:
    """Extract an FMU once per content (cached per process) and return the directory."""
    path = Path(path)
    if not path.is_file():
        raise AxirError(f"FMU file not found: {path}")
    return extract_once(path, "an FMU")


def load_model_description(path: Path) -> ModelDescription:
    """Read an FMU's modelDescription, with a clear error."""
    try:
        return read_model_description(str(path), validate=False)
    except Exception as e:  # fmpy raises bare Exceptions for malformed files
        raise AxirError(f"cannot read the modelDescription of {path}: {e}") from None


@dataclass
class Port:
    """Value references of one type on one instance, with a reusable ctypes buffer."""

    inst: FmuInstance
    kind: str  # "Real" | "Integer" | "Boolean"
    names: tuple[str, ...]
    vr: Any
    buf: Any

    def read(self) -> Any:
        """Fetch the current values into ``buf`` and return it."""
        self.inst.get_into(self.kind, self.vr, self.buf)
        return self.buf

    def write(self, values: Sequence[float] | None = None) -> None:
        """Send ``values`` (or the current ``buf``) to the instance."""
        if values is not None:
            for i, v in enumerate(values):
                self.buf[i] = v
        self.inst.set_from(self.kind, self.vr, self.buf)


class FmuInstance:
    """One instantiated co-simulation FMU. Use as a context manager, or call :meth:`close`."""

    def __init__(self, path: Path, instance_name: str, logging_on: bool = False) -> None:
        self.path = Path(path)
        self.name = instance_name
        self.md = load_model_description(self.path)
        if self.md.coSimulation is None:
            raise AxirError(f"{self.path} does not support FMI 2.0 co-simulation")
        self.variables: dict[str, ScalarVariable] = {v.name: v for v in self.md.modelVariables}
        self.log: list[str] = []
        self._fmu: FMU2Slave | None = None
        self._component = None
        self._lib_loaded = False
        unzip = extract(self.path)
        self._fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=str(unzip),
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=instance_name,
        )
        self._lib_loaded = True
        self._callbacks = self._make_callbacks()
        try:
            self._fmu.instantiate(callbacks=self._callbacks, loggingOn=logging_on)
        except Exception:
            self.close()
            raise FmiError(instance_name, "fmi2Instantiate", 3, self.log) from None
        self._component = self._fmu.component
        #: True once the instance is freed (set by :meth:`close` with ``_component = None``)
        self.freed = False
        #: incremented by every call that may change the instance (all but fmi2Get*)
        self.epoch = 0
        # fmpy's ctypes function pointers (argtypes/restype set by fmpy) and whether the
        # function returns an fmi2Status, as fmpy's _call checks it
        self._cfun: dict[str, tuple[Any, bool, bool]] = {
            name: (f, f.restype is ctypes.c_int, not name.startswith("fmi2Get"))
            for name, f in getattr(self._fmu, "_functions", {}).items()
        }

    # -- logging -------------------------------------------------------------------------
    def _make_callbacks(self) -> fmi2CallbackFunctions:
        """Callbacks whose function pointers are module-level thunks (never freed, see
        :func:`_route_log`); ``componentEnvironment`` carries this instance's log key."""
        global _NEXT_LOG_KEY
        _NEXT_LOG_KEY += 1
        self._log_key = _NEXT_LOG_KEY
        _LOGS[self._log_key] = self.log
        cb = fmi2CallbackFunctions()
        cb.logger = _LOGGER
        cb.allocateMemory = _ALLOCATE
        cb.freeMemory = _FREE
        cb.componentEnvironment = self._log_key
        if _add_logger_proxy is not None:
            _add_logger_proxy(ctypes.byref(cb))
        return cb

    # -- the choke point -----------------------------------------------------------------
    def call(self, function: str, *args: Any) -> int:
        """Call ``<function>(component, *args)``; status above Warning → :class:`FmiError`."""
        comp = self._component
        if comp is None:
            self._check(function, None)
        entry = self._cfun.get(function)
        if entry is None:  # not a C function fmpy loaded: its Python method, as before
            if not function.startswith("fmi2Get"):
                self.epoch += 1
            try:
                return getattr(self._fmu, function)(comp, *args)
            except FMICallException as e:
                raise FmiError(self.name, function, e.status, self.log) from None
        f, returns_status, mutates = entry
        if mutates:
            self.epoch += 1
        status = f(comp, *args)
        if returns_status and status > _WARNING:
            self._check(function, status)
        return status

    def _raw(self, function: str, args: Sequence[Any]) -> tuple[Any, tuple[Any, ...]] | None:
        """The C function without ctypes argument conversion, and ``(component, *args)``
        converted once to the C types fmpy declares (arrays passed as they are): ctypes'
        per-call ``from_param`` of pointer arguments costs ≈ 1 µs per call. None when an
        argument is not a fixed ctypes array / number (then :meth:`call` converts per call)."""
        f = self._cfun.get(function, (None,))[0]
        types = getattr(f, "argtypes", None)
        if f is None or types is None or len(types) != len(args) + 1 or f.restype is not \
                ctypes.c_int or not isinstance(self._component, (int, ctypes.c_void_p)):
            return None
        conv: list[Any] = [ctypes.c_void_p(getattr(self._component, "value", self._component))]
        for a, t in zip(args, types[1:], strict=True):
            if isinstance(a, ctypes.Array):
                conv.append(a)
            elif isinstance(a, (int, float)) and not hasattr(t, "contents") and t is not \
                    ctypes.c_void_p:
                conv.append(t(a))
            else:
                return None
        # PYFUNCTYPE: the GIL stays held (pythonfmu takes it anyway; no release/re-take)
        raw = ctypes.PYFUNCTYPE(ctypes.c_int)(ctypes.cast(f, ctypes.c_void_p).value)
        return raw, tuple(conv)

    def bind(self, function: str, *args: Any) -> Any:
        """A no-argument callable doing :meth:`call` ``(function, *args)`` (same checks, same
        errors), with the lookups and argument conversions done once: for calls repeated every
        step on fixed buffers."""
        entry = self._cfun.get(function)
        if entry is None:
            return lambda: self.call(function, *args)
        f, returns_status, mutates = entry
        check = self._check
        raw = self._raw(function, args) if returns_status else None
        if raw is not None:
            fn, conv = raw

            def invoke_raw() -> int:
                if self._component is None:
                    check(function, None)
                if mutates:
                    self.epoch += 1
                status = fn(*conv)
                if status > _WARNING:
                    check(function, status)
                return status

            # for a caller that inlines this call (Master's stepping loop): the same steps
            invoke_raw.raw = RawCall(self, fn, conv, mutates, function)  # type: ignore[attr-defined]
            return invoke_raw

        def invoke() -> int:
            comp = self._component
            if comp is None:
                check(function, None)
            if mutates:
                self.epoch += 1
            status = f(comp, *args)
            if returns_status and status > _WARNING:
                check(function, status)
            return status

        return invoke

    def bind_do_step(self) -> Any:
        """A callable ``(t, h)`` doing :meth:`do_step` (same checks, same errors) without the
        per-call lookups: the master's hot path."""
        raw = self._raw("fmi2DoStep", (0.0, 0.0, 1))
        if raw is None:
            return self.do_step
        fn, (comp, ct, ch, no_set_prior) = raw  # ct, ch: this callable's own c_double
        check = self._check

        def do_step(t: float, h: float) -> None:
            if self._component is None:
                check("fmi2DoStep", None)
            self.epoch += 1
            ct.value = t  # (cheaper than two new c_double per call)
            ch.value = h
            status = fn(comp, ct, ch, no_set_prior)
            if status > _WARNING:
                check("fmi2DoStep", status)

        # for a caller that inlines this call: the same steps, ``t`` and ``h`` into ct, ch
        do_step.raw = RawDoStep(self, fn, comp, ct, ch, no_set_prior)  # type: ignore[attr-defined]
        return do_step

    def fail(self, function: str, status: int | None) -> None:
        """Raise the :class:`FmiError` of ``function`` answering ``status`` (None: the
        instance is freed); for a caller of a :class:`RawCall` whose status was not OK."""
        self._check(function, status)

    def _check(self, function: str, status: int | None) -> None:
        """Raise the :class:`FmiError` of a failed call (None: the instance is freed)."""
        if status is None:
            raise FmiError(self.name, function, 3, ["instance already freed"])
        if status > _WARNING:
            raise FmiError(self.name, function, status, self.log)

    def get_into(self, kind: str, vr: Any, buf: Any) -> None:
        self.call(f"fmi2Get{kind}", vr, len(vr), buf)

    def set_from(self, kind: str, vr: Any, buf: Any) -> None:
        self.call(f"fmi2Set{kind}", vr, len(vr), buf)

    # -- variables -------------------------------------------------------------------------
    def variable(self, name: str) -> ScalarVariable:
        try:
            return self.variables[name]
        except KeyError:
            raise AxirError(f"{self.name} ({self.path.name}) has no variable {name!r}") from None

    def port(self, names: Sequence[str]) -> Port:
        """A :class:`Port` over variables that all have the same type."""
        vars_ = [self.variable(n) for n in names]
        kinds = {v.type for v in vars_}
        if len(kinds) != 1 or next(iter(kinds)) not in _CTYPE:
            raise AxirError(f"{self.name}: port over mixed or unsupported types {sorted(kinds)}")
        kind = kinds.pop()
        n = len(vars_)
        vr = (fmi2ValueReference * n)(*[v.valueReference for v in vars_])
        return Port(self, kind, tuple(names), vr, (_CTYPE[kind] * n)())

    def set_parameter(self, name: str, value: Any) -> None:
        """Set one parameter/input by name, converting to its FMI type."""
        v = self.variable(name)
        vr = (fmi2ValueReference * 1)(v.valueReference)
        if v.type == "String":
            self.call("fmi2SetString", vr, 1, (ctypes.c_char_p * 1)(str(value).encode()))
            return
        if v.type == "Boolean":
            value = bool(value)
        elif v.type == "Integer" or v.type == "Enumeration":
            if isinstance(value, float) and not value.is_integer():
                raise AxirError(f"{self.name}.{name} is an Integer, got {value!r}")
            value = int(value)
        else:
            value = float(value)
        kind = "Integer" if v.type == "Enumeration" else v.type
        self.set_from(kind, vr, (_CTYPE[kind] * 1)(value))

    # -- life cycle ------------------------------------------------------------------------
    def setup(self, start: float = 0.0, stop: float | None = None) -> None:
        stop_defined = 1 if stop is not None else 0
        self.call("fmi2SetupExperiment", 0, 0.0, start, stop_defined, stop or 0.0)

    def enter_init(self) -> None:
        self.call("fmi2EnterInitializationMode")

    def exit_init(self) -> None:
        self.call("fmi2ExitInitializationMode")

    def do_step(self, t: float, h: float) -> None:
        self.call("fmi2DoStep", t, h, 1)

    def terminate(self) -> None:
        self.call("fmi2Terminate")

    def close(self) -> None:
        """fmi2FreeInstance then freeLibrary, exactly once each (idempotent)."""
        fmu = self._fmu
        if fmu is None:
            return
        if self._component is not None:
            try:
                fmu.fmi2FreeInstance(self._component)
            finally:
                self._component = None
                self.freed = True
        if self._lib_loaded:
            self._lib_loaded = False
            fmu.freeLibrary()
        self._fmu = None
        _LOGS.pop(getattr(self, "_log_key", 0), None)

    def __enter__(self) -> FmuInstance:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:  # last resort; normal paths close explicitly
        with contextlib.suppress(Exception):
            self.close()
