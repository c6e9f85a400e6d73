"""Shared fixtures: the four FMUs built once per test session from the working tree."""

from __future__ import annotations

from pathlib import Path

import pytest

from axir.models.system import UNITS


@pytest.fixture(scope="session")
def fmu_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A directory holding the four freshly built FMUs (``<name>.fmu``), built once."""
    from axir.fmus.build import build_all

    d = tmp_path_factory.mktemp("fmus")
    built = build_all(d)
    assert sorted(p.name for p in built) == sorted(f"{n}.fmu" for n in UNITS)
    return d
