"""The Python an axir FMU runs on: recorded at build time, read by the C shim at run time.

A pythonfmu FMU embeds CPython. In a Python host (fmpy, libcosimpy, the axir master) the FMU
runs in the host's interpreter. In any other host the C shim (``fmus/shim/axir_fmi2_shim.c``)
loads and initializes a Python itself, before it loads pythonfmu's binary; which one is
decided here:

* ``resources/axir_python.txt`` (data only, ``key=value`` lines, written by :func:`record`):
  the build interpreter's ``libpython`` (the shared library to ``dlopen``), ``home``
  (``sys.base_prefix``, the ``PYTHONHOME``), ``stdlib``, ``executable`` (``sys.executable``,
  e.g. the venv's python), its ``sys.path`` entries (``path=``, in order: stdlib, lib-dynload,
  site-packages, ...) and the third-party top-level modules the bundled code imports
  (``require=numpy`` ...). The shim checks that they import before it hands over to pythonfmu.
  Packages only some parameter values need (the Tracker's IMM filter: filterpy) are written
  as ``require_if=<package> <parameter>=<value>`` lines instead (the shim ignores them; the
  model reports a missing one when it is configured): :func:`packages_needed` reads both.
* ``AXIR_FMU_PYTHON=/path/to/python3`` (environment of the host process) overrides everything
  but the ``require=`` lines: the shim runs ``$AXIR_FMU_PYTHON -E resources/axir_python_probe.py``
  (the :data:`PROBE` script below, shipped in the FMU) and takes the same keys from its output.
  The build records the build interpreter with the very same script, so both paths give the
  same settings for the same interpreter.

See docs/fmu_build.md ("The Python of the FMU").
"""

from __future__ import annotations

import ast
import subprocess
import sys
from collections.abc import Mapping

#: Resource file holding the recorded settings (read by the shim).
CONFIG_NAME = "axir_python.txt"
#: Resource file holding :data:`PROBE` (run by the shim with ``$AXIR_FMU_PYTHON -E``).
PROBE_NAME = "axir_python_probe.py"
#: Environment variable naming the python3 executable to run the FMU on instead.
ENV_VAR = "AXIR_FMU_PYTHON"
#: First line of a settings text (the shim rejects other formats).
FORMAT = "format=axir-python 1"

PROBE = '''\
"""Print the settings the axir FMU shim needs to embed this Python (axir docs/fmu_build.md).

Run as: python3 -E axir_python_probe.py. Output: key=value lines (paths as bytes)."""
import os
import sys
import sysconfig


def out(key, value):
    value = os.fsencode(value)
    if b"\\n" not in value and b"\\r" not in value:
        sys.stdout.buffer.write(key.encode() + b"=" + value + b"\\n")


def libpython():
    """The shared libpython of this interpreter ("" if it has none)."""
    libdir = sysconfig.get_config_var("LIBDIR") or ""
    dirs = [libdir, os.path.join(libdir, sysconfig.get_config_var("MULTIARCH") or "")]
    for name in (sysconfig.get_config_var("INSTSONAME"), sysconfig.get_config_var("LDLIBRARY")):
        for d in dirs:
            if name and ".so" in name and os.path.isfile(os.path.join(d, name)):
                return os.path.join(d, name)
    return ""


out("format", "axir-python 1")
out("implementation", sys.implementation.name)
out("version", "%d.%d" % sys.version_info[:2])
out("executable", sys.executable)
out("libpython", libpython())
if sys.base_exec_prefix == sys.base_prefix:
    out("home", sys.base_prefix)
else:
    out("home", sys.base_prefix + os.pathsep + sys.base_exec_prefix)
out("stdlib", sysconfig.get_path("stdlib"))
for entry in sys.path[1:]:  # [0] is the script's folder (or "" with -c)
    if os.path.isabs(entry):
        out("path", entry)
'''

_PROBE_CACHE: dict[str, tuple[bytes, str]] = {}


def probe(python: str | None = None) -> tuple[bytes, str]:
    """Run :data:`PROBE` with ``python -E`` (default: this interpreter); (output, problem).

    ``problem`` is "" when the interpreter can be embedded (it has a shared libpython), else
    a sentence saying why not.
    """
    python = python or sys.executable
    if python in _PROBE_CACHE:
        return _PROBE_CACHE[python]
    try:
        r = subprocess.run([python, "-E", "-c", PROBE], capture_output=True, timeout=120)
    except (OSError, subprocess.SubprocessError) as e:
        return b"", f"{python} cannot be run: {e}"
    if r.returncode != 0 or not r.stdout.startswith(FORMAT.encode()):
        return b"", f"{python} -E {PROBE_NAME} failed: {r.stderr.decode(errors='replace')[-500:]}"
    problem = ""
    if b"\nlibpython=\n" in r.stdout:
        problem = (f"{python} has no shared libpython (built without --enable-shared): "
                   f"non-Python hosts need {ENV_VAR} set to a python3 that has one")
    _PROBE_CACHE[python] = (r.stdout, problem)
    return r.stdout, problem


def required_modules(entries: Mapping[str, bytes]) -> list[str]:
    """Third-party top-level modules imported by the FMU's Python code (``resources/**.py``):
    absolute imports (module level or in functions) that are neither in the standard library
    nor shipped in ``resources/`` (pythonfmu, the bundle, the slave script)."""
    shipped = set()
    for name in entries:
        if name.startswith("resources/"):
            parts = name[len("resources/"):].split("/")
            shipped.add(parts[0][:-3] if len(parts) == 1 and parts[0].endswith(".py")
                        else parts[0])
    found: set[str] = set()
    for name, data in entries.items():
        if not (name.startswith("resources/") and name.endswith(".py")):
            continue
        for node in ast.walk(ast.parse(data, filename=name)):
            if isinstance(node, ast.Import):
                found.update(a.name.split(".")[0] for a in node.names)
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                found.add(node.module.split(".")[0])
    return sorted(m for m in found
                  if m not in sys.stdlib_module_names and m not in shipped and m != "__future__")


def record(entries: dict[str, bytes],
           conditional: Mapping[str, Mapping[str, tuple[str, ...]]] | None = None) -> str:
    """Add ``resources/axir_python.txt`` and ``resources/axir_python_probe.py`` to an FMU's
    entries (the build interpreter, probed with :data:`PROBE`, and the required modules);
    returns "" or a sentence saying why non-Python hosts will need ``AXIR_FMU_PYTHON``.

    ``conditional``: ``{FMI parameter name: {value: (package, ...)}}``, the packages only
    those parameter values need (``require_if=`` lines, not ``require=``)."""
    out, problem = probe()
    when = sorted((pkg, name, value) for name, by_value in (conditional or {}).items()
                  for value, pkgs in by_value.items() for pkg in pkgs)
    optional = {pkg for pkg, _, _ in when}
    requires = [m for m in required_modules(entries) if m not in optional]
    text = (f"# The Python this FMU runs on in a non-Python host (axir docs/fmu_build.md).\n"
            f"# Recorded at build time; {ENV_VAR}=/path/to/python3 overrides all but require=.\n"
            ).encode() + (out or (FORMAT + "\n").encode())
    text += b"".join(f"require={m}\n".encode() for m in requires)
    text += b"".join(f"require_if={pkg} {name}={value}\n".encode() for pkg, name, value in when)
    entries[f"resources/{CONFIG_NAME}"] = text
    entries[f"resources/{PROBE_NAME}"] = PROBE.encode()
    return problem


def packages_needed(settings: bytes, parameters: Mapping[str, str]) -> tuple[list[str], dict]:
    """What a host Python needs for an FMU whose ``resources/axir_python.txt`` is ``settings``
    and whose parameters are ``parameters`` (FMI name -> value as text; missing names take
    the FMU default, which never needs an optional package).

    Returns (packages, recorded) where ``recorded`` holds the build interpreter's
    ``implementation``, ``version`` and ``executable``.
    """
    if not settings.startswith(b"#") and not settings.startswith(FORMAT.encode()):
        raise ValueError("not an axir Python settings file")
    needed: list[str] = []
    recorded: dict[str, str] = {}
    for raw in settings.decode("utf-8", errors="replace").splitlines():
        key, sep, value = raw.partition("=")
        if raw.startswith("#") or not sep:
            continue
        if key == "require" and value not in needed:
            needed.append(value)
        elif key == "require_if":
            pkg, _, cond = value.partition(" ")
            name, _, want = cond.partition("=")
            if parameters.get(name) == want and pkg not in needed:
                needed.append(pkg)
        elif key in ("implementation", "version", "executable"):
            recorded[key] = value
    return needed, recorded
