"""The process that turns a recording's rows into ``results.csv`` text while the run steps.

Started by :class:`~.record._CsvStream` as ``python -m axir.orchestrator.csv_writer PATH FORMAT
NCOLS`` in its own session: it reads rows as raw native float64 values (``NCOLS`` per row) from
its standard input, formats each block with ``FORMAT`` (one line's %-format: ``%r`` and ``%d``
fields, :func:`~.record._row_format`; the text :func:`~.record._rows` makes) and appends whole
lines to ``PATH`` (which already holds the header) with one ``os.write`` per block. It ends at
the end of its input — the run closed the pipe, or the run's process died (even by SIGKILL):
the rows it received are then still written. SIGINT, SIGTERM and SIGHUP are ignored (the run
decides when recording ends). Exit status 0: every row written; 1: input ending inside a row;
2: bad arguments. Nothing read is executed: the input is numbers only.

Why a process: the text of a float (``repr``: CPython's shortest round-trip digits) costs
≈ 0.7 µs per value, ≈ 15 µs per row of the default 24 variables, i.e. about a seventh of a
PRI step; here it runs beside the stepping loop instead of inside it.
"""

from __future__ import annotations

import os
import re
import signal
import sys
from array import array

#: one CSV line's format: %r / %d fields separated by commas, then a newline
_FORMAT = re.compile(r"%[rd](,%[rd])*\n")


def _write_all(fd: int, data: bytes) -> None:
    while data:
        n = os.write(fd, data)
        data = data[n:]


def main(argv: list[str]) -> int:
    """Run the writer (see the module doc); returns the exit status."""
    for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, signal.SIG_IGN)
    if len(argv) != 4 or not _FORMAT.fullmatch(argv[2]) or not argv[3].isdigit() or \
            argv[2].count("%") != int(argv[3]):
        print("csv_writer: usage: PATH FORMAT NCOLS (FORMAT: NCOLS %r/%d fields)",
              file=sys.stderr)
        return 2
    path, fmt, ncols = argv[1], argv[2], int(argv[3])
    row_bytes = 8 * ncols
    fd = os.open(path, os.O_WRONLY | os.O_APPEND)
    pending = b""
    try:
        while True:
            chunk = os.read(0, 1 << 20)
            if not chunk:
                break
            pending += chunk
            whole = len(pending) // row_bytes * row_bytes
            if not whole:
                continue
            values = array("d")
            values.frombytes(pending[:whole])
            pending = pending[whole:]
            _write_all(fd, ((fmt * (whole // row_bytes)) % tuple(values.tolist()))
                       .encode("utf-8"))
    finally:
        os.close(fd)
    return 1 if pending else 0


if __name__ == "__main__":  # pragma: no cover - run as a process
    sys.exit(main(sys.argv))
