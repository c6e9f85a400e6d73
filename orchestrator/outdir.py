"""Output folders: one run at a time, never the files of two runs mixed, JSON written atomically.

Policy (README "Output folders"):

- :func:`claim` creates the folder (checking before the run that it can be written: a clear
  one-line :class:`AxirError` for ``--out afile/sub`` or a read-only folder), then takes an
  exclusive ``fcntl.flock`` on ``<folder>/.axir.lock`` for the whole run. A second run into
  the same folder is refused (exit 2) while the first holds the lock; the lock is released
  by the kernel when the process ends, whatever the way (even SIGKILL), so a stale lock
  file never blocks a later run.
- A folder is reused only if it holds nothing but the files an axir run writes there
  (``owned`` names and patterns, the lock file, temp files of an atomic write); those are
  deleted first, so a folder never mixes two runs' results (e.g. the PNGs of an earlier
  ``--plot`` run). Subfolders that are themselves results folders (holding a lock file, a
  ``summary.json`` or a ``campaign.json``, e.g. ``out/montecarlo``) are left alone. A folder
  holding anything else is refused (naming one foreign entry): choose a new or empty folder.
- :func:`write_json_atomic` writes a temp file in the same folder and renames it over the
  target: a reader sees the old or the new file, never half of one.
"""

from __future__ import annotations

import contextlib
import errno
import fnmatch
import json
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from .errors import AxirError

LOCK_NAME = ".axir.lock"
#: prefix of the temp files of :func:`write_json_atomic` (cleared with the folder)
TMP_PREFIX = ".axir-tmp-"


def _problem(path: Path, e: OSError) -> str:
    """One line on why ``path`` cannot be used as an output folder."""
    if e.errno in (errno.ENOTDIR, errno.EEXIST):
        p = path
        while p != p.parent and not p.exists():
            p = p.parent
        if p.exists() and not p.is_dir():
            return f"output folder {path}: {p} is a file, not a folder"
    if e.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        return f"output folder {path}: not writable ({e.strerror})"
    return f"output folder {path}: {e.strerror or e}"


#: a subfolder holding one of these is another run's output folder (e.g. out/montecarlo
#: inside out/): left alone, neither cleared nor foreign
_RESULT_MARKERS = (LOCK_NAME, "summary.json", "campaign.json")


def _nested_results(p: Path) -> bool:
    return p.is_dir() and any((p / m).exists() for m in _RESULT_MARKERS)


class OutputFolder:
    """An output folder claimed by this process (see the module docstring)."""

    def __init__(self, path: Path, fd: int) -> None:
        self.path = path
        self._fd: int | None = fd

    def release(self) -> None:
        """Unlock (idempotent); the lock file stays, marking an axir folder."""
        if self._fd is not None:
            os.close(self._fd)  # closing drops the flock
            self._fd = None

    def __enter__(self) -> OutputFolder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()


def claim(path: Path, owned: Iterable[str]) -> OutputFolder:
    """Create/lock/clear the output folder ``path`` for one run; ``owned``: the names (or
    glob patterns) of the files a run writes there. :class:`AxirError` (one line naming the
    folder) if it cannot be created or written, another run holds it, or it holds files that
    are not an axir run's."""
    import fcntl

    path = Path(path)
    owned = list(owned)
    try:
        path.mkdir(parents=True, exist_ok=True)
        if not path.is_dir():
            raise AxirError(f"output folder {path}: is a file, not a folder")
        fd = os.open(path / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as e:
        raise AxirError(_problem(path, e)) from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        other = os.pread(fd, 64, 0).decode(errors="replace").strip() or "?"
        os.close(fd)
        raise AxirError(f"output folder {path} is in use by another axir run (pid {other}); "
                        "wait for it or choose another --out") from None
    folder = OutputFolder(path, fd)
    try:
        entries = sorted(p.name for p in path.iterdir()
                         if p.name != LOCK_NAME and not _nested_results(p))
        mine = [n for n in entries if n.startswith(TMP_PREFIX)
                or any(fnmatch.fnmatchcase(n, pat) for pat in owned)]
        foreign = [n for n in entries if n not in mine]
        if foreign:
            raise AxirError(f"output folder {path} holds {foreign[0]!r}, which no axir run "
                            "wrote: choose a new or empty folder")
        for n in mine:
            p = path / n
            if p.is_dir():
                raise AxirError(f"output folder {path}: {n} is a folder, expected a file")
            p.unlink()
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        with tempfile.NamedTemporaryFile(dir=path, prefix=TMP_PREFIX):  # writable?
            pass
    except OSError as e:
        folder.release()
        raise AxirError(_problem(path, e)) from None
    except BaseException:
        folder.release()
        raise
    return folder


def write_json_atomic(path: Path, data: Any) -> None:
    """``json.dumps(data, indent=2)`` into ``path`` through a temp file in the same folder
    and ``os.replace`` (never a half-written file; the temp file is removed on failure)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=TMP_PREFIX, suffix=".json")
    try:
        os.fchmod(fd, 0o644)  # as a plain open() under the usual umask (mkstemp: 0600)
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(json.dumps(data, indent=2) + "\n")
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
