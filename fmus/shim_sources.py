"""Where the C shim's sources are and how a shim build fails: shared by the Linux build
(:mod:`.build`) and the win64 cross-build (:mod:`.shim_win64`). Build time only."""

from __future__ import annotations

from pathlib import Path

SHIM_DIR = Path(__file__).resolve().parent / "shim"
SHIM_SOURCE = "axir_fmi2_shim.c"
SHIM_HEADERS = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")


class ShimUnavailableError(RuntimeError):
    """The C shim cannot be compiled here (no compiler, unsupported platform, compiler error)."""


class ShimWarning(UserWarning):
    """An FMU was built without the C shim although it was requested."""
