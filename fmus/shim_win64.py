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

import os
import shutil
import warnings

from .shim_sources import (
    ShimUnavailableError,
    ShimWarning,
    compile_shim_with,
)

#: The cross compiler (``$AXIR_MINGW_CC`` overrides; Debian: ``apt-get install
#: gcc-mingw-w64-x86-64``).
MINGW_CC = "x86_64-w64-mingw32-gcc"
INNER_SUFFIX = "_pythonfmu.dll"
#: Deterministic PE: no timestamp, stripped, no libgcc DLL, fixed seed, paths mapped.
CFLAGS = ("-std=c99", "-O2", "-shared", "-Wall", "-Wextra", "-static-libgcc", "-s",
          "-frandom-seed=axir_fmi2_shim", "-Wl,--no-insert-timestamp")
_WARNED: list[str] = []


def compile_shim_win64() -> bytes:
    """The shim as a win64 DLL (compiled once per process and compiler); raises
    :class:`~axir.fmus.shim_sources.ShimUnavailableError` when mingw-w64 is missing or fails."""

    cc = shutil.which(os.environ.get("AXIR_MINGW_CC") or MINGW_CC)
    if cc is None:
        raise ShimUnavailableError(f"{os.environ.get('AXIR_MINGW_CC') or MINGW_CC} not found "
                                   "(Debian: apt-get install gcc-mingw-w64-x86-64)")
    return compile_shim_with(cc, CFLAGS, "shim.dll")


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
