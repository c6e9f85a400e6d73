"""Where the C shim's sources are and how a shim build fails: shared by the Linux build
(:mod:`.build`) and the win64 cross-build (:mod:`.shim_win64`). Build time only."""

from __future__ import annotations

import hashlib
import os
import subprocess
import tempfile
from collections.abc import Sequence
from pathlib import Path

SHIM_DIR = Path(__file__).resolve().parent / "shim"
SHIM_SOURCE = "axir_fmi2_shim.c"
SHIM_HEADERS = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")


class ShimUnavailableError(RuntimeError):
    """The C shim cannot be compiled here (no compiler, unsupported platform, compiler error)."""


class ShimWarning(UserWarning):
    """An FMU was built without the C shim although it was requested."""


_CACHE: dict[tuple[str, ...], bytes] = {}


def compile_shim_with(cc: str, flags: Sequence[str], out_name: str,
                      libs: Sequence[str] = ()) -> bytes:
    """The shim compiled by ``cc`` (a path) into ``out_name``, reproducibly: the sources are
    copied to a fresh folder and compiled there with relative paths and
    ``-ffile-prefix-map``, fixed locale and ``SOURCE_DATE_EPOCH``; the same sources, compiler
    and flags give the same bytes (cached per process). Raises :class:`ShimUnavailableError`
    naming the compiler when the sources or the compiler are unusable."""
    files = (SHIM_SOURCE, *SHIM_HEADERS)
    try:
        sources = {f: (SHIM_DIR / f).read_bytes() for f in files}
        version = subprocess.run([cc, "--version"], capture_output=True, text=True,
                                 timeout=60).stdout.splitlines()[:1]
    except (OSError, subprocess.SubprocessError) as e:
        raise ShimUnavailableError(f"shim sources or compiler {cc} unusable: {e}") from None
    key = (cc, *version, *flags, out_name, *libs,
           hashlib.sha256(repr(sorted(sources.items())).encode()).hexdigest())
    if key in _CACHE:
        return _CACHE[key]
    with tempfile.TemporaryDirectory(prefix="axir_shim_") as tmp:
        work = Path(tmp) / "axir-shim"
        work.mkdir()
        for f, data in sources.items():
            (work / f).write_bytes(data)
        cmd = [cc, *flags, f"-ffile-prefix-map={work}=.", f"-ffile-prefix-map={tmp}=.",
               "-o", out_name, SHIM_SOURCE, *libs]
        env = {**os.environ, "LC_ALL": "C", "SOURCE_DATE_EPOCH": "315532800"}
        try:
            r = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=300,
                               env=env)
        except (OSError, subprocess.SubprocessError) as e:
            raise ShimUnavailableError(f"{cc} failed to run: {e}") from None
        if r.returncode != 0:
            raise ShimUnavailableError(f"{cc} failed ({r.returncode}): {r.stderr.strip()[:2000]}")
        lib = (work / out_name).read_bytes()
    _CACHE[key] = lib
    return lib
