"""Zip archives (FMUs, SSP archives) extracted once per content and process."""

from __future__ import annotations

import atexit
import hashlib
import shutil
import tempfile
import zipfile
from pathlib import Path

from .errors import AxirError

#: SHA-256 of an archive's bytes → the directory it was extracted to (this process)
_EXTRACTED: dict[str, Path] = {}
_EXIT_HOOK: list[bool] = []


def remove_extracted() -> None:
    """Remove every directory this process extracted (call once the FMUs loaded from them are
    freed; the CLI does at exit, also after errors and signals, and so does ``atexit``)."""
    while _EXTRACTED:
        _digest, target = _EXTRACTED.popitem()
        shutil.rmtree(target, ignore_errors=True)


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes (identifies what was built or exported)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def extract_once(path: Path, what: str, error: type[AxirError] = AxirError) -> Path:
    """Extract the zip archive ``path`` once per content (cached per process) and return the
    directory. ``error`` (naming ``path``, ``what`` it should be) for a file that is not a zip
    archive or has a member outside the directory (absolute or ``..`` name)."""
    path = Path(path)
    digest = file_digest(path)
    cached = _EXTRACTED.get(digest)
    if cached is not None and cached.is_dir():
        return cached
    if not _EXIT_HOOK:
        atexit.register(remove_extracted)
        _EXIT_HOOK.append(True)
    target = Path(tempfile.mkdtemp(prefix=f"axir_{path.stem}_"))
    try:
        with zipfile.ZipFile(path) as z:
            for name in z.namelist():
                if name.startswith("/") or ".." in Path(name).parts:
                    raise error(f"{path}: unsafe member name {name!r}")
            z.extractall(target)
    except zipfile.BadZipFile as e:
        shutil.rmtree(target, ignore_errors=True)
        raise error(f"{path} is not {what} (not a zip archive): {e}") from None
    except BaseException:
        shutil.rmtree(target, ignore_errors=True)
        raise
    _EXTRACTED[digest] = target
    return target
