"""The bundle hash: digest of a bundled package's sources (build time: names the package;
run time: the slave checks that the package it imported is the one the FMU was built with).

Bundled into every FMU: relative imports only.
"""

from __future__ import annotations

import hashlib
import sys
from collections.abc import Iterable
from pathlib import Path


def source_digest(files: Iterable[tuple[str, bytes]]) -> str:
    """sha256 over (relative path, content) pairs, sorted by path (the bundle hash)."""
    h = hashlib.sha256()
    for rel, data in sorted(files):
        h.update(rel.encode() + b"\0" + len(data).to_bytes(8, "little") + data)
    return h.hexdigest()


def bundle_files(root: Path) -> list[tuple[str, bytes]]:
    """The hashed files of a bundled package: every ``*.py`` except the top ``__init__.py``
    (which carries the hash itself)."""
    files = []
    for f in sorted(root.rglob("*.py")):
        rel = f.relative_to(root).as_posix()
        if rel != "__init__.py" and "__pycache__" not in rel:
            files.append((rel, f.read_bytes()))
    return files


_VERIFIED: dict[str, str] = {}


def verify_bundle(package: str, expected: str) -> str | None:
    """Check that the imported ``package`` is the bundle with hash ``expected``.

    Returns None if it is, else an error message naming both versions. The check re-hashes
    the package's source files once per process.
    """
    mod = sys.modules.get(package)
    if mod is None:
        return f"bundled package {package} (hash {expected[:12]}) is not imported"
    declared = getattr(mod, "BUNDLE_HASH", None)
    root = Path(mod.__file__).parent
    key = str(root)
    if key not in _VERIFIED:
        _VERIFIED[key] = source_digest(bundle_files(root))
    actual = _VERIFIED[key]
    if declared != expected or actual != expected:
        return (f"bundled code mismatch: this FMU was built with {package} hash {expected[:12]}, "
                f"but the imported {package} (from {root}) declares "
                f"{str(declared)[:12]} and its sources hash to {actual[:12]}")
    return None


def add_bundle_root(package: str, resources: str | None) -> None:
    """Let an already imported bundle ``package`` also import from this instance's copy.

    All instances of one FMU in a process share the package (``sys.modules``), imported from
    the resources folder of the first instance. A host may free that instance and delete its
    extracted folder (fmpy's ``simulate_fmu``, a campaign worker between campaigns) and then
    instantiate the FMU again from a new folder: a module the bundle imports only on demand
    (the IMM filter, models/filters/registry.py) would then not be found. Each instance puts
    its own folder first on the search path (``__path__``) of every imported package of the
    bundle, keeping the others: the sources are the same (same bundle hash, checked by
    :func:`verify_bundle`), so any folder still present serves.
    """
    if not resources:
        return
    loc = resources[7:] if resources.startswith("file://") else resources
    root = Path(loc) / package
    if package not in sys.modules or not root.is_dir():
        return
    prefix = package + "."
    for name, mod in sys.modules.copy().items():  # copy(): atomic (see state_codec)
        if name != package and not name.startswith(prefix):
            continue
        path = getattr(mod, "__path__", None)
        if not isinstance(path, list):
            continue
        sub = root.joinpath(*name.split(".")[1:])
        if str(sub) not in path and sub.is_dir():
            path.insert(0, str(sub))
