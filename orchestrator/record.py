"""The recording observer and the results CSV.

:class:`Recorder` observes a :class:`~.master.Master`: every ``decimation`` steps it reads the
chosen variables (grouped per instance and type into ports, a few C calls per sample) into a
growing numpy array. :func:`write_csv` writes ``results.csv`` with time first in the layout of
``fmpy.util.write_csv`` (quoted header), readable by ``fmpy.util.read_csv``.
"""

from __future__ import annotations

from collections.abc import Sequence
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
        self._sample(master.t_ns)

    def _sample(self, t_ns: int) -> None:
        if self.n == len(self._data):
            self._data = np.concatenate([self._data, np.empty_like(self._data)])
        row = self._data[self.n]
        row[0] = t_ns / NS
        for port, cols in self._reads:
            row[cols] = port.read()
        self.n += 1

    def step(self, master: Master, t_ns: int) -> None:
        if master.steps % self.decimation == 0:
            self._sample(t_ns)

    def finish(self, master: Master, complete: bool) -> None:
        if self.n and self._data[self.n - 1, 0] != master.t_ns / NS:
            self._sample(master.t_ns)  # always keep the final state

    def column(self, ref: str) -> np.ndarray | None:
        try:
            return self.data[:, 1 + self.variables.index(ref)]
        except ValueError:
            return None


def _fmt(kind: str):
    if kind in ("Integer", "Boolean"):
        return lambda v: str(int(v))
    return lambda v: repr(float(v))


def write_csv(path: Path, rec: Recorder) -> None:
    """``results.csv``: quoted header ``"time","Unit.var",...``, one row per sample."""
    fmts = [_fmt("Real")] + [_fmt(rec.types.get(v, "Real")) for v in rec.variables]
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(",".join(f'"{n}"' for n in ["time", *rec.variables]) + "\n")
        for row in rec.data:
            f.write(",".join(fmt(v) for fmt, v in zip(fmts, row, strict=True)) + "\n")
