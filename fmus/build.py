"""Build the axir FMUs: pythonfmu's FmuBuilder, then a deterministic post-processing pass.

``build_fmu("Pedestal", "dist")`` → ``dist/Pedestal.fmu``:

1. collect the bundle: the FMU's declaration module (``fmus/<name>_fmu.py``), ``fmus/_base.py``
   and the import closure of both inside ``axir.models``/``axir.fmus`` (relative imports
   followed with :mod:`ast`; absolute ``axir.*`` imports are rewritten to relative ones);
2. hash it (sha256 over path + content, :func:`axir.fmus._base.source_digest`) → package name
   ``_axir_<hash8>`` and slave module name ``axir_<name>_<hash8>`` (unique per content, so FMUs
   sharing one interpreter never run each other's code);
3. stage package + generated slave script, run ``FmuBuilder.build_FMU`` (in-process; the
   modules and ``sys.path`` entries it leaves behind are removed afterwards);
4. with ``shim=True``: compile the C shim (``fmus/shim/axir_fmi2_shim.c``, gcc) into
   ``binaries/linux64/<name>.so`` and rename pythonfmu's binary to ``<name>_pythonfmu.so``; the
   shim forwards every FMI call and turns a call that logged an Error-status message into
   ``fmi2Error`` (pythonfmu 0.7.0 cannot return it). No gcc (or not Linux x86_64): warning,
   pythonfmu's binary only;
5. rewrite the archive: our own modelDescription.xml (units, descriptions, ModelStructure,
   state capabilities), GUID = uuid5 over the archive content, fixed timestamps, sorted entries
   → the same sources (and the same compiler) give a byte-identical FMU.

See docs/fmu_build.md.
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import importlib.metadata
import importlib.util
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import uuid
import warnings
import zipfile
from collections.abc import Iterable
from pathlib import Path

from . import python_env, shim_win64
from ._base import source_digest

#: FMU name → declaration module in axir.fmus (each defines ``SPEC``).
DECLARATIONS: dict[str, str] = {
    "TargetGenerator": "target_generator_fmu",
    "Tracker": "tracker_fmu",
    "Pedestal": "pedestal_fmu",
    "RadarManager": "radar_manager_fmu",
}
#: Namespace of the content-derived GUIDs.
GUID_NAMESPACE = uuid.uuid5(uuid.NAMESPACE_URL, "urn:axir:fmu")
_ZIP_DATE = (1980, 1, 1, 0, 0, 0)
_ABS_IMPORT = re.compile(r"^(\s*from\s+)axir\.((?:models|fmus)(?:\.\w+)*)(\s+import\b)", re.M)


#: Default of ``build_fmu(..., shim=)``: wrap pythonfmu's binary in the C shim. The
#: environment variable ``AXIR_FMU_SHIM`` (``1``/``0``) overrides it.
SHIM_DEFAULT = True
SHIM_DIR = Path(__file__).resolve().parent / "shim"
SHIM_SOURCE = "axir_fmi2_shim.c"
SHIM_HEADERS = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")
#: Suffix of pythonfmu's own binary inside a shimmed FMU (the shim derives the name from its
#: own file name: ``<id>.so`` loads ``<id>_pythonfmu.so``).
INNER_SUFFIX = "_pythonfmu.so"
#: Deterministic output: no debug info, paths mapped, symbols stripped, fixed random seed.
SHIM_CFLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-fvisibility=hidden", "-Wall",
               "-Wextra", "-frandom-seed=axir_fmi2_shim", "-s", "-Wl,--build-id=sha1")
SHIM_LIBS = ("-ldl", "-pthread")
_SHIM_CACHE: dict[tuple[str, ...], bytes] = {}


class BuildError(RuntimeError):
    """The FMU cannot be built (missing declaration, bad import in bundled code, ...)."""


class ShimUnavailableError(RuntimeError):
    """The C shim cannot be compiled here (no gcc, not Linux x86_64, compiler error)."""


class ShimWarning(UserWarning):
    """An FMU was built without the C shim although it was requested."""


def _package_dirs() -> dict[str, Path]:
    """Source folders of the bundled sub-packages (``models``, ``fmus``)."""
    dirs = {}
    for sub in ("models", "fmus"):
        spec = importlib.util.find_spec(f"axir.{sub}")
        if spec is None or not spec.submodule_search_locations:
            raise BuildError(f"cannot locate axir.{sub}")
        dirs[sub] = Path(next(iter(spec.submodule_search_locations)))
    return dirs


def _relativise(text: str, package: str, rel: str) -> str:
    """Rewrite ``from axir.<pkg>... import`` into a relative import (bundled code only)."""

    def repl(m: re.Match[str]) -> str:
        target = m.group(2)
        if target == package or target.startswith(package + "."):
            dotted = "." + target[len(package) + 1:]
        else:
            dotted = ".." + target
        return f"{m.group(1)}{dotted}{m.group(3)}"

    text = _ABS_IMPORT.sub(repl, text)
    if re.search(r"^\s*import\s+axir\b|^\s*from\s+axir\s+import\b", text, re.M):
        raise BuildError(f"{rel}: 'import axir...' cannot be bundled; use relative imports")
    return text


def collect_sources(declaration: str) -> dict[str, bytes]:
    """Bundle content for a declaration module: {``models/x.py`` | ``fmus/y.py``: source}.

    The import closure (relative imports, after rewriting absolute ``axir.*`` ones) of the
    declaration and ``fmus/_base.py``, plus the ``__init__.py`` of each sub-package.
    """
    dirs = _package_dirs()
    out: dict[str, bytes] = {}
    todo = [("fmus", declaration), ("fmus", "_base"), ("fmus", "__init__"),
            ("models", "__init__")]
    while todo:
        package, mod = todo.pop()
        rel = f"{package}/{mod}.py"
        if rel in out:
            continue
        path = dirs[package] / f"{mod}.py"
        if not path.is_file():
            raise BuildError(f"bundled module {rel} not found in {dirs[package]}")
        text = _relativise(path.read_text(encoding="utf-8"), package, rel)
        out[rel] = text.encode("utf-8")
        for node in ast.walk(ast.parse(text, filename=str(path))):
            if not isinstance(node, ast.ImportFrom) or node.level == 0:
                continue
            if node.level > 2:
                raise BuildError(f"{rel}: relative import beyond axir (level {node.level})")
            parts = ([package] if node.level == 1 else []) + (
                node.module.split(".") if node.module else [])
            if not parts or parts[0] not in dirs:
                raise BuildError(f"{rel}: cannot resolve relative import {ast.unparse(node)}")
            base = dirs[parts[0]].joinpath(*parts[1:])
            if len(parts) > 1 and base.with_suffix(".py").is_file():
                todo.append((parts[0], "/".join(parts[1:])))
            for alias in node.names:  # `from . import x` / `from ..models import x`
                if len(parts) == 1 and (dirs[parts[0]] / f"{alias.name}.py").is_file():
                    todo.append((parts[0], alias.name))
    return out


def _slave_script(name: str, declaration: str, package: str, digest: str) -> str:
    return (
        f'"""Slave script of {name}.fmu (generated by axir.fmus.build; do not edit)."""\n\n'
        "import ctypes as _ctypes\n\n"
        f"from {package}.fmus._base import AxirSlave as _AxirSlave\n"
        f"from {package}.fmus.{declaration} import SPEC as _SPEC\n\n\n"
        f"class {name}Fmu(_AxirSlave):\n"
        f'    """{name} FMU running the bundled package {package}."""\n\n'
        f"    SPEC = _SPEC\n"
        f'    BUNDLE = ("{package}", "{digest}")\n\n\n'
        "# pythonfmu 0.7.0's fmi2Instantiate re-executes this file in the module's globals and\n"
        "# then Py_DECREFs that borrowed dict once: one extra reference per execution keeps the\n"
        "# module dict alive (without it the 2nd instantiation segfaults).\n"
        "_ctypes.pythonapi.Py_IncRef(_ctypes.py_object(globals()))\n"
    )


def _write_reproducible_zip(path: Path, entries: dict[str, bytes]) -> None:
    names = sorted(entries, key=lambda n: (n != "modelDescription.xml", n))
    tmp = path.with_suffix(".fmu.tmp")
    with zipfile.ZipFile(tmp, "w") as z:
        for n in names:
            zi = zipfile.ZipInfo(n, date_time=_ZIP_DATE)
            zi.compress_type = zipfile.ZIP_DEFLATED
            zi.create_system = 3
            zi.external_attr = (0o100755 if n.startswith("binaries/") else 0o100644) << 16
            z.writestr(zi, entries[n], compresslevel=9)
    tmp.replace(path)


def shim_default() -> bool:
    """``AXIR_FMU_SHIM`` (``1``/``0``, ``true``/``false``) if set, else :data:`SHIM_DEFAULT`."""
    env = os.environ.get("AXIR_FMU_SHIM", "").strip().lower()
    if env in ("1", "true", "yes", "on"):
        return True
    if env in ("0", "false", "no", "off"):
        return False
    return SHIM_DEFAULT


def compile_shim() -> bytes:
    """The C shim as a Linux x86_64 shared object (compiled once per process and compiler).

    Deterministic: the sources are copied to a fixed relative layout in a temporary folder and
    compiled there with relative paths and ``-ffile-prefix-map``, without debug info, stripped;
    the same sources and compiler give the same bytes. Raises :class:`ShimUnavailableError`.
    """
    if not (sys.platform.startswith("linux") and platform.machine() in ("x86_64", "AMD64")):
        raise ShimUnavailableError(f"the shim is built for Linux x86_64 only (this is "
                              f"{sys.platform}/{platform.machine()})")
    cc = shutil.which(os.environ.get("CC") or "gcc")
    if cc is None:
        raise ShimUnavailableError(f"C compiler {os.environ.get('CC') or 'gcc'!r} not found")
    files = (SHIM_SOURCE, *SHIM_HEADERS)
    try:
        sources = {f: (SHIM_DIR / f).read_bytes() for f in files}
        version = subprocess.run([cc, "--version"], capture_output=True, text=True,
                                 timeout=60).stdout.splitlines()[:1]
    except (OSError, subprocess.SubprocessError) as e:
        raise ShimUnavailableError(f"shim sources or compiler unusable: {e}") from None
    key = (cc, *version, hashlib.sha256(repr(sorted(sources.items())).encode()).hexdigest())
    if key in _SHIM_CACHE:
        return _SHIM_CACHE[key]
    with tempfile.TemporaryDirectory(prefix="axir_shim_") as tmp:
        work = Path(tmp) / "axir-shim"
        work.mkdir()
        for f, data in sources.items():
            (work / f).write_bytes(data)
        cmd = [cc, *SHIM_CFLAGS, f"-ffile-prefix-map={work}=.", f"-ffile-prefix-map={tmp}=.",
               "-o", "shim.so", SHIM_SOURCE, *SHIM_LIBS]
        env = {**os.environ, "LC_ALL": "C", "SOURCE_DATE_EPOCH": "315532800"}
        try:
            r = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=300,
                               env=env)
        except (OSError, subprocess.SubprocessError) as e:
            raise ShimUnavailableError(f"{cc} failed to run: {e}") from None
        if r.returncode != 0:
            raise ShimUnavailableError(f"{cc} failed ({r.returncode}): {r.stderr.strip()[:2000]}")
        lib = (work / "shim.so").read_bytes()
    _SHIM_CACHE[key] = lib
    return lib


def _add_shim(name: str, entries: dict[str, bytes]) -> bool:
    """Put the shim in place of pythonfmu's linux64 binary (renamed ``<name>_pythonfmu.so``);
    False with a :class:`ShimWarning` when it cannot be built."""
    so = f"binaries/linux64/{name}.so"
    try:
        if so not in entries:
            raise ShimUnavailableError(f"pythonfmu produced no {so}")
        lib = compile_shim()
    except ShimUnavailableError as e:
        warnings.warn(f"{name}.fmu is built without the axir C shim ({e}): pythonfmu's binary "
                      "alone cannot return fmi2Error, so an invalid parameter (or any error "
                      "the FMU logs) answers fmi2Discard at the next fmi2DoStep instead of "
                      "fmi2Error at the call that failed", ShimWarning, stacklevel=3)
        return False
    entries[f"binaries/linux64/{name}{INNER_SUFFIX}"] = entries[so]
    entries[so] = lib
    # the Python the shim loads in a non-Python host (fmus/python_env.py)
    problem = python_env.record(entries)
    if problem:
        warnings.warn(f"{name}.fmu: {problem}", ShimWarning, stacklevel=3)
    return True


def build_fmu(name: str, dest_dir: str | Path, shim: bool | None = None) -> Path:
    """Build ``<dest_dir>/<name>.fmu`` from its declaration; returns the FMU path.

    ``shim`` (default :func:`shim_default`): wrap pythonfmu's Linux binary in the C shim that
    returns ``fmi2Error`` from a call that logged an error (see docs/fmu_build.md); when it
    cannot be compiled, a :class:`ShimWarning` is issued and the FMU is built without it.
    """
    from pythonfmu import FmuBuilder
    from pythonfmu import __version__ as pythonfmu_version

    if shim is None:
        shim = shim_default()
    if name not in DECLARATIONS:
        raise BuildError(f"unknown FMU {name!r}; known: {', '.join(DECLARATIONS)}")
    declaration = DECLARATIONS[name]
    sources = collect_sources(declaration)
    digest = source_digest(sources.items())
    package = f"_axir_{digest[:8]}"
    script_mod = f"axir_{name.lower()}_{digest[:8]}"
    dest = Path(dest_dir)
    dest.mkdir(parents=True, exist_ok=True)

    with tempfile.TemporaryDirectory(prefix="axir_fmu_") as tmp:
        stage = Path(tmp) / "stage"
        for rel, data in sources.items():
            f = stage / package / rel
            f.parent.mkdir(parents=True, exist_ok=True)
            f.write_bytes(data)
        (stage / package / "__init__.py").write_text(
            f'"""axir code bundled into {name}.fmu (generated; do not edit)."""\n\n'
            f'BUNDLE_HASH = "{digest}"\n', encoding="utf-8")
        script = stage / f"{script_mod}.py"
        script.write_text(_slave_script(name, declaration, package, digest), encoding="utf-8")

        saved_path = list(sys.path)
        try:
            raw = FmuBuilder.build_FMU(
                script, dest=Path(tmp) / "out", project_files=[stage / package],
                canGetAndSetFMUstate=True, canSerializeFMUstate=True,
            )
            base = sys.modules[f"{package}.fmus._base"]
            spec = sys.modules[f"{package}.fmus.{declaration}"].SPEC
            with zipfile.ZipFile(raw) as z:
                entries = {i.filename: z.read(i) for i in z.infolist()
                           if not i.is_dir() and "__pycache__" not in i.filename
                           and not i.filename.endswith(".pyc")}
            shimmed = shim and _add_shim(name, entries)
            version = importlib.metadata.version("axir")
            tool = f"axir.fmus.build with PythonFMU {pythonfmu_version}"
            if shimmed:  # platform-exact: the win64 shim needs mingw-w64 (shim_win64.py)
                win64 = shim_win64.add_win64_shim(name, entries)
                tool += f" and the axir fmi2 shim ({'linux64, win64' if win64 else 'linux64 only'})"
            entries.pop("modelDescription.xml")
            h = hashlib.sha256()
            for n in sorted(entries):
                h.update(n.encode() + b"\0" + hashlib.sha256(entries[n]).digest())
            h.update(base.model_description_xml(spec, "{GUID}", version, tool).encode())
            guid = "{" + str(uuid.uuid5(GUID_NAMESPACE, h.hexdigest())) + "}"
            entries["modelDescription.xml"] = base.model_description_xml(
                spec, guid, version, tool).encode("utf-8")
        finally:
            sys.path[:] = saved_path
            for m in [m for m in sys.modules
                      if m in (script_mod, package) or m.startswith(package + ".")]:
                del sys.modules[m]
        out = dest / f"{name}.fmu"
        _write_reproducible_zip(out, entries)
    return out


def build_all(dest_dir: str | Path, names: Iterable[str] | None = None,
              skip_missing: bool = False, shim: bool | None = None) -> list[Path]:
    """Build every declared FMU (or ``names``) into ``dest_dir``.

    With ``skip_missing``, FMUs whose declaration module does not exist yet are skipped.
    ``shim``: see :func:`build_fmu`.
    """
    dirs = _package_dirs()
    built = []
    for name in names or DECLARATIONS:
        if skip_missing and not (dirs["fmus"] / f"{DECLARATIONS[name]}.py").is_file():
            continue
        built.append(build_fmu(name, dest_dir, shim=shim))
    return built


def main(argv: list[str] | None = None) -> int:
    """``python -m axir.fmus.build [-d dist] [NAME ...]``."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help=f"FMUs to build (default: {', '.join(DECLARATIONS)})")
    ap.add_argument("-d", "--dest", default="dist", help="output folder (default: dist)")
    ap.add_argument("--skip-missing", action="store_true",
                    help="skip FMUs whose declaration file does not exist yet")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--shim", dest="shim", action="store_true", default=None,
                   help="wrap pythonfmu's binary in the C shim (fmi2Error support; needs gcc)")
    g.add_argument("--no-shim", dest="shim", action="store_false",
                   help="pythonfmu's binary only (errors answer fmi2Discard at fmi2DoStep)")
    a = ap.parse_args(argv)
    for p in build_all(a.dest, a.names or None, a.skip_missing, shim=a.shim):
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
