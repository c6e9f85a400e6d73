"""The values of an axir FMU instance in one block of memory shared with the C shim.

The runtime slave (:mod:`.slave`) keeps every variable's value in the typed arrays of a
:class:`SharedBlock` (views into ONE numpy byte array) and hands the block to the C shim
(``fmus/shim/axir_fmi2_shim.c``, section "shared values") when it is constructed. The shim then
serves ``fmi2Get{Real,Integer,Boolean}`` and ``fmi2Set{Real,Integer,Boolean}`` from the block
without entering Python; only ``fmi2DoStep`` (and the rare calls) reach the slave. Calls the
shim does not serve (a wrong value reference, a variable not settable now, Strings) go
through pythonfmu to the slave's own get/set, which work on the same arrays: both paths see
and change the same values. The layout (little-endian 64-bit header words, then the
arrays) is the C side's; :data:`HEADER_FIELDS` names the words in order.

Hand-over: ``sys._axir_shared[threading.get_ident()] = (address, block, fast step, fast
step I/O)``; the shim
takes the entry out in the same thread right after pythonfmu's ``fmi2Instantiate``/``fmi2Reset``
returned and keeps a reference to the block and the fast step until ``fmi2FreeInstance``.
Without the shim (the plain pythonfmu binary, win64, a slave built in a test) the entry stays
until the next slave of the same thread replaces it: one block per thread, nothing else
happens.

Bundled into every FMU: relative imports only (this module imports none).
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

MAGIC = int.from_bytes(b"AXIRSHM1", "little")
VERSION = 3
HEADER_FIELDS = ("magic", "version", "n_vars", "kind", "index", "flags", "real", "n_real",
                 "integer", "n_integer", "boolean", "n_boolean", "ctl", "name_offset", "names",
                 "size", "screen_real_n", "screen_real_pos", "screen_real_lo", "screen_real_hi",
                 "screen_real_held", "screen_integer_n", "screen_integer_pos",
                 "screen_integer_lo", "screen_integer_hi", "screen_integer_held", "step")
KIND_CODE = {"Real": 0, "Integer": 1, "Boolean": 2, "String": 3}
SETTABLE_INIT, SETTABLE_RUN, TUNABLE = 1, 2, 4  # flag bits per variable
CTL_INITIALIZED, CTL_DIRTY, CTL_SCREENED = 0, 1, 2  # words of ``ctl``
HANDOVER_ATTR = "_axir_shared"  # sys.<this>: {thread ident: (address, block, ...)}


def _align(n: int, a: int) -> int:
    return (n + a - 1) // a * a


class SharedBlock:
    """The typed value arrays of one slave instance, laid out in one byte block.

    ``kinds[vr]``, ``index[vr]`` (position in its type's array), ``flags[vr]`` and ``names[vr]``
    describe value reference ``vr``; ``starts`` holds the start values per type; ``screens``
    per type (Real, Integer) the inputs' positions in that type's array and their closed
    domain bounds (lo, hi), which the shim checks before each doStep. Attributes: ``real``
    (float64), ``integer`` (int64), ``boolean`` (bool), ``ctl`` (int64 words: initialized,
    dirty, screened), ``step`` (float64: t, h written by the shim before it calls the fast
    step), ``held[type]`` (the last valid input values) — views that stay valid
    as long as the block lives (never reassign them: copy into them).
    """

    def __init__(self, kinds: Sequence[str], index: Sequence[int], flags: Sequence[int],
                 names: Sequence[str], starts: dict[str, Sequence[Any]],
                 screens: dict[str, tuple[Any, Any, Any]] | None = None) -> None:
        n = len(kinds)
        counts = {k: len(starts.get(k, ())) for k in ("Real", "Integer", "Boolean")}
        screens = screens or {}
        ns = {k: len(screens[k][0]) if k in screens else 0 for k in ("Real", "Integer")}
        text = [x.encode("utf-8", "replace").replace(b"\0", b"?") + b"\0" for x in names]
        name_off = np.zeros(n, dtype=np.int32)
        pos = 0
        for i, b in enumerate(text):
            name_off[i] = pos
            pos += len(b)
        name_bytes = b"".join(text) or b"\0"
        off: dict[str, int] = {}
        cur = 8 * len(HEADER_FIELDS)
        for field, size, align in (("kind", n, 1), ("index", 4 * n, 4), ("flags", n, 1),
                                   ("real", 8 * counts["Real"], 8),
                                   ("integer", 8 * counts["Integer"], 8),
                                   ("boolean", counts["Boolean"], 1), ("ctl", 24, 8),
                                   ("screen_real_pos", 4 * ns["Real"], 4),
                                   ("screen_real_lo", 8 * ns["Real"], 8),
                                   ("screen_real_hi", 8 * ns["Real"], 8),
                                   ("screen_real_held", 8 * ns["Real"], 8),
                                   ("screen_integer_pos", 4 * ns["Integer"], 4),
                                   ("screen_integer_lo", 8 * ns["Integer"], 8),
                                   ("screen_integer_hi", 8 * ns["Integer"], 8),
                                   ("screen_integer_held", 8 * ns["Integer"], 8),
                                   ("step", 16, 8),
                                   ("name_offset", 4 * n, 4), ("names", len(name_bytes), 1)):
            cur = _align(cur, align)
            off[field] = cur
            cur += size
        self.block = np.zeros(cur, dtype=np.uint8)
        if self.block.ctypes.data % 8:  # numpy allocates aligned memory; checked anyway
            raise MemoryError("shared value block is not 8-byte aligned")
        b = self.block
        header = {"magic": MAGIC, "version": VERSION, "n_vars": n, "n_real": counts["Real"],
                  "n_integer": counts["Integer"], "n_boolean": counts["Boolean"], "size": cur,
                  "screen_real_n": ns["Real"], "screen_integer_n": ns["Integer"], **off}
        b[:8 * len(HEADER_FIELDS)].view("<u8")[:] = [header[f] for f in HEADER_FIELDS]
        b[off["kind"]:off["kind"] + n] = [KIND_CODE[k] for k in kinds]
        b[off["index"]:off["index"] + 4 * n].view(np.int32)[:] = index
        b[off["flags"]:off["flags"] + n] = flags
        b[off["name_offset"]:off["name_offset"] + 4 * n].view(np.int32)[:] = name_off
        b[off["names"]:] = np.frombuffer(name_bytes, dtype=np.uint8)
        self.real = b[off["real"]:off["real"] + 8 * counts["Real"]].view(np.float64)
        self.integer = b[off["integer"]:off["integer"] + 8 * counts["Integer"]].view(np.int64)
        self.boolean = b[off["boolean"]:off["boolean"] + counts["Boolean"]].view(np.bool_)
        self.ctl = b[off["ctl"]:off["ctl"] + 24].view(np.int64)
        self.step = b[off["step"]:off["step"] + 16].view(np.float64)  # t, h of the fast step
        self.held: dict[str, np.ndarray] = {}
        for kind, key, dt in (("Real", "real", np.float64), ("Integer", "integer", np.int64)):
            m = ns[kind]

            def part(name: str, size: int, t: Any, m: int = m, key: str = key) -> np.ndarray:
                o = off[f"screen_{key}_{name}"]
                return b[o:o + size * m].view(t)

            self.held[kind] = part("held", 8, dt)
            if m:
                pos, lo, hi = screens[kind]
                part("pos", 4, np.int32)[:] = pos
                part("lo", 8, dt)[:] = lo
                part("hi", 8, dt)[:] = hi
        self.real[:] = starts.get("Real", ())
        self.integer[:] = starts.get("Integer", ())
        self.boolean[:] = starts.get("Boolean", ())

    def hand_over(self, usable: bool = True, fast_step: Callable[[], int] | None = None,
                  fast_io: tuple[Any, ...] | None = None) -> None:
        """Offer the block to the C shim of this thread's current fmi2Instantiate/fmi2Reset;
        ``usable=False`` offers none (address 0: the shim forwards every call to the slave,
        e.g. so that a message the slave logged at construction is delivered by the next
        call, as pythonfmu does). ``fast_step``: the callable the shim calls for fmi2DoStep
        instead of pythonfmu's bridge (:mod:`.step_plan`; it reads t, h from ``step``);
        ``fast_io``: :func:`.step_plan.make_fast_io`'s tuple, with which the shim gathers the
        inputs and scatters the outputs of the fast step itself (None: the fast step does)."""
        slots = sys.__dict__.setdefault(HANDOVER_ATTR, {})
        if type(slots) is dict:
            slots[threading.get_ident()] = ((int(self.block.ctypes.data), self.block, fast_step,
                                             fast_io) if usable else (0, None, None))
