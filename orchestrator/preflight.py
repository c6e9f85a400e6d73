"""Everything about a run that can be checked before it starts, checked before it starts.

Each check raises :class:`AxirError` (exit 2) with one line naming the file, key, variable or
value, instead of a traceback (or a silent wrap-around in ctypes) after minutes of simulation:

- :func:`check_fmu_file`: the FMU is a zip with a readable modelDescription, supports
  co-simulation, has a binary for this platform (``binaries/linux64/<modelIdentifier>.so``) and,
  for an FMU built by axir, a GUID equal to the content GUID its build computes
  (``fmus/build.py``: uuid5 over the archive's entries), so an edited archive or a GUID that
  does not belong to the files is refused.
- :func:`value_problem`: a parameter or input value fits its FMI variable: a Real is a finite
  number within the variable's ``min``/``max`` (derived from the models' ``Param`` ranges); an
  Integer is an integer within int32 and ``min``/``max`` (ctypes would silently wrap
  4294967298 to 2); a Boolean is true/false or 0/1; a String is a string.
- :func:`check_duration`: a run estimated (at :data:`~.config.US_PER_STEP`) to take longer than
  :data:`~.config.LONG_RUN_S` needs ``--long``.
"""

from __future__ import annotations

import math
import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .config import LONG_RUN_S, US_PER_STEP
from .errors import AxirError
from .fmi import load_model_description

INT32 = (-(2**31), 2**31 - 1)
#: what an axir build writes into ``generationTool`` (fmus/build.py)
AXIR_TOOL_PREFIX = "axir.fmus.build"


def _platform() -> tuple[str, str]:
    from fmpy import platform, sharedLibraryExtension

    return platform, sharedLibraryExtension


def content_guid(entries: Mapping[str, bytes], model_description: str, guid: str) -> str:
    """The GUID an axir build gives an archive of ``entries`` (without modelDescription.xml)
    whose modelDescription reads ``model_description`` with ``guid`` in it: uuid5 in the
    build's namespace over (name, sha256) of the sorted entries and the modelDescription with
    the ``{GUID}`` placeholder (:func:`axir.fmus.build.content_guid`, used by the build;
    tests/test_preflight.py checks it against freshly built FMUs)."""
    from axir.fmus.build import content_guid as build_guid

    return build_guid(entries, model_description.replace(guid, "{GUID}"))


def check_fmu_file(path: Path, unit: str) -> Any:
    """Check the FMU file of ``unit`` (see the module docstring); returns its model
    description."""
    path = Path(path)
    if not path.is_file():
        raise AxirError(f"FMU file not found: {path} (unit {unit}); run `axir build` first "
                        "or pass --fmu-dir")
    try:
        with zipfile.ZipFile(path) as z:
            names = set(z.namelist())
            if "modelDescription.xml" not in names:
                raise AxirError(f"{path}: no modelDescription.xml (not an FMU)")
            md_text = z.read("modelDescription.xml").decode("utf-8")
            md = load_model_description(path)
            if md.coSimulation is None:
                raise AxirError(f"{path}: does not support FMI 2.0 co-simulation")
            plat, ext = _platform()
            lib = f"binaries/{plat}/{md.coSimulation.modelIdentifier}{ext}"
            if lib not in names:
                raise AxirError(f"{path}: no binary for this platform ({lib} missing; "
                                f"platforms: {_platforms(names) or 'none'})")
            if (md.generationTool or "").startswith(AXIR_TOOL_PREFIX):
                entries = {i.filename: z.read(i) for i in z.infolist()
                           if not i.is_dir() and i.filename != "modelDescription.xml"}
                expected = content_guid(entries, md_text, md.guid)
                if md.guid != expected:
                    raise AxirError(f"{path}: GUID {md.guid} does not match the FMU's content "
                                    f"(expected {expected}): modified after `axir build`; "
                                    "rebuild it")
    except (zipfile.BadZipFile, OSError, UnicodeDecodeError) as e:
        raise AxirError(f"{path}: not a readable FMU (zip) file: {e}") from None
    return md


def _platforms(names: set[str]) -> str:
    found = sorted({n.split("/")[1] for n in names
                    if n.startswith("binaries/") and n.count("/") >= 2})
    return ", ".join(found)


def _bound(text: Any) -> float | None:
    try:
        return None if text is None else float(text)
    except (TypeError, ValueError):
        return None


def value_problem(ref: str, v: Any, value: Any) -> str | None:
    """Why ``value`` cannot be given to the FMI variable ``v`` (named ``ref``), or None."""
    kind = v.type
    if kind == "String":
        return None if isinstance(value, str) else \
            f"{ref} is a String, got {value!r}"
    if kind == "Boolean":
        if isinstance(value, bool) or (isinstance(value, int) and value in (0, 1)):
            return None
        return f"{ref} is a Boolean: true, false, 0 or 1, got {value!r}"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"{ref} is a{'n' if kind[0] in 'IE' else ''} {kind}: a number, got {value!r}"
    if not math.isfinite(value):
        return f"{ref} must be finite, got {value!r}"
    if kind in ("Integer", "Enumeration"):
        if isinstance(value, float) and not value.is_integer():
            return f"{ref} is an Integer, got {value!r}"
        if not INT32[0] <= int(value) <= INT32[1]:
            return f"{ref} is an Integer (32 bit): {INT32[0]}..{INT32[1]}, got {value!r}"
    lo, hi = _bound(v.min), _bound(v.max)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        unit = f" {v.unit}" if getattr(v, "unit", None) else ""
        return f"{ref} = {value!r} is out of range [{v.min}, {v.max}]{unit}"
    return None


def check_values(parameters: Mapping[str, Mapping[str, Any]], mds: Mapping[str, Any],
                 source: str = "") -> None:
    """Check every unit's parameter/input values against its model description (unknown
    names are left to the system validation, which names them)."""
    where = f"{source}: " if source else ""
    for unit, values in parameters.items():
        md = mds.get(unit)
        if md is None:
            continue
        variables = {v.name: v for v in md.modelVariables}
        for name, value in values.items():
            v = variables.get(name)
            if v is None or v.causality not in ("parameter", "input"):
                continue
            p = value_problem(f"{unit}.{name}", v, value)
            if p is not None:
                raise AxirError(where + p)


def estimate_wall_s(duration: float, step: float) -> float:
    """Estimated wall time [s] of a run of ``duration`` [s] at macro steps of ``step`` [s]."""
    return duration / step * US_PER_STEP * 1e-6


def check_duration(duration: float, step: float, long_ok: bool, runs: int = 1,
                   workers: int = 1) -> None:
    """Refuse a run (or campaign) estimated to take more than a day, unless ``long_ok``."""
    est = estimate_wall_s(duration, step) * runs / max(workers, 1)
    if est > LONG_RUN_S and not long_ok:
        raise AxirError(f"duration {duration:g} s at steps of {step:g} s would take about "
                        f"{est / 86400:.3g} days ({US_PER_STEP:g} µs per step); pass --long "
                        "if you mean it")


__all__ = ["check_duration", "check_fmu_file", "check_values", "content_guid",
           "estimate_wall_s", "value_problem"]
