"""The recording observer and the results CSV.

:class:`Recorder` observes a :class:`~.master.Master`: every ``decimation`` steps it reads the
chosen variables (grouped per instance and type into ports, a few C calls per sample) into a
growing numpy array. :func:`write_csv` writes ``results.csv`` with time first in the layout of
``fmpy.util.write_csv`` (quoted header), readable by ``fmpy.util.read_csv``; with
:meth:`Recorder.stream_to` the same bytes reach the file while the run goes (rows appended and
flushed at least every ``flush_s`` seconds of wall time), so a killed run keeps its rows.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .errors import AxirError
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
        self._reads: list[tuple[Any, list[int]]] = []
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
        self._reads = [
            (master.instances[u].port([v for _, v in cols]), [c for c, _ in cols])
            for (u, _), cols in groups.items()
        ]
        self._data = np.empty((1024, 1 + len(self.variables)))
        self.n = 0
        if self._stream is not None:
            self._stream.open(self)
        self._sample(master.t_ns)

    def _sample(self, t_ns: int) -> None:
        if self.n == len(self._data):
            self._data = np.concatenate([self._data, np.empty_like(self._data)])
        row = self._data[self.n]
        row[0] = t_ns / NS
        for port, cols in self._reads:
            row[cols] = port.read()
        self.n += 1
        if self._stream is not None:
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


def _fmt(kind: str) -> Callable[[float], str]:
    if kind in ("Integer", "Boolean"):
        return lambda v: str(int(v))
    return lambda v: repr(float(v))


def _header(rec: Recorder) -> str:
    return ",".join(f'"{n}"' for n in ["time", *rec.variables]) + "\n"


def _rows(rec: Recorder, start: int, stop: int) -> str:
    """Rows ``start:stop`` of the recording as CSV lines."""
    fmts = [_fmt("Real")] + [_fmt(rec.types.get(v, "Real")) for v in rec.variables]
    return "".join(",".join(fmt(v) for fmt, v in zip(fmts, row, strict=True)) + "\n"
                   for row in rec.data[start:stop])


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

    def __init__(self, path: Path, flush_s: float) -> None:
        self.path = path
        self.flush_s = float(flush_s)
        self._fd: int | None = None
        self._written = 0
        self._last = 0.0

    def open(self, rec: Recorder) -> None:
        self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        self._written = 0
        self._write(_header(rec))
        self._last = time.monotonic()

    def _write(self, text: str) -> None:
        data = text.encode("utf-8")
        while data:
            n = os.write(self._fd, data)
            data = data[n:]

    def maybe_flush(self, rec: Recorder) -> None:
        if rec.n - self._written >= self.MAX_ROWS or time.monotonic() - self._last >= self.flush_s:
            self.flush(rec)

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
