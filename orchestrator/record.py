"""The recording observer and the results CSV.

:class:`Recorder` observes a :class:`~.master.Master`: every ``decimation`` steps it reads the
chosen variables into a growing numpy array: one bound ``fmi2Get*`` call per (instance, type)
straight into a staging vector per C type, and one indexed copy of each staging vector into the
row (≈ 3-5 µs per sample for the default 24 variables, was ≈ 15).
:func:`write_csv` writes ``results.csv`` with time first in the layout of
``fmpy.util.write_csv`` (quoted header), readable by ``fmpy.util.read_csv``; with
:meth:`Recorder.stream_to` the same bytes reach the file while the run goes (rows appended and
flushed at least every ``flush_s`` seconds of wall time), so a killed run keeps its rows.
The text of a value is ``repr(float(v))`` (Real) or ``str(int(v))`` (Integer, Boolean), made by
one %-format per block of rows; that text costs ≈ 0.7 µs per Real value (CPython's
shortest round-trip repr), ≈ 15 µs per row of 24 variables: the largest cost of recording.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .errors import AxirError
from .fmi import _CTYPE, fmi2ValueReference
from .master import NS, Master


class Recorder:
    """Decimated recording of ``Unit.variable`` references."""

    def __init__(self, variables: Sequence[str], decimation: int = 1) -> None:
        if decimation < 1:
            raise AxirError(f"record decimation must be >= 1, got {decimation}")
        self.variables = list(variables)
        self.decimation = int(decimation)
        self._data = np.empty((0, 1 + len(self.variables)))
        self.n = 0
        self._reads: list[Callable[[], Any]] = []
        self._moves: list[tuple[np.ndarray, slice | np.ndarray]] = []
        self.types: dict[str, str] = {}
        self._stream: _CsvStream | None = None

    def stream_to(self, path: Path, flush_s: float = 1.0) -> None:
        """Write ``results.csv`` to ``path`` while recording: the header at :meth:`start`, the
        rows appended at least every ``flush_s`` [s] of wall time (and every 4096 rows), the
        rest at :meth:`finish`. The file's bytes equal :func:`write_csv`'s."""
        self._stream = _CsvStream(Path(path), flush_s)

    @property
    def data(self) -> np.ndarray:
        """Recorded rows: column 0 is time [s], then the variables in order."""
        return self._data[: self.n]

    def start(self, master: Master) -> None:
        groups: dict[tuple[str, str], list[tuple[int, str]]] = {}
        for col, ref in enumerate(self.variables, start=1):
            unit, _, var = ref.partition(".")
            inst = master.instances.get(unit)
            if inst is None:
                raise AxirError(f"record: unknown unit in {ref!r}")
            v = inst.variable(var)
            if v.type not in ("Real", "Integer", "Boolean"):
                raise AxirError(f"record: {ref} is a {v.type}; only numbers can be recorded")
            self.types[ref] = v.type
            groups.setdefault((unit, v.type), []).append((col, var))
        # One staging vector per C type (Real: float64; Integer, Boolean: int32); each
        # (unit, type) group is read with one bound fmi2Get* call straight into its slice, and a
        # sample moves each staging vector into the row with one indexed assignment.
        stages: dict[str, tuple[np.ndarray, list[int]]] = {}
        self._reads = []
        for kind in ("Real", "Int"):
            members = [(u, t, cols) for (u, t), cols in groups.items()
                       if (t == "Real") == (kind == "Real")]
            if not members:
                continue
            n = sum(len(cols) for _, _, cols in members)
            stage = np.zeros(n, dtype=np.float64 if kind == "Real" else np.int32)
            order: list[int] = []
            for u, t, cols in members:
                inst = master.instances[u]
                vars_ = [inst.variable(v) for _, v in cols]
                m = len(vars_)
                vr = (fmi2ValueReference * m)(*[v.valueReference for v in vars_])
                buf = (_CTYPE[t] * m).from_buffer(stage, 4 * len(order) if kind != "Real"
                                                  else 8 * len(order))
                self._reads.append(inst.bind(f"fmi2Get{t}", vr, m, buf))
                order.extend(c for c, _ in cols)
            stages[kind] = (stage, order)
        self._moves = [(stage, _index(order)) for stage, order in stages.values()]
        self._data = np.empty((1024, 1 + len(self.variables)))
        self.n = 0
        if self._stream is not None:
            self._stream.open(self)
        self._sample(master.t_ns)

    def _sample(self, t_ns: int) -> None:
        if self.n == len(self._data):
            self._data = np.concatenate([self._data, np.empty_like(self._data)])
        for read in self._reads:
            read()
        row = self._data[self.n]
        row[0] = t_ns / NS
        for stage, cols in self._moves:
            row[cols] = stage
        self.n += 1
        if self._stream is not None and self.n >= self._stream.next_check:
            self._stream.maybe_flush(self)

    def step(self, master: Master, t_ns: int) -> None:
        if master.steps % self.decimation == 0:
            self._sample(t_ns)

    def finish(self, master: Master, complete: bool) -> None:
        if self.n and self._data[self.n - 1, 0] != master.t_ns / NS:
            self._sample(master.t_ns)  # always keep the final state
        if self._stream is not None:
            self._stream.close(self)

    def column(self, ref: str) -> np.ndarray | None:
        try:
            return self.data[:, 1 + self.variables.index(ref)]
        except ValueError:
            return None


def _index(cols: list[int]) -> slice | np.ndarray:
    """Row positions ``cols`` as a slice when they are consecutive, else an index array."""
    if cols == list(range(cols[0], cols[0] + len(cols))):
        return slice(cols[0], cols[0] + len(cols))
    return np.array(cols, dtype=np.intp)


def _row_format(rec: Recorder) -> str:
    """The %-format of one CSV line: ``%r`` (``repr`` of the float: shortest round-trip) for
    time and Real columns, ``%d`` (``str(int(v))``) for Integer and Boolean columns."""
    kinds = [rec.types.get(v, "Real") for v in rec.variables]
    return ",".join(["%r"] + ["%d" if k in ("Integer", "Boolean") else "%r"
                              for k in kinds]) + "\n"


def _header(rec: Recorder) -> str:
    return ",".join(f'"{n}"' for n in ["time", *rec.variables]) + "\n"


def _rows(rec: Recorder, start: int, stop: int) -> str:
    """Rows ``start:stop`` of the recording as CSV lines (one %-format over the block's values
    as Python floats: the text ``repr(float(v))`` / ``str(int(v))`` per value gives)."""
    block = rec.data[start:stop]
    if not len(block):
        return ""
    return (_row_format(rec) * len(block)) % tuple(block.ravel().tolist())


def write_csv(path: Path, rec: Recorder) -> None:
    """``results.csv``: quoted header ``"time","Unit.var",...``, one row per sample."""
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(_header(rec))
        f.write(_rows(rec, 0, rec.n))


class _CsvStream:
    """``results.csv`` written while recording: whole lines appended with one ``os.write``
    each flush (a kill between flushes loses only the unflushed rows, never half a line
    except when killed inside that one write call)."""

    #: rows buffered at most between flushes (bounded memory of the pending text)
    MAX_ROWS = 4096
    #: samples between two looks at the clock (≈ 6 ms of an 100 µs/step run: flushes stay
    #: within ``flush_s`` + a few ms)
    CHECK_ROWS = 64

    def __init__(self, path: Path, flush_s: float) -> None:
        self.path = path
        self.flush_s = float(flush_s)
        self._fd: int | None = None
        self._written = 0
        self._last = 0.0
        #: the sample count at which the recorder next calls :meth:`maybe_flush`
        self.next_check = 0

    def open(self, rec: Recorder) -> None:
        self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        self._written = 0
        self._write(_header(rec))
        self._last = time.monotonic()
        self.next_check = rec.n + 1

    def _write(self, text: str) -> None:
        data = text.encode("utf-8")
        while data:
            n = os.write(self._fd, data)
            data = data[n:]

    def maybe_flush(self, rec: Recorder) -> None:
        """Flush if ``MAX_ROWS`` rows are pending or ``flush_s`` passed since the last flush;
        the recorder calls this when ``rec.n`` reaches ``next_check`` (the clock is read every
        ``CHECK_ROWS`` samples, not every sample)."""
        if rec.n - self._written >= self.MAX_ROWS or time.monotonic() - self._last >= self.flush_s:
            self.flush(rec)
        self.next_check = min(rec.n + self.CHECK_ROWS, self._written + self.MAX_ROWS)

    def flush(self, rec: Recorder) -> None:
        if self._fd is None:
            return
        if rec.n > self._written:
            self._write(_rows(rec, self._written, rec.n))
            self._written = rec.n
        self._last = time.monotonic()

    def close(self, rec: Recorder) -> None:
        if self._fd is not None:
            self.flush(rec)
            os.close(self._fd)
            self._fd = None
