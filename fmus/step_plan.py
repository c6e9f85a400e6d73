"""Moving a step's values between the shared value block and the model, planned once.

:class:`StepPlan` is built once per slave from its declared inputs and outputs (positions in
the typed arrays of :class:`~.shared_block.SharedBlock`): :meth:`StepPlan.gather` makes the
input mapping for ``model.step``, :meth:`StepPlan.scatter` stores the model's output mapping.
Both the regular ``do_step`` (called through pythonfmu) and the fast step the C shim calls
directly (:func:`make_fast_step`) use them, so both hand the model the same values.

The fast step (issue 14): the shim calls it instead of forwarding ``fmi2DoStep`` to pythonfmu
when nothing but the step itself has to happen — the instance is initialized, no tunable
parameter changed, every input passed the shim's domain check. It reads ``t`` and ``h`` from
the block (the shim wrote them), steps the model and returns :data:`FAST_DONE`. Whenever the
regular path is needed (the instance failed, no model) it returns :data:`FAST_FORWARD` having
changed nothing, and the shim forwards the call to pythonfmu as before. An exception of the
model (or of the scatter) is kept as the slave's ``_pending`` and answered
:data:`FAST_FORWARD`: the forwarded ``do_step`` then raises it at the point where the model
would have raised it, so the status (fmi2Error through the shim), the log message and the
instance state are those of the regular path.

Bundled into every FMU: relative imports only.
"""

from __future__ import annotations

import operator
import struct
import sys
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

FAST_DONE = 0  # the step was made: the shim answers fmi2OK
FAST_FORWARD = 1  # nothing done (or a pending exception): forward fmi2DoStep to pythonfmu

# (key, type, start index in its type's array, size, shape) of a declared variable
Entry = tuple[str, str, int, int, tuple[int, ...]]


def _index(idx: Sequence[int]) -> slice | list[int]:
    """``idx`` as a slice when it is a contiguous ascending run (a view), else a list."""
    idx = [int(i) for i in idx]
    if idx and idx == list(range(idx[0], idx[0] + len(idx))):
        return slice(idx[0], idx[0] + len(idx))
    return idx


class StepPlan:
    """Gather/scatter of one slave's inputs and outputs through views of its value arrays.

    ``block``: the shared byte block (uint8); ``buf`` maps "Real", "Integer", "Boolean" to
    the slave's value arrays, views into ``block`` (they never change identity).
    ``inputs``/``outputs``: :data:`Entry` per declared variable, in declaration order.
    """

    def __init__(self, block: np.ndarray, buf: Mapping[str, np.ndarray],
                 inputs: Sequence[Entry], outputs: Sequence[Entry]) -> None:
        # inputs: every scalar read with ONE struct.unpack_from of the block (d: float64 →
        # float, q: int64 → int, ?: bool byte → bool; what ndarray.item gives), in memory
        # order; arrays copied from a precomputed view
        self._mem = memoryview(block)
        base = block.ctypes.data
        fmt = {"Real": "d", "Integer": "q", "Boolean": "?"}
        size = {"Real": 8, "Integer": 8, "Boolean": 1}
        scal = sorted((buf[kind].ctypes.data - base + size[kind] * i, fmt[kind], size[kind], key)
                      for key, kind, i, _, shape in inputs if not shape)
        pos, codes = 0, ["<"]
        for off, code, n, _ in scal:
            codes.append(f"{off - pos}x{code}" if off > pos else code)
            pos = off + n
        self._scalar_keys = tuple(key for *_, key in scal)
        self._unpack = struct.Struct("".join(codes)).unpack_from
        self._array_in: list[tuple[str, Callable[[], np.ndarray]]] = [
            (key, buf[kind][i:i + size].reshape(shape).copy)
            for key, kind, i, size, shape in inputs if shape]
        # outputs: the scalars of each type packed with one struct.pack (d: float64 of each
        # item's __float__/__index__, as numpy's item assignment converts float, int, bool,
        # numpy scalars, 0-d arrays; q: int64 of __index__ — struct rejects the floats and
        # numpy scalars numpy would truncate, which then take the item path; ?: truthiness,
        # what numpy's bool assignment uses) and stored with one byte copy when contiguous
        # (non-contiguous Reals: one numpy assignment of the tuple; non-contiguous Integer or
        # Boolean: the item path); arrays of their declared shape copied into a view of that
        # shape (anything else: np.ravel into the flat view, as before). Whenever a packed
        # store raises, every output takes the item-by-item path, which stores or raises
        # exactly as numpy's item assignment does (issue 14, sessions 5 and 7).
        self._stores: list[Callable[[Mapping[str, Any]], None]] = []
        packed: set[str] = set()
        for kind, code in (("Real", "d"), ("Integer", "q"), ("Boolean", "?")):
            items = [(key, i) for key, k, i, _, shape in outputs if k == kind and not shape]
            if len(items) < (1 if kind == "Real" else 2):  # one Integer/Boolean: numpy's item
                continue  # assignment (≈ 0.15 µs) is as cheap as a store closure
            store = self._packed_store(block, buf[kind], items, code)
            if store is not None:
                self._stores.append(store)
                packed.update(key for key, _ in items)
        self._rest_out: list[tuple[str, np.ndarray, int, bool]] = []  # key, flat view, i, array
        self._all_out: list[tuple[str, np.ndarray, int, bool]] = []
        #: array outputs: (key, flat view, view of the declared shape, shape)
        self._array_out: list[tuple[str, np.ndarray, np.ndarray, tuple[int, ...]]] = []
        for key, kind, i, size, shape in outputs:
            item = ((key, buf[kind][i:i + size], 0, True) if shape
                    else (key, buf[kind], i, False))
            self._all_out.append(item)
            if shape:
                self._array_out.append((key, item[1], item[1].reshape(shape), tuple(shape)))
            elif key not in packed:
                self._rest_out.append(item)

    def _packed_store(self, block: np.ndarray, arr: np.ndarray, items: list[tuple[str, int]],
                      code: str) -> Callable[[Mapping[str, Any]], None] | None:
        """The store of the scalar outputs ``items`` (key, index in ``arr``) with one
        ``struct.pack`` (format ``code``; see ``__init__``); None when they are not contiguous
        and not Real."""
        keys = [k for k, _ in items]
        get = operator.itemgetter(*keys) if len(keys) > 1 else (lambda o, k=keys[0]: (o[k],))
        idx = _index([i for _, i in items])
        if isinstance(idx, slice):
            item = arr.itemsize
            start = arr.ctypes.data - block.ctypes.data + item * idx.start
            stop = start + item * (idx.stop - idx.start)
            pack, mem = struct.Struct(f"<{len(keys)}{code}").pack, self._mem

            def store(o: Mapping[str, Any]) -> None:
                mem[start:stop] = pack(*get(o))
            return store
        if code != "d":
            return None

        def store_tuple(o: Mapping[str, Any]) -> None:
            arr[idx] = get(o)
        return store_tuple

    def gather(self) -> dict[str, Any]:
        """Input mapping for ``model.step``: scalars as Python ``float``/``int``/``bool``,
        arrays as fresh numpy arrays of their declared shape (the model may keep them).
        Keys: the scalars in memory order (Real, Integer, Boolean), then the arrays."""
        inputs = dict(zip(self._scalar_keys, self._unpack(self._mem)))  # noqa: B905 (strict: +1 µs)
        for key, copy in self._array_in:
            inputs[key] = copy()
        return inputs

    def scatter(self, out: Mapping[str, Any]) -> None:
        """Copy the model's outputs into the value arrays (a missing key → KeyError)."""
        try:
            for store in self._stores:
                store(out)
        except Exception:
            for key, arr, i, is_array in self._all_out:
                if is_array:
                    arr[:] = np.ravel(out[key])
                else:
                    arr[i] = out[key]
            return
        for key, arr, i, _ in self._rest_out:
            arr[i] = out[key]
        for key, flat, view, shape in self._array_out:
            v = out[key]
            if type(v) is np.ndarray and v.shape == shape:
                view[...] = v
            else:
                flat[:] = np.ravel(v)


def make_fast_step(slave: Any, plan: StepPlan, step_th: np.ndarray) -> Callable[[], int]:
    """The callable the C shim calls for ``fmi2DoStep`` (see the module doc): reads
    ``t, h = step_th`` [s], steps ``slave.model`` with :meth:`StepPlan.gather`'s inputs,
    stores the outputs and the time; :data:`FAST_DONE`, or :data:`FAST_FORWARD` with nothing
    done (or the exception kept in ``slave._pending`` for the forwarded ``do_step``)."""
    gather, scatter, th = plan.gather, plan.scatter, step_th.tolist

    def fast_step() -> int:
        model = slave.model
        if slave._failed is not None or model is None or slave._pending is not None:
            return FAST_FORWARD
        try:
            t, h = th()
            scatter(model.step(h, gather()))
            slave._time = t + h
            return FAST_DONE
        except BaseException as e:  # kept: the forwarded do_step raises it
            slave._pending = e
            return FAST_FORWARD

    return fast_step


#: :func:`make_fast_io`'s word layout (the C shim's "fast step I/O"): header
#: [n scalar inputs, n array inputs, n scalar outputs, n array outputs], then per scalar input
#: (kind, byte offset in the block), per scalar output (kind, byte offset), per array output
#: (byte offset, byte count, ndim, shape[0..3]); kinds: 0 Real (float64), 1 Integer (int64),
#: 2 Boolean (one byte)
IO_KINDS = {"Real": 0, "Integer": 1, "Boolean": 2}
IO_MAX_NDIM = 4


def make_fast_io(slave: Any, plan: StepPlan, step_th: np.ndarray,
                 inputs: Sequence[Entry], outputs: Sequence[Entry],
                 buf: Mapping[str, np.ndarray], block: np.ndarray) -> tuple[Any, ...] | None:
    """The fast step with the gather and scatter made by the C shim (issue 14, session 9).

    Returns ``(step, finish, forward, words address, words, input keys, array copies,
    output keys)``; None when an output cannot be described (an array of more than
    :data:`IO_MAX_NDIM` dimensions): the shim then uses :func:`make_fast_step` alone.

    The shim builds the input mapping :meth:`StepPlan.gather` builds (the scalars in memory
    order as Python ``float``/``int``/``bool``, then fresh array copies) and calls
    ``step(inputs)``: the checks and the model step of :func:`make_fast_step`; it answers the
    model's output mapping, or ``forward`` (a sentinel object) when the regular path is needed
    (nothing done, or the model's exception kept in ``slave._pending``). The shim then stores
    the outputs itself when every one has a plain value — a dict holding each scalar output
    key, Real values that ``PyFloat_AsDouble`` converts (what ``struct.pack('d')`` and numpy's
    float64 item assignment store), Integer values of exact type ``int``/``bool`` within int64,
    Boolean values of exact type ``bool``/``int``, arrays exposing a C-contiguous float64
    buffer of the declared shape — converting everything before it stores anything; otherwise
    it calls ``finish(out)``: :meth:`StepPlan.scatter` in Python, which stores or raises
    exactly as before (an exception: kept as pending, the time put back, FAST_FORWARD).
    """
    forward = object()
    gather_keys = plan._scalar_keys
    by_key = {e[0]: e for e in inputs}
    base = block.ctypes.data
    item = {"Real": 8, "Integer": 8, "Boolean": 1}

    def offset(kind: str, i: int) -> int:
        return buf[kind].ctypes.data - base + item[kind] * i

    words: list[int] = []
    in_scalar = [(IO_KINDS[by_key[k][1]], offset(by_key[k][1], by_key[k][2]))
                 for k in gather_keys]
    in_arrays = [(key, copy) for key, copy in plan._array_in]
    out_scalar = [(key, IO_KINDS[kind], offset(kind, i))
                  for key, kind, i, _, shape in outputs if not shape]
    out_arrays = []
    for key, kind, i, size, shape in outputs:
        if not shape:
            continue
        if kind != "Real" or len(shape) > IO_MAX_NDIM:
            return None
        dims = [*shape, *([0] * (IO_MAX_NDIM - len(shape)))]
        out_arrays.append((key, [offset(kind, i), 8 * size, len(shape), *dims]))
    words = [len(in_scalar), len(in_arrays), len(out_scalar), len(out_arrays)]
    for kind, off in in_scalar:
        words += [kind, off]
    for _, kind, off in out_scalar:
        words += [kind, off]
    for _, w in out_arrays:
        words += w
    desc = np.array(words, dtype=np.int64)
    th = step_th.tolist

    def step(inputs: dict[str, Any]) -> Any:
        model = slave.model
        if slave._failed is not None or model is None or slave._pending is not None:
            return forward
        try:
            t, h = th()
            out = model.step(h, inputs)
        except BaseException as e:  # kept: the forwarded do_step raises it
            slave._pending = e
            return forward
        slave._time_before = slave._time
        slave._time = t + h
        return out

    scatter = plan.scatter

    def finish(out: Any) -> int:
        try:
            scatter(out)
            return FAST_DONE
        except BaseException as e:  # as make_fast_step: the forwarded do_step raises it
            slave._time = slave._time_before
            slave._pending = e
            return FAST_FORWARD

    return (step, finish, forward, int(desc.ctypes.data), desc,
            tuple(sys.intern(k) for k in gather_keys) + tuple(k for k, _ in in_arrays),
            tuple(copy for _, copy in in_arrays),
            tuple(sys.intern(k) for k, _, _ in out_scalar) + tuple(k for k, _ in out_arrays))
