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
