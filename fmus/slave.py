"""The runtime slave of every axir FMU: a pythonfmu ``Fmi2Slave`` driven by an
:class:`~.spec.FmuSpec`.

- all values live in one numpy buffer per FMI type, views into the block shared with the C
  shim (:mod:`.shared_block`: the shim serves valid get/set calls from it without entering
  Python); ``get_real``/``set_real`` & co. (the calls the shim forwards) are
  vectorised through value-reference → buffer-index maps (no per-variable Python call); the
  model is built at ``exit_initialization_mode`` from the parameter values; ``do_step`` hands
  the inputs to ``model.step`` and scatters the outputs back (:mod:`.step_plan`); the shim
  calls the slave's fast step directly for a doStep with nothing else to do;
- the whole model state for ``fmi2GetFMUstate``/``fmi2SetFMUstate`` and
  ``fmi2SerializeFMUstate`` (data-only, versioned format of :mod:`.state_codec`; no pickle);
- at instantiation, the bundle put on this instance's resources (:func:`~.digest.add_bundle_root`)
  and checked (:func:`~.digest.verify_bundle`).

pythonfmu 0.7.0 facts this module is built around (see docs/fmu_build.md):

- any Python exception escaping a callback becomes ``fmi2Fatal`` and frees the Python
  instance: every callback here catches everything;
- a callback cannot return ``fmi2Warning`` or ``fmi2Error``: the only non-OK, non-fatal status
  is ``fmi2Discard`` from ``do_step`` returning ``False``. Errors (invalid parameter, model
  exception) are therefore logged with status Error; the C shim that
  :mod:`axir.fmus.build` puts around pythonfmu's binary turns the call that logged them into
  ``fmi2Error`` (without it: ``fmi2Discard`` from the next and every following
  ``fmi2DoStep``); warnings (out-of-domain inputs) are logged, and the shim answers that
  call ``fmi2Warning``;
- log messages reach the importer only if the instance was created with ``loggingOn``.

This module must only use relative imports: it is bundled into every FMU under a unique,
content-hashed package name (``_axir_<hash8>.fmus.slave``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, ClassVar

import numpy as np
from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Integer, Real, String
from pythonfmu.enums import Fmi2Status, Fmi2Variability

from .digest import add_bundle_root, verify_bundle
from .shared_block import (
    CTL_DIRTY,
    CTL_INITIALIZED,
    CTL_SCREENED,
    SETTABLE_INIT,
    SETTABLE_RUN,
    TUNABLE,
    SharedBlock,
)
from .spec import LOG_CATEGORIES, FmuSpec, Scalar, layout
from .state_check import checked_state
from .state_codec import StateFormatError, decode_state, encode_state
from .step_plan import StepPlan, make_fast_io, make_fast_step

_KINDS = ("Real", "Integer", "Boolean", "String")
_NP_DTYPES = {"Real": np.float64, "Integer": np.int64, "Boolean": np.bool_}


class AxirSlave(Fmi2Slave):
    """pythonfmu slave driven by an :class:`FmuSpec` (set ``SPEC`` and ``BUNDLE`` in a subclass).

    The generated slave script of each FMU subclasses this with ``SPEC`` (the declaration)
    and ``BUNDLE = (package name, full hash)``.
    """

    SPEC: ClassVar[FmuSpec]
    BUNDLE: ClassVar[tuple[str, str] | None] = None

    log_categories: ClassVar[dict[str, str]] = LOG_CATEGORIES

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        spec = self.SPEC
        self.modelName = spec.name
        self.description = spec.description
        self.model: Any = None
        self._failed: str | None = None  # set once the instance is unusable (error message)
        self._time = 0.0
        if self.BUNDLE is not None:
            add_bundle_root(self.BUNDLE[0], self.resources)
            err = verify_bundle(*self.BUNDLE)
            if err is None and not spec.model.__module__.startswith(self.BUNDLE[0] + "."):
                err = (f"model class {spec.model.__module__}.{spec.model.__name__} is not "
                       f"from the bundled package {self.BUNDLE[0]}")
            if err is not None:
                self._fail(err, Fmi2Status.fatal)
        self._build_tables(layout(spec))
        # to the C shim: it serves get/set from the same arrays (not after a failed bundle
        # check: its Fatal log must reach the host with the next call, through pythonfmu)
        self._shared.hand_over(usable=self._failed is None, fast_step=self._fast_step,
                               fast_io=self._fast_io)

    # initialized / tunable parameters changed: words of the shared block (the shim reads the
    # first to know what is settable, and sets the second when it sets a tunable parameter)
    _initialized = property(lambda self: bool(self._ctl[CTL_INITIALIZED]),
                            lambda self, v: self._ctl.__setitem__(CTL_INITIALIZED, bool(v)))
    _dirty_params = property(lambda self: bool(self._ctl[CTL_DIRTY]),
                             lambda self, v: self._ctl.__setitem__(CTL_DIRTY, bool(v)))

    # -- tables ---------------------------------------------------------------------------
    def _build_tables(self, rows: list[Scalar]) -> None:
        """Buffers per type, vr → (type, index) maps, slices per declared variable."""
        spec = self.SPEC
        n = len(rows)
        counts = dict.fromkeys(_KINDS, 0)
        self._kind_of = [r.kind for r in rows]
        self._index: dict[str, np.ndarray] = {k: np.full(n, -1, dtype=np.intp) for k in _KINDS}
        self._settable_init = np.zeros(n, dtype=bool)  # settable before/in initialization
        self._param_rows: list[tuple[str, str, int]] = []  # (param name, kind, index)
        self._rows = rows
        pnames = [p.name for p in spec.model.PARAMS]
        starts: dict[str, list[Any]] = {k: [] for k in _KINDS}
        for vr, r in enumerate(rows):
            i = counts[r.kind]
            counts[r.kind] += 1
            self._index[r.kind][vr] = i
            self._settable_init[vr] = r.causality in ("parameter", "input")
            starts[r.kind].append(r.start if r.start is not None else _zero(r.kind))
            if r.causality == "parameter":
                self._param_rows.append((pnames[len(self._param_rows)], r.kind, i))
        self._tunable = np.array([r.variability == "tunable" for r in rows], dtype=bool)
        inputs = np.array([r.causality == "input" for r in rows], dtype=bool)
        self._settable_run = inputs | self._tunable  # settable after initialization
        # per declared variable: (key, kind, slice in its type buffer, shape)
        first = {r.name: self._index[r.kind][vr] for vr, r in enumerate(rows)}
        self._inputs = [(v.name, v.type, first[v.scalar_names()[0]], v.size, v.shape)
                        for v in spec.inputs]
        self._outputs = [(v.name, v.type, first[v.scalar_names()[0]], v.size, v.shape)
                         for v in spec.outputs]
        self._build_domains(rows)
        flags = (self._settable_init * SETTABLE_INIT + self._settable_run * SETTABLE_RUN
                 + self._tunable * TUNABLE)
        self._shared = SharedBlock(
            self._kind_of, [int(self._index[r.kind][vr]) for vr, r in enumerate(rows)],
            flags.tolist(), [r.name for r in rows], starts,
            {d[0]: (np.arange(counts[d[0]])[d[1]], d[2], d[3]) for d in self._domains})
        self._buf: dict[str, Any] = {"Real": self._shared.real, "Integer": self._shared.integer,
                                     "Boolean": self._shared.boolean,
                                     "String": list(starts["String"])}
        for d in self._domains:  # the held values live in the block too (the shim updates them)
            self._shared.held[d[0]][:] = d[6]
        self._domains = [(*d[:6], self._shared.held[d[0]], d[7]) for d in self._domains]
        self._ctl = self._shared.ctl  # [initialized, dirty, screened]: see the properties above
        self._plan = StepPlan(self._shared.block, self._buf, self._inputs, self._outputs)
        self._gather, self._scatter = self._plan.gather, self._plan.scatter
        self._pending: BaseException | None = None  # raised by the fast step (step_plan)
        self._fast_step = make_fast_step(self, self._plan, self._shared.step)
        self._time_before = 0.0  # the time before the fast step (step_plan.make_fast_io)
        self._fast_io = make_fast_io(self, self._plan, self._shared.step, self._inputs,
                                     self._outputs, self._buf, self._shared.block)
        # validated value-reference tuples → buffer index (slice or index array), filled on
        # first use by the slow paths of _get/_set; set plans per initialization state
        self._get_plans: dict[str, dict[tuple[int, ...], Any]] = {k: {} for k in _NP_DTYPES}
        self._set_plans: dict[bool, dict[str, dict[tuple[int, ...], tuple[Any, bool]]]] = {
            init: {k: {} for k in _NP_DTYPES} for init in (False, True)}
        # pythonfmu bookkeeping: register every scalar (value reference = position)
        for vr, r in enumerate(rows):
            cls = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}[r.kind]
            v = cls(r.name, causality=getattr(Fmi2Causality, r.causality),
                    variability=getattr(Fmi2Variability, r.variability),
                    description=r.description,
                    getter=(lambda vr=vr: self._get_one(vr)), setter=(lambda x: None))
            self.register_variable(v, nested=False)

    def _build_domains(self, rows: list[Scalar]) -> None:
        """Per type (Real, Integer): the input scalars' buffer indices, closed domain bounds
        (the ports' ``bounds()``), replacement policy (hold or start value), start values,
        names and the held last valid values (:meth:`_screen_inputs`)."""
        ports = {p.name: p for p in self.SPEC.model.INPUTS}
        self._domains: list[tuple[str, Any, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                  np.ndarray, list[str]]] = []
        for kind in ("Real", "Integer"):
            idx: list[int] = []
            lo: list[Any] = []
            hi: list[Any] = []
            use_start: list[bool] = []
            start: list[Any] = []
            names: list[str] = []
            for key, k, i, size, _ in self._inputs:
                if k != kind:
                    continue
                port = ports[key]
                a, b = port.bounds()
                idx += range(int(i), int(i) + size)
                lo += [a] * size
                hi += [b] * size
                use_start += [port.invalid == "start"] * size
                start += [port.initial] * size
                names += port.scalar_names()
            if not idx:
                continue
            dt = _NP_DTYPES[kind]
            self._domains.append((kind, _as_index(np.array(idx, dtype=np.intp)),
                                  np.array(lo, dtype=dt), np.array(hi, dtype=dt),
                                  np.array(use_start, dtype=bool), np.array(start, dtype=dt),
                                  np.array(start, dtype=dt), names))

    def _get_one(self, vr: int) -> Any:
        kind = self._kind_of[vr]
        return self._buf[kind][self._index[kind][vr]]

    # -- logging / failure ------------------------------------------------------------------
    def log(self, msg: str, status: Fmi2Status = Fmi2Status.ok, category: str | None = None,
            debug: Any = None) -> None:
        """Queue a log message; '%' is doubled (pythonfmu passes it as a printf format)."""
        super().log(msg.replace("%", "%%"), status, category)

    def _fail(self, msg: str, status: Fmi2Status = Fmi2Status.error) -> None:
        """Mark the instance unusable; every later do_step returns False (pythonfmu:
        fmi2Discard; fmi2Error through the C shim, which sees the Error log)."""
        self._failed = msg
        self.log(msg, status)

    def _log_error(self, where: str, exc: BaseException) -> None:
        self.log(f"{self.instance_name}: {where}: {type(exc).__name__}: {exc}", Fmi2Status.error)

    # -- FMI life cycle ---------------------------------------------------------------------
    def setup_experiment(self, start_time: float = 0.0, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        """Remember the start time."""
        try:
            self._time = float(start_time)
        except Exception as e:  # never let an exception reach pythonfmu (fmi2Fatal)
            self._log_error("setup_experiment", e)

    def enter_initialization_mode(self) -> None:
        """Nothing to do: parameters are collected at exit."""

    def _param_values(self) -> dict[str, Any]:
        vals: dict[str, Any] = {}
        for name, kind, i in self._param_rows:
            x = self._buf[kind][i]
            vals[name] = (float(x) if kind == "Real" else int(x) if kind == "Integer"
                          else bool(x) if kind == "Boolean" else str(x))
        return vals

    def exit_initialization_mode(self) -> None:
        """Build the model from the parameter values (invalid → Error log, instance failed)."""
        if self._failed:
            self.log(self._failed, Fmi2Status.error)
            return
        try:
            self.model = self.SPEC.model(**self._param_values())
        except ValueError as e:
            self._fail(f"{self.instance_name}: invalid parameter: {e}")
            return
        except Exception as e:
            self._fail(f"{self.instance_name}: model construction failed: "
                       f"{type(e).__name__}: {e}")
            return
        self._initialized = True
        self._dirty_params = False
        self._init_held()
        try:  # every output is initial="calculated": the model's outputs at its initial state
            self._scatter(self.model.outputs())
        except Exception as e:
            self._fail(f"{self.instance_name}: initial outputs failed: "
                       f"{type(e).__name__}: {e}")

    def terminate(self) -> None:
        """Nothing to release."""

    # -- stepping ---------------------------------------------------------------------------
    def _init_held(self) -> None:
        """At initialization: the held values are the inputs set so far (start values where
        they are out of domain)."""
        for kind, idx, lo, hi, _, start, held, _ in self._domains:
            vals = self._buf[kind][idx]
            held[:] = np.where((vals >= lo) & (vals <= hi), vals, start)

    def _screen_inputs(self) -> list[tuple[str, int, Any, Any, str]]:
        """THE input check: every Real/Integer input against its port's domain (NaN, ±inf,
        out of range). In domain: remembered as the last valid value. Out of domain: listed as
        (type, buffer index, value, replacement, name); the replacement is the last valid
        value (``Port.invalid == "hold"``) or the start value (``"start"``). Fast path: the C
        shim makes the same comparisons on the same bounds (``lo <= v <= hi``, from the
        block) just before each doStep and, when all pass, updates ``held`` and sets the
        ``screened`` word: nothing is left to do here."""
        bad: list[tuple[str, int, Any, Any, str]] = []
        if self._ctl[CTL_SCREENED]:  # the C shim found every input in domain (held updated)
            self._ctl[CTL_SCREENED] = 0
            return bad
        for kind, idx, lo, hi, use_start, start, held, names in self._domains:
            vals = self._buf[kind][idx]
            ok = (vals >= lo) & (vals <= hi)
            if ok.all():
                held[:] = vals
                continue
            buf_idx = np.arange(len(self._buf[kind]))[idx]
            for j in np.flatnonzero(~ok).tolist():
                repl = start[j] if use_start[j] else held[j]
                bad.append((kind, int(buf_idx[j]), vals[j].item(), repl.item(), names[j]))
            held[ok] = vals[ok]
        return bad

    def _gather_screened(self) -> dict[str, Any]:
        """Inputs for ``model.step`` after :meth:`_screen_inputs`: out-of-domain values are
        replaced for the model (the buffers keep what the host set), logged as a Warning naming
        variable and value, and reported to the model (``note_invalid_inputs``)."""
        bad = self._screen_inputs()
        if not bad:
            return self._gather()
        buf = self._buf
        for kind, i, _, repl, _ in bad:
            buf[kind][i] = repl
        try:
            inputs = self._gather()
        finally:
            for kind, i, value, _, _ in bad:
                buf[kind][i] = value
        text = "; ".join(f"{name} = {value!r} (replaced by {repl!r})"
                         for _, _, value, repl, name in bad[:8])
        self.log(f"{self.instance_name}: t={self._time!r}: input(s) out of domain: {text}"
                 f"{f'; and {len(bad) - 8} more' if len(bad) > 8 else ''} (domains: the "
                 "variables' min/max in the modelDescription; NaN and inf never valid)",
                 Fmi2Status.warning)
        note = getattr(self.model, "note_invalid_inputs", None)
        if note is not None:
            note([b[4] for b in bad])
        return inputs

    def do_step(self, current_time: float, step_size: float) -> bool:
        """One communication step; False (fmi2Discard) on any failure, with an Error log."""
        if self._failed:
            self.log(self._failed, Fmi2Status.error)
            return False
        if not self._initialized:
            self._fail(f"{self.instance_name}: fmi2DoStep before fmi2ExitInitializationMode")
            return False
        try:
            if self._pending is not None:  # the fast step's exception (see .step_plan)
                pending, self._pending = self._pending, None
                raise pending
            if self._dirty_params:
                self._apply_tunable()
            out = self.model.step(float(step_size), self._gather_screened())
            self._scatter(out)
            self._time = float(current_time) + float(step_size)
            return True
        except Exception as e:
            self._fail(f"{self.instance_name}: do_step(t={current_time!r}, h={step_size!r}) "
                       f"failed: {type(e).__name__}: {e}; the model state is undefined, "
                       "restore an FMU state or reset the instance")
            return False

    def _apply_tunable(self) -> None:
        """Validate and apply changed tunable parameters (invalid → Error log, kept old)."""
        self._dirty_params = False
        vals = self._param_values()
        try:
            self.SPEC.model(**vals)  # full validation (incl. cross checks) on a throw-away
        except ValueError as e:
            old = self.model.params()
            for name, kind, i in self._param_rows:
                self._buf[kind][i] = old[name]
            self.log(f"{self.instance_name}: invalid tunable parameter ignored: {e}",
                     Fmi2Status.error)
            return
        self.model.configure(vals)

    # -- vectorised get/set -----------------------------------------------------------------
    # pythonfmu's binary hands every call a fresh Python list of value references. The first
    # call with a given list is validated by the slow path (``_indices``, settable checks) and
    # its buffer index (a slice when contiguous) is remembered under ``tuple(vrs)``; later calls
    # with the same list cost one dict lookup and one slice/fancy-index copy. Invalid requests
    # are never remembered, so they take the slow path (and log) every time.
    def _indices(self, kind: str, vrs: Sequence[int]) -> np.ndarray | None:
        try:
            idx = self._index[kind][vrs]
            if len(vrs) and min(vrs) < 0:  # a negative index would wrap in numpy
                idx = None
        except (IndexError, TypeError, ValueError):
            idx = None
        if idx is None or (idx < 0).any():
            self.log(f"{self.instance_name}: get/set {kind}: value reference(s) {list(vrs)} "
                     f"not all of type {kind}", Fmi2Status.error)
            return None
        return idx

    def _get(self, kind: str, vrs: Sequence[int], conv: Callable[[Any], Any]) -> list[Any]:
        try:
            return self._buf[kind][self._get_plans[kind][tuple(vrs)]].tolist()
        except Exception:  # not seen yet (KeyError) or anything odd: the checked path
            pass
        try:
            idx = self._indices(kind, vrs)
            if idx is None:
                return [conv(0)] * len(vrs)
            plans = self._get_plans[kind]
            if len(plans) < _PLAN_CACHE_MAX:
                plans[tuple(vrs)] = _as_index(idx)
            return self._buf[kind][idx].tolist()
        except Exception as e:
            self._log_error(f"get {kind}", e)
            return [conv(0)] * len(vrs)

    def _set(self, kind: str, vrs: Sequence[int], values: Sequence[Any]) -> None:
        try:
            idx, tunable = self._set_plans[self._initialized][kind][tuple(vrs)]
        except Exception:  # not seen yet (KeyError), String, or anything odd: the checked path
            self._set_checked(kind, vrs, values)
            return
        try:
            if tunable:
                self._dirty_params = True
            self._buf[kind][idx] = values
        except Exception as e:
            self._log_error(f"set {kind}", e)

    def _set_checked(self, kind: str, vrs: Sequence[int], values: Sequence[Any]) -> None:
        """Validating set; remembers the index of a fully valid request (see ``_get``)."""
        try:
            idx = self._indices(kind, vrs)
            if idx is None:
                return
            vr_arr = np.asarray(vrs, dtype=np.intp)
            ok = (self._settable_run if self._initialized else self._settable_init)[vr_arr]
            if ok.all() and kind != "String":
                plans = self._set_plans[self._initialized][kind]
                if len(plans) < _PLAN_CACHE_MAX:
                    tunable = bool(self._initialized and self._tunable[vr_arr].any())
                    plans[tuple(vrs)] = (_as_index(idx), tunable)
            if not ok.all():
                names = [self._rows[v].name for v in vr_arr[~ok].tolist()]
                self.log(f"{self.instance_name}: variable(s) {names} cannot be set now "
                         "(outputs; fixed parameters after initialization): ignored",
                         Fmi2Status.error)
                idx = idx[ok]
                values = [x for x, g in zip(values, ok.tolist(), strict=True) if g]
            if self._initialized and self._tunable[vr_arr].any():
                self._dirty_params = True
            if kind == "String":
                for i, x in zip(idx.tolist(), values, strict=True):
                    self._buf["String"][i] = x
            else:
                self._buf[kind][idx] = values
        except Exception as e:
            self._log_error(f"set {kind}", e)

    def get_real(self, vrs: list[int]) -> list[float]:
        """fmi2GetReal."""
        return self._get("Real", vrs, float)

    def get_integer(self, vrs: list[int]) -> list[int]:
        """fmi2GetInteger."""
        return self._get("Integer", vrs, int)

    def get_boolean(self, vrs: list[int]) -> list[bool]:
        """fmi2GetBoolean."""
        return self._get("Boolean", vrs, bool)

    def get_string(self, vrs: list[int]) -> list[str]:
        """fmi2GetString."""
        try:
            idx = self._indices("String", vrs)
            if idx is None:
                return [""] * len(vrs)
            return [str(self._buf["String"][i]) for i in idx.tolist()]
        except Exception as e:
            self._log_error("get String", e)
            return [""] * len(vrs)

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        """fmi2SetReal."""
        self._set("Real", vrs, values)

    def set_integer(self, vrs: list[int], values: list[int]) -> None:
        """fmi2SetInteger."""
        self._set("Integer", vrs, values)

    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        """fmi2SetBoolean."""
        self._set("Boolean", vrs, values)

    def set_string(self, vrs: list[int], values: list[str]) -> None:
        """fmi2SetString."""
        self._set("String", vrs, values)

    # -- FMU state --------------------------------------------------------------------------
    def _get_fmu_state(self) -> dict[str, Any]:
        """The whole instance state: buffers, flags and ``model.get_state()`` (deep copy)."""
        try:
            return {
                "bundle": None if self.BUNDLE is None else self.BUNDLE[1],
                "buf": {k: (v.copy() if k != "String" else list(v))
                        for k, v in self._buf.items()},
                "model": None if self.model is None else self.model.get_state(),
                "held": {d[0]: d[6].copy() for d in self._domains},
                "flags": (self._initialized, self._failed, self._dirty_params, self._time),
            }
        except Exception as e:
            self._log_error("fmi2GetFMUstate", e)
            return {"invalid": f"fmi2GetFMUstate failed: {e}"}

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """Restore a state from :meth:`_get_fmu_state` (the state object stays reusable)."""
        try:
            if "invalid" in state:
                self.log(f"{self.instance_name}: fmi2SetFMUstate: unusable state: "
                         f"{state['invalid']}", Fmi2Status.error)
                return
            mine = None if self.BUNDLE is None else self.BUNDLE[1]
            if state.get("bundle") != mine:
                self.log(f"{self.instance_name}: fmi2SetFMUstate: state from another build "
                         f"({str(state.get('bundle'))[:12]}, this FMU {str(mine)[:12]}): ignored",
                         Fmi2Status.error)
                return
            for k, v in state["buf"].items():  # in place: the shim shares the arrays
                if k == "String":
                    self._buf[k] = list(v)
                else:
                    self._buf[k][:] = v
            for d in self._domains:
                d[6][:] = state["held"][d[0]]
            self._initialized, self._failed, self._dirty_params, self._time = state["flags"]
            if state["model"] is None:
                self.model = None
            else:
                if self.model is None:
                    self.model = self.SPEC.model.__new__(self.SPEC.model)
                self.model.set_state(state["model"])
        except Exception as e:
            self._log_error("fmi2SetFMUstate", e)

    @classmethod
    def _fmu_state_to_bytes(cls, state: dict[str, Any]) -> bytes:
        """Serialise a state: the data-only, versioned format of :mod:`.state_codec` (no
        pickle); a value it cannot hold gives a state that is refused when set."""
        bundle = None if cls.BUNDLE is None else cls.BUNDLE[1]
        try:
            return encode_state(state, cls.SPEC.name, bundle)
        except Exception as e:
            return encode_state({"invalid": f"serialisation failed: {e}"}, cls.SPEC.name, bundle)

    @classmethod
    def _fmu_state_from_bytes(cls, data: bytes) -> dict[str, Any]:
        """Inverse of :meth:`_fmu_state_to_bytes`, validated field by field (pythonfmu calls it
        on the class, so it cannot log: a malformed or foreign state becomes an ``invalid``
        state, refused with an Error log by ``fmi2SetFMUstate``). Runs no code of the data."""
        bundle = None if cls.BUNDLE is None else cls.BUNDLE[1]
        try:
            state = decode_state(data, cls.SPEC.name, bundle)
            return checked_state(cls.SPEC, state)
        except StateFormatError as e:
            return {"invalid": f"not a state of this FMU: {e}"}
        except Exception as e:
            return {"invalid": f"deserialisation failed: {type(e).__name__}: {e}"}


def _zero(kind: str) -> Any:
    return {"Real": 0.0, "Integer": 0, "Boolean": False, "String": ""}[kind]


_PLAN_CACHE_MAX = 256  # remembered value-reference lists per type (get and set each)


def _as_index(idx: np.ndarray) -> slice | np.ndarray:
    """``idx`` as a slice when it is a contiguous ascending run (a view, no fancy indexing),
    else unchanged."""
    n = len(idx)
    if n and int(idx[-1]) - int(idx[0]) == n - 1 and (n == 1 or bool((np.diff(idx) == 1).all())):
        return slice(int(idx[0]), int(idx[0]) + n)
    return idx
