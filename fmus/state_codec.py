"""Data-only, versioned serialisation of an axir FMU state (``fmi2SerializeFMUstate``).

FMI hosts treat a serialised FMU state as *data*: it may come from a file or a network. This
codec therefore never uses pickle, ``eval`` or an import by a name read from the data; decoding
a foreign or malformed byte string raises :class:`StateFormatError` and runs no code of the
data's choosing.

Layout (all integers little-endian)::

    MAGIC (13 bytes "AXIRFMUSTATE\\n") | version u32 | header length u32 | header (UTF-8 JSON)
    | array buffers (raw little-endian bytes, concatenated in the order of ``"buffers"``)

The JSON header is ``{"model": modelIdentifier, "bundle": bundle hash or null, "buffers":
[byte length, ...], "tree": <node>}``. A node is a JSON ``null``, ``true``/``false``, string,
integer (arbitrary size), finite float, or a tagged object ``{"$": tag, ...}``:

============  ==========================================================================
tag           value
============  ==========================================================================
``float``     ``{"v": "nan" | "inf" | "-inf"}`` (non-finite floats; finite ones are JSON)
``complex``   ``{"re": node, "im": node}``
``tuple``     ``{"v": [node, ...]}``
``list``      ``{"id": n, "v": [node, ...]}``
``dict``      ``{"id": n, "k": [node, ...], "v": [node, ...]}`` (keys: str/int/float/bool/
              None/tuple)
``deque``     ``{"id": n, "maxlen": int | null, "v": [node, ...]}``
``nd``        ``{"id": n, "dtype": "<f8", "shape": [..], "buf": i}`` numpy array (numeric
              dtypes of :data:`DTYPES` only; the bytes are buffer ``i``)
``np``        ``{"dtype": "<f8", "buf": i}`` numpy scalar
``rng``       ``{"id": n, "bitgen": "PCG64", "state": node}`` ``numpy.random.Generator``
              (bit generators of :data:`BIT_GENERATORS`; numpy validates the state dict)
``obj``       ``{"id": n, "cls": "models.filters.svd:SVDFilter", "d": dict node}``
``ref``       ``{"id": n}``: the object with that id, already decoded (shared references)
============  ==========================================================================

Objects (``obj``) are rebuilt only for classes of the allow-list: the classes *defined* in the
project's own ``models`` package modules that are already loaded (``<package>.models.*`` in
``sys.modules``; nothing is imported). They are created with ``object.__new__`` (only for
classes without their own ``__new__``: no constructor code runs) and their ``__dict__`` is
filled with the decoded fields. ``id`` values must appear in increasing order from 0 (the
order of first appearance); a ``ref`` may only name an object decoded before it.

Every numeric type keeps its exact type and bits (Python float vs numpy float64, array dtypes,
-0.0, big integers of the PCG64 state), so a get/serialise/deserialise/set round trip is
bit-identical. Relative imports only (bundled into every FMU).
"""

from __future__ import annotations

import json
import math
import struct
import sys
from collections import deque
from typing import Any

import numpy as np

MAGIC = b"AXIRFMUSTATE\n"
VERSION = 2  # version 1 was "AXIRFMUSTATE1\n" + pickle: refused
#: numpy dtypes an array or scalar of the state may have (numeric only, never object).
DTYPES = frozenset(
    np.dtype(t).newbyteorder("<").str if np.dtype(t).itemsize > 1 else np.dtype(t).str
    for t in ("?", "i1", "i2", "i4", "i8", "u1", "u2", "u4", "u8", "f4", "f8", "c8", "c16"))
#: bit generators a ``numpy.random.Generator`` of the state may use.
BIT_GENERATORS: dict[str, type] = {
    c.__name__: c for c in (np.random.PCG64, np.random.PCG64DXSM, np.random.MT19937,
                            np.random.Philox, np.random.SFC64)}
_MAX_DEPTH = 200
_MAX_HEADER = 1 << 30


class StateFormatError(ValueError):
    """A byte string is not a valid axir FMU state of this FMU (message says why)."""


def _package_root() -> str:
    """``axir`` or the bundled ``_axir_<hash>``: the package this module belongs to."""
    return (__package__ or "").rpartition(".")[0]


def state_classes(root: str | None = None) -> dict[str, type]:
    """Allow-list of the classes an ``obj`` node may name: ``"models.x.y:Class"`` → class, for
    each class defined in a loaded module ``<root>.models.*`` (no import happens here)."""
    root = _package_root() if root is None else root
    head = root + ".models."
    out: dict[str, type] = {}
    # dict.copy() copies without allocating Python objects: no GC, no __del__, no thread
    # switch in between. list(d.items()) allocates a tuple per item; a collection there may
    # run a finaliser that lets another thread (a Dask worker's event loop) import a module,
    # and the iteration fails with 'dictionary changed size during iteration'.
    for name, mod in sys.modules.copy().items():
        if mod is None or not name.startswith(head):
            continue
        for v in vars(mod).copy().values():
            if isinstance(v, type) and v.__module__ == name and v.__new__ is object.__new__:
                out[f"{name[len(root) + 1:]}:{v.__qualname__}"] = v
    return out


def _dtype_str(dt: np.dtype) -> str:
    s = dt.newbyteorder("<").str if dt.itemsize > 1 else dt.str
    if s not in DTYPES:
        raise StateFormatError(f"dtype {dt} cannot be serialised")
    return s


class _Encoder:
    def __init__(self, root: str) -> None:
        self.root = root
        self.buffers: list[bytes] = []
        self.ids: dict[int, int] = {}
        self.keep: list[Any] = []  # keeps encoded objects alive (id() stays unique)

    def _new_id(self, x: Any) -> int:
        n = len(self.ids)
        self.ids[id(x)] = n
        self.keep.append(x)
        return n

    def _buf(self, a: np.ndarray) -> int:
        self.buffers.append(np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<")).tobytes())
        return len(self.buffers) - 1

    def enc(self, x: Any, depth: int = 0) -> Any:
        if depth > _MAX_DEPTH:
            raise StateFormatError("state nested too deeply")
        t = type(x)
        if x is None or t is bool or t is str or t is int:
            return x
        if t is float:
            return x if math.isfinite(x) else {"$": "float", "v": repr(x)}
        if t is complex:
            return {"$": "complex", "re": self.enc(x.real), "im": self.enc(x.imag)}
        if t is tuple:
            return {"$": "tuple", "v": [self.enc(v, depth + 1) for v in x]}
        if isinstance(x, np.generic):
            a = np.asarray(x)
            return {"$": "np", "dtype": _dtype_str(a.dtype), "buf": self._buf(a.reshape(1))}
        if id(x) in self.ids:
            return {"$": "ref", "id": self.ids[id(x)]}
        if t is list:
            n = self._new_id(x)
            return {"$": "list", "id": n, "v": [self.enc(v, depth + 1) for v in x]}
        if t is dict:
            n = self._new_id(x)
            return {"$": "dict", "id": n, "k": [self.enc(k, depth + 1) for k in x],
                    "v": [self.enc(v, depth + 1) for v in x.values()]}
        if t is deque:
            n = self._new_id(x)
            return {"$": "deque", "id": n, "maxlen": x.maxlen,
                    "v": [self.enc(v, depth + 1) for v in x]}
        if t is np.ndarray:
            n = self._new_id(x)
            return {"$": "nd", "id": n, "dtype": _dtype_str(x.dtype), "shape": list(x.shape),
                    "buf": self._buf(x)}
        if t is np.random.Generator:
            bg = type(x.bit_generator)
            if BIT_GENERATORS.get(bg.__name__) is not bg:
                raise StateFormatError(f"bit generator {bg.__name__} cannot be serialised")
            n = self._new_id(x)
            return {"$": "rng", "id": n, "bitgen": bg.__name__,
                    "state": self.enc(x.bit_generator.state, depth + 1)}
        mod = t.__module__
        if mod.startswith(self.root + ".models.") and hasattr(x, "__dict__"):
            key = f"{mod[len(self.root) + 1:]}:{t.__qualname__}"
            n = self._new_id(x)
            return {"$": "obj", "id": n, "cls": key, "d": self.enc(dict(vars(x)), depth + 1)}
        raise StateFormatError(f"a value of type {mod}.{t.__qualname__} cannot be serialised")


class _Decoder:
    def __init__(self, buffers: list[memoryview], classes: dict[str, type]) -> None:
        self.buffers = buffers
        self.classes = classes
        self.objs: list[Any] = []

    def _register(self, node: dict[str, Any], x: Any) -> None:
        if node.get("id") != len(self.objs) or type(node.get("id")) is not int:
            raise StateFormatError(f"object id {node.get('id')!r} out of order")
        self.objs.append(x)

    def _array(self, dtype: Any, shape: Any, i: Any) -> np.ndarray:
        if type(dtype) is not str or dtype not in DTYPES:
            raise StateFormatError(f"dtype {dtype!r} not allowed")
        if (type(shape) is not list or len(shape) > 32
                or not all(type(s) is int and s >= 0 for s in shape)):
            raise StateFormatError(f"bad array shape {shape!r}")
        if type(i) is not int or not 0 <= i < len(self.buffers):
            raise StateFormatError(f"bad buffer index {i!r}")
        dt = np.dtype(dtype)
        raw = self.buffers[i]
        if len(raw) != dt.itemsize * math.prod(shape):
            raise StateFormatError(f"buffer {i}: {len(raw)} bytes for {dtype}{shape}")
        a = np.frombuffer(raw, dtype=dt).reshape(shape)
        return a.astype(dt.newbyteorder("="))  # native byte order, a writable copy

    def _items(self, v: Any, depth: int) -> list[Any]:
        if type(v) is not list:
            raise StateFormatError("expected a list of nodes")
        return [self.dec(x, depth + 1) for x in v]

    def dec(self, node: Any, depth: int = 0) -> Any:
        if depth > _MAX_DEPTH:
            raise StateFormatError("state nested too deeply")
        t = type(node)
        if node is None or t is bool or t is str or t is int:
            return node
        if t is float:
            if not math.isfinite(node):
                raise StateFormatError("non-finite float outside a float node")
            return node
        if t is not dict:
            raise StateFormatError(f"unexpected JSON value of type {t.__name__}")
        tag = node.get("$")
        if tag == "float":
            v = node.get("v")
            if v not in ("nan", "inf", "-inf"):
                raise StateFormatError(f"bad float node {v!r}")
            return float(v)
        if tag == "complex":
            re, im = self.dec(node.get("re"), depth + 1), self.dec(node.get("im"), depth + 1)
            if type(re) is not float or type(im) is not float:
                raise StateFormatError("bad complex node")
            return complex(re, im)
        if tag == "tuple":
            return tuple(self._items(node.get("v"), depth))
        if tag == "ref":
            n = node.get("id")
            if type(n) is not int or not 0 <= n < len(self.objs):
                raise StateFormatError(f"reference to unknown object {n!r}")
            return self.objs[n]
        if tag == "np":
            return self._array(node.get("dtype"), [1], node.get("buf"))[0]
        if tag == "list":
            out: list[Any] = []
            self._register(node, out)
            out.extend(self._items(node.get("v"), depth))
            return out
        if tag == "dict":
            d: dict[Any, Any] = {}
            self._register(node, d)
            keys, vals = self._items(node.get("k"), depth), self._items(node.get("v"), depth)
            if len(keys) != len(vals):
                raise StateFormatError("dict node: keys and values differ in number")
            for k, v in zip(keys, vals, strict=True):
                if type(k) not in (str, int, float, bool, tuple) and k is not None:
                    raise StateFormatError(f"dict key of type {type(k).__name__}")
                d[k] = v
            return d
        if tag == "deque":
            maxlen = node.get("maxlen")
            if maxlen is not None and (type(maxlen) is not int or maxlen < 0):
                raise StateFormatError(f"bad deque maxlen {maxlen!r}")
            q: deque[Any] = deque(maxlen=maxlen)
            self._register(node, q)
            q.extend(self._items(node.get("v"), depth))
            return q
        if tag == "nd":
            a = self._array(node.get("dtype"), node.get("shape"), node.get("buf"))
            self._register(node, a)
            return a
        if tag == "rng":
            bg = BIT_GENERATORS.get(node.get("bitgen"))  # type: ignore[arg-type]
            if bg is None:
                raise StateFormatError(f"bit generator {node.get('bitgen')!r} not allowed")
            g = np.random.Generator(bg())
            self._register(node, g)
            st = self.dec(node.get("state"), depth + 1)
            if type(st) is not dict:
                raise StateFormatError("bad generator state")
            try:
                g.bit_generator.state = st
            except (TypeError, ValueError, KeyError, OverflowError) as e:
                raise StateFormatError(f"bad generator state: {e}") from None
            return g
        if tag == "obj":
            key = node.get("cls")
            cls = self.classes.get(key) if type(key) is str else None
            if cls is None:
                raise StateFormatError(f"class {key!r} is not one of the model's classes")
            obj = object.__new__(cls)
            self._register(node, obj)
            fields = self.dec(node.get("d"), depth + 1)
            if type(fields) is not dict or not all(type(k) is str for k in fields):
                raise StateFormatError(f"bad fields of {key}")
            obj.__dict__.update(fields)
            return obj
        raise StateFormatError(f"unknown node tag {tag!r}")


def encode_state(tree: Any, model: str, bundle: str | None, root: str | None = None) -> bytes:
    """Serialise ``tree`` (the slave's state dict) for FMU ``model`` of build ``bundle``.

    Raises :class:`StateFormatError` for a value the format cannot hold.
    """
    enc = _Encoder(_package_root() if root is None else root)
    body = enc.enc(tree)
    header = json.dumps({"model": model, "bundle": bundle,
                         "buffers": [len(b) for b in enc.buffers], "tree": body},
                        allow_nan=False, separators=(",", ":")).encode("utf-8")
    return b"".join([MAGIC, struct.pack("<II", VERSION, len(header)), header, *enc.buffers])


def decode_state(data: bytes, model: str, bundle: str | None,
                 root: str | None = None) -> Any:
    """Inverse of :func:`encode_state`; a state of another format version, FMU (model
    identifier) or build (bundle hash), or any malformed byte string raises
    :class:`StateFormatError`."""
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise StateFormatError("not bytes")
    data = bytes(data)
    if not data.startswith(MAGIC):
        raise StateFormatError("not an axir FMU state (no AXIRFMUSTATE header"
                               + ("; format 1 (pickle) is no longer accepted)"
                                  if data.startswith(b"AXIRFMUSTATE1\n") else ")"))
    p = len(MAGIC)
    if len(data) < p + 8:
        raise StateFormatError("truncated header")
    version, n = struct.unpack_from("<II", data, p)
    if version != VERSION:
        raise StateFormatError(f"state format version {version}, this FMU reads {VERSION}")
    p += 8
    if n > _MAX_HEADER or p + n > len(data):
        raise StateFormatError("truncated header")
    try:
        header = json.loads(data[p:p + n].decode("utf-8"),
                            parse_constant=_refuse_constant)
    except (UnicodeDecodeError, ValueError, RecursionError) as e:
        raise StateFormatError(f"header is not valid JSON: {e}") from None
    if type(header) is not dict or set(header) != {"model", "bundle", "buffers", "tree"}:
        raise StateFormatError("header fields are not model, bundle, buffers, tree")
    if header["model"] != model:
        raise StateFormatError(f"state of FMU {str(header['model'])[:40]!r}, not {model!r}")
    if header["bundle"] != bundle:
        raise StateFormatError(f"state from another build ({str(header['bundle'])[:12]}, this "
                               f"FMU {str(bundle)[:12]})")
    sizes = header["buffers"]
    if type(sizes) is not list or not all(type(s) is int and s >= 0 for s in sizes):
        raise StateFormatError("bad buffer table")
    p += n
    if p + sum(sizes) != len(data):
        raise StateFormatError(f"{len(data) - p} bytes of buffers, table says {sum(sizes)}")
    view = memoryview(data)
    buffers = []
    for s in sizes:
        buffers.append(view[p:p + s])
        p += s
    root = _package_root() if root is None else root
    try:
        return _Decoder(buffers, state_classes(root)).dec(header["tree"])
    except RecursionError:
        raise StateFormatError("state nested too deeply") from None


def _refuse_constant(name: str) -> Any:
    raise StateFormatError(f"JSON constant {name} not allowed")
