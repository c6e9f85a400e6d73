"""The C shim for win64: cross-compiled with mingw-w64 (``x86_64-w64-mingw32-gcc``).

The same source as the Linux shim (``fmus/shim/axir_fmi2_shim.c``, ``#ifdef _WIN32`` parts):
forwarding of the 34 FMI functions to pythonfmu's DLL (shipped as
``binaries/win64/<id>_pythonfmu.dll``), ``fmi2Error`` for a call that logged an error, errors
of a failed ``fmi2Instantiate`` always delivered. It does not load or initialize Python (on
Windows the host provides it, as before). Without mingw-w64 the win64 binary stays
pythonfmu's (one :class:`~axir.fmus.shim_sources.ShimWarning` per process) and the
modelDescription's generationTool says "linux64 only". See docs/fmu_build.md.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import warnings
from pathlib import Path

from .shim_sources import (
    SHIM_DIR,
    SHIM_HEADERS,
    SHIM_SOURCE,
    ShimUnavailableError,
    ShimWarning,
)

#: The cross compiler (``$AXIR_MINGW_CC`` overrides; Debian: ``apt-get install
#: gcc-mingw-w64-x86-64``).
MINGW_CC = "x86_64-w64-mingw32-gcc"
INNER_SUFFIX = "_pythonfmu.dll"
#: Deterministic PE: no timestamp, stripped, no libgcc DLL, fixed seed, paths mapped.
CFLAGS = ("-std=c99", "-O2", "-shared", "-Wall", "-Wextra", "-static-libgcc", "-s",
          "-frandom-seed=axir_fmi2_shim", "-Wl,--no-insert-timestamp")
_CACHE: dict[tuple[str, ...], bytes] = {}
_WARNED: list[str] = []


def compile_shim_win64() -> bytes:
    """The shim as a win64 DLL (compiled once per process and compiler); raises
    :class:`~axir.fmus.shim_sources.ShimUnavailableError` when mingw-w64 is missing or fails."""

    cc = shutil.which(os.environ.get("AXIR_MINGW_CC") or MINGW_CC)
    if cc is None:
        raise ShimUnavailableError(f"{os.environ.get('AXIR_MINGW_CC') or MINGW_CC} not found "
                                   "(Debian: apt-get install gcc-mingw-w64-x86-64)")
    files = (SHIM_SOURCE, *SHIM_HEADERS)
    try:
        sources = {f: (SHIM_DIR / f).read_bytes() for f in files}
        version = subprocess.run([cc, "--version"], capture_output=True, text=True,
                                 timeout=60).stdout.splitlines()[:1]
    except (OSError, subprocess.SubprocessError) as e:
        raise ShimUnavailableError(f"shim sources or {cc} unusable: {e}") from None
    key = (cc, *version, hashlib.sha256(repr(sorted(sources.items())).encode()).hexdigest())
    if key in _CACHE:
        return _CACHE[key]
    with tempfile.TemporaryDirectory(prefix="axir_shim_w64_") as tmp:
        work = Path(tmp) / "axir-shim"
        work.mkdir()
        for f, data in sources.items():
            (work / f).write_bytes(data)
        cmd = [cc, *CFLAGS, f"-ffile-prefix-map={work}=.", f"-ffile-prefix-map={tmp}=.",
               "-o", "shim.dll", SHIM_SOURCE]
        env = {**os.environ, "LC_ALL": "C", "SOURCE_DATE_EPOCH": "315532800"}
        try:
            r = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=300,
                               env=env)
        except (OSError, subprocess.SubprocessError) as e:
            raise ShimUnavailableError(f"{cc} failed to run: {e}") from None
        if r.returncode != 0:
            raise ShimUnavailableError(f"{cc} failed ({r.returncode}): {r.stderr.strip()[:2000]}")
        lib = (work / "shim.dll").read_bytes()
    _CACHE[key] = lib
    return lib


def add_win64_shim(name: str, entries: dict[str, bytes]) -> bool:
    """Put the win64 shim in place of pythonfmu's DLL (renamed ``<name>_pythonfmu.dll``);
    False (and one warning per process) when it cannot be built."""

    dll = f"binaries/win64/{name}.dll"
    if dll not in entries:
        return False
    try:
        lib = compile_shim_win64()
    except ShimUnavailableError as e:
        if not _WARNED:
            _WARNED.append(str(e))
            warnings.warn(f"the win64 binaries are pythonfmu's, without the axir C shim ({e}); "
                          "the FMUs' generationTool says 'linux64 only'", ShimWarning,
                          stacklevel=3)
        return False
    entries[f"binaries/win64/{name}{INNER_SUFFIX}"] = entries[dll]
    entries[dll] = lib
    return True
