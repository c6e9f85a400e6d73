"""Shared fixtures: the four FMUs built once per test session from the working tree, and the
C test hosts of tests/c_host compiled once."""

from __future__ import annotations

import subprocess
from collections.abc import Callable
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


#: the C test hosts (tests/c_host/<name>.c) and the official FMI 2.0 headers they include
C_HOST = Path(__file__).parent / "c_host"
FMI_HEADERS = Path(__file__).parents[1] / "fmus" / "shim"


@pytest.fixture(scope="session")
def c_host(tmp_path_factory: pytest.TempPathFactory) -> Callable[[str], Path]:
    """``c_host("fmu_host")``: tests/c_host/fmu_host.c compiled with gcc (warnings are
    errors), once per session; the executable's path."""
    built: dict[str, Path] = {}

    def build(name: str) -> Path:
        if name not in built:
            exe = tmp_path_factory.mktemp(name) / name
            r = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-O2",
                                f"-I{FMI_HEADERS}", "-o", str(exe), str(C_HOST / f"{name}.c"),
                                "-ldl"], capture_output=True, text=True, timeout=120)
            assert r.returncode == 0, r.stderr
            built[name] = exe
        return built[name]

    return build
