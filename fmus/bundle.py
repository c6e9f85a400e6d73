"""Build-time bundling of an FMU's Python code, and the reproducible zip writer.

- :func:`collect_sources`: the bundle of a declaration module: its import closure inside
  ``axir.models``/``axir.fmus`` and that of the runtime slave (:mod:`axir.fmus.slave`), relative
  imports followed with :mod:`ast`, absolute ``axir.*`` imports rewritten to relative ones, plus
  the ``__init__.py`` of every package on the way. Its hash (:func:`~.digest.source_digest`)
  names the bundled package.
- :func:`write_reproducible_zip`: a zip archive whose bytes depend only on its entries (fixed
  timestamps, sorted entries, fixed permissions); used for the FMUs, reusable for any archive
  (the SSP export).

Not bundled into the FMUs (build time only).
"""

from __future__ import annotations

import ast
import importlib.util
import re
import zipfile
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

_ZIP_DATE = (1980, 1, 1, 0, 0, 0)
_ABS_IMPORT = re.compile(r"^(\s*from\s+)axir\.((?:models|fmus)(?:\.\w+)*)(\s+import\b)", re.M)
#: Start of every FMU's bundle besides its declaration: the runtime slave and the two packages.
RUNTIME_MODULES: tuple[tuple[str, ...], ...] = (("fmus", "slave"), ("fmus",), ("models",))


class BuildError(RuntimeError):
    """The FMU cannot be built (missing declaration, bad import in bundled code, ...)."""


def package_dirs() -> dict[str, Path]:
    """Source folders of the bundled sub-packages (``models``, ``fmus``)."""
    dirs = {}
    for sub in ("models", "fmus"):
        spec = importlib.util.find_spec(f"axir.{sub}")
        if spec is None or not spec.submodule_search_locations:
            raise BuildError(f"cannot locate axir.{sub}")
        dirs[sub] = Path(next(iter(spec.submodule_search_locations)))
    return dirs


def _module_file(parts: tuple[str, ...], dirs: dict[str, Path]) -> tuple[Path, bool] | None:
    """Source file of the module or package ``parts`` (``("models", "radar", "params")``) and
    whether it is a package (``__init__.py``); None if it is neither."""
    if not parts or parts[0] not in dirs:
        return None
    base = dirs[parts[0]].joinpath(*parts[1:])
    if len(parts) > 1 and base.with_suffix(".py").is_file():
        return base.with_suffix(".py"), False
    if (base / "__init__.py").is_file():
        return base / "__init__.py", True
    return None


def _relativise(text: str, package: tuple[str, ...], rel: str) -> str:
    """Rewrite ``from axir.<pkg>... import`` into a relative import (bundled code only);
    ``package``: the parts of the package the module lives in (``("models", "radar")``)."""

    def repl(m: re.Match[str]) -> str:
        target = tuple(m.group(2).split("."))
        common = 0
        while common < min(len(target), len(package)) and target[common] == package[common]:
            common += 1
        dots = "." * (len(package) - common + 1)
        return f"{m.group(1)}{dots}{'.'.join(target[common:])}{m.group(3)}"

    text = _ABS_IMPORT.sub(repl, text)
    if re.search(r"^\s*import\s+axir\b|^\s*from\s+axir\s+import\b", text, re.M):
        raise BuildError(f"{rel}: 'import axir...' cannot be bundled; use relative imports")
    return text


def collect_sources(declaration: str) -> dict[str, bytes]:
    """Bundle content for a declaration module: {``models/x.py`` | ``fmus/y.py``: source}.

    The import closure (relative imports, after rewriting absolute ``axir.*`` ones) of the
    declaration and the runtime slave (:data:`RUNTIME_MODULES`), plus the ``__init__.py`` of
    every package on the way.
    """
    dirs = package_dirs()
    out: dict[str, bytes] = {}
    todo: list[tuple[str, ...]] = [("fmus", declaration), *RUNTIME_MODULES]
    while todo:
        mod = todo.pop()
        found = _module_file(mod, dirs)
        if found is None:
            raise BuildError(f"bundled module {'.'.join(mod)} not found in {dirs[mod[0]]}")
        path, is_pkg = found
        rel = f"{mod[0]}/{path.relative_to(dirs[mod[0]]).as_posix()}"
        if rel in out:
            continue
        package = mod if is_pkg else mod[:-1]
        todo += [package[:i] for i in range(1, len(package) + 1)]  # enclosing packages
        text = _relativise(path.read_text(encoding="utf-8"), package, rel)
        out[rel] = text.encode("utf-8")
        for node in ast.walk(ast.parse(text, filename=str(path))):
            if not isinstance(node, ast.ImportFrom) or node.level == 0:
                continue
            if node.level > len(package) + 1:
                raise BuildError(f"{rel}: relative import beyond axir (level {node.level})")
            base = package[:len(package) - node.level + 1] + (
                tuple(node.module.split(".")) if node.module else ())
            if _module_file(base, dirs) is None:
                raise BuildError(f"{rel}: cannot resolve relative import {ast.unparse(node)}")
            todo.append(base)
            for alias in node.names:  # `from . import x` / `from ..models import x`
                if _module_file((*base, alias.name), dirs) is not None:
                    todo.append((*base, alias.name))
    return out


def write_reproducible_zip(path: Path, entries: Mapping[str, bytes], *,
                           first: Sequence[str] = ("modelDescription.xml",),
                           stored: Callable[[str], bool] = lambda name: False) -> None:
    """Write ``entries`` (archive name → bytes) to the zip file ``path``, reproducibly.

    The names in ``first`` come first (in that order), then the others sorted; every entry has
    the 1980-01-01 timestamp, Unix permissions (0755 under ``binaries/``, else 0644) and is
    deflated at level 9, except the names for which ``stored(name)`` is true (kept
    uncompressed, e.g. archives inside an archive). The file is written next to ``path`` and
    renamed over it at the end (never half-written).
    """
    rank = {n: i for i, n in enumerate(first)}
    names = sorted(entries, key=lambda n: (rank.get(n, len(rank)), n))
    tmp = path.with_name(path.name + ".tmp")
    with zipfile.ZipFile(tmp, "w") as z:
        for n in names:
            zi = zipfile.ZipInfo(n, date_time=_ZIP_DATE)
            zi.compress_type = zipfile.ZIP_STORED if stored(n) else zipfile.ZIP_DEFLATED
            zi.create_system = 3
            zi.external_attr = (0o100755 if n.startswith("binaries/") else 0o100644) << 16
            z.writestr(zi, entries[n], compresslevel=9)
    tmp.replace(path)
