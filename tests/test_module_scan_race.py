"""The FMUs' scans of ``sys.modules`` survive a finaliser that imports in the middle of them.

A campaign worker once failed ``Pedestal fmi2Reset`` with "dictionary changed size during
iteration" (a Dask worker process: our run in one thread, the worker's event loop in another).
Instantiation scans ``sys.modules`` (:func:`axir.fmus.digest.add_bundle_root`; restoring a
state, :func:`axir.fmus.state_codec.state_classes`). Building a list of ``items()`` allocates
a tuple per item; a garbage collection there may run a finaliser, the finaliser (or another
thread it lets run) imports a module, and the scan fails. Here the finaliser adds a module to
``sys.modules`` itself, with the collector made to run on (nearly) every allocation: the scans
must complete and still see every module they should.
"""

from __future__ import annotations

import gc
import sys
import types
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import axir.models.pedestal  # noqa: F401  (a models module for state_classes to find)
from axir.fmus.digest import add_bundle_root
from axir.fmus.state_codec import state_classes


class _Importer:
    """Cyclic garbage whose finaliser 'imports' a fresh module and leaves the next such
    garbage behind: while :attr:`active`, every collection (with threshold 1: nearly every
    allocation, the scans' own included) changes the size of ``sys.modules``."""

    made = 0
    active = False

    def __init__(self) -> None:
        self.me = self  # a cycle: only the collector frees it

    def __del__(self) -> None:
        if not _Importer.active:
            return
        _Importer.made += 1
        sys.modules[f"_axir_scan_race_{_Importer.made}"] = types.ModuleType("x")
        _Importer()


@contextmanager
def _finalisers_everywhere() -> Iterator[None]:
    old = gc.get_threshold()
    gc.collect()
    _Importer.active = True
    gc.set_threshold(1, 1, 1)
    _Importer()
    try:
        yield
    finally:
        _Importer.active = False
        gc.set_threshold(*old)
        gc.collect()
        for k in [k for k in sys.modules if k.startswith("_axir_scan_race_")]:
            del sys.modules[k]


def _under_fire(scan: Callable[[], object]) -> object:
    """``scan()`` 100 times under :func:`_finalisers_everywhere` (the former
    ``list(sys.modules.items())`` failed ≈ 10 % of such scans); its last result."""
    with _finalisers_everywhere():
        out = None
        for _ in range(100):
            out = scan()
        assert _Importer.made > 100  # the finalisers did run during the scans
    return out


def test_state_classes_survives_imports_during_the_scan() -> None:
    found = _under_fire(lambda: state_classes("axir"))
    assert isinstance(found, dict)
    assert "models.pedestal:Pedestal" in found


def test_add_bundle_root_survives_imports_during_the_scan(tmp_path: Path) -> None:
    # a bundle-like package whose sub-packages have a folder under the resources path
    (tmp_path / "axir" / "models").mkdir(parents=True)
    pkg_models = sys.modules["axir.models"]
    path_before = list(pkg_models.__path__)
    try:
        _under_fire(lambda: add_bundle_root("axir", "file://" + str(tmp_path)))
        assert str(tmp_path / "axir" / "models") in pkg_models.__path__
    finally:
        pkg_models.__path__[:] = path_before
