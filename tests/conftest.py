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


# pythonfmu 0.7.0's Linux binary can corrupt the heap during interpreter finalization after its
# FMUs were used in the process (glibc abort "corrupted double-linked list"; measured: 3/100
# CLI runs with normal finalization, 0/100 ending with os._exit; see orchestrator/cli.py:main).
# The test session hosts FMUs in-process too, so once pytest has written its report the
# process ends with os._exit and pytest's exit status instead of running the finalizers.
_EXIT_STATUS: list[int] = []


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    _EXIT_STATUS.append(int(exitstatus))


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config: pytest.Config) -> None:
    if _EXIT_STATUS and _fmus_loaded():
        import os
        import sys

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_EXIT_STATUS[-1])


def _fmus_loaded() -> bool:
    """True when a pythonfmu slave ran in this process (its bundled package is imported)."""
    import sys

    return any(name.startswith("_axir_") for name in sys.modules)
