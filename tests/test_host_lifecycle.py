"""Non-Python hosts load, run and unload the FMUs and exit normally, in an empty environment.

tests/c_host/lifecycle_host.c (dlopen + the FMI 2.0 C API, ``return 0`` at the end of main,
so the process's exit handlers run) is run as a real process with nothing in its environment
but ``PATH`` (no ``LD_PRELOAD``, ``PYTHONHOME``, ``PYTHONPATH``): the shim loads the Python
recorded in the FMU. Scenarios, each repeated ``AXIR_LIFECYCLE_RUNS`` times (default 10; the
50-run figures in docs/other_tools.md come from ``AXIR_LIFECYCLE_RUNS=50``):

* ``once``: one lifecycle; ``twice``: two lifecycles in one process (same library handle);
  ``reload``: a lifecycle, ``dlclose``, ``dlopen`` again, a second lifecycle — for each of
  the four FMUs;
* ``pair``: Tracker and Pedestal loaded, instantiated and stepped at once.

Every run must exit with code 0, print its last stdout line (stdout is a pipe, so it is
flushed by the exit handlers: a crash there loses it), log nothing with status Error/Fatal,
and a second lifecycle must give the same outputs as the first.

Before the shim initialized Python itself (pythonfmu finalized it from the exit handlers),
the same host crashed with SIGSEGV at exit in 40-90 % of the runs (docs/other_tools.md §1.4).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

FMUS = ("TargetGenerator", "Tracker", "Pedestal", "RadarManager")
RUNS = int(os.environ.get("AXIR_LIFECYCLE_RUNS", "10"))
STEPS = 20
#: nothing from the test process: the FMU must find its Python itself
CLEAN_ENV = {"PATH": "/usr/bin:/bin"}
SCENARIOS = [(mode, (name,)) for name in FMUS for mode in ("once", "twice", "reload")] + [
    ("pair", ("Tracker", "Pedestal"))]

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not found")


@pytest.fixture(scope="module")
def lifecycle_host(c_host) -> Path:
    return c_host("lifecycle_host")


@pytest.fixture(scope="module")
def extracted(fmu_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("lifecycle_fmus")
    for name in FMUS:
        with zipfile.ZipFile(fmu_dir / f"{name}.fmu") as z:
            z.extractall(d / name)
    return d


def run(host: Path, mode: str, dirs: list[Path], env: dict[str, str] | None = None
        ) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(host), mode, str(STEPS), *map(str, dirs)],
                          env=CLEAN_ENV if env is None else env, capture_output=True,
                          text=True, timeout=300)


@pytest.mark.slow  # ≈130 processes of ≈1 s CPU each (import scipy.stats)
def test_lifecycles_exit_normally(lifecycle_host: Path, extracted: Path) -> None:
    jobs = [(mode, names) for mode, names in SCENARIOS for _ in range(RUNS)]
    with ThreadPoolExecutor(max_workers=2) as pool:  # 2 cores, shared
        results = list(pool.map(
            lambda job: (job, run(lifecycle_host, job[0], [extracted / n for n in job[1]])),
            jobs))
    failures: dict[str, list[str]] = {}
    for (mode, names), r in results:
        key = f"{mode} {'+'.join(names)}"
        lines = r.stdout.splitlines()
        problem = ""
        if r.returncode != 0:
            problem = f"exit code {r.returncode}"
        elif not lines or lines[-1] != f"lifecycle_host: {mode} done":
            problem = f"stdout tail lost: {r.stdout[-200:]!r}"
        elif "[status 3]" in r.stderr or "[status 4]" in r.stderr:
            problem = f"error logged: {r.stderr[-500:]}"
        elif mode in ("twice", "reload"):
            sums = [line.split("checksum ")[1] for line in lines if "lifecycle" in line[:40]
                    and "checksum" in line]
            if len(sums) != 2 or sums[0] != sums[1]:
                problem = f"second lifecycle differs: {lines}"
        if problem:
            failures.setdefault(key, []).append(problem + " | " + r.stderr[-300:])
    for mode, names in SCENARIOS:  # shown with pytest -s
        key = f"{mode} {'+'.join(names)}"
        print(f"{key}: exit code 0 and complete output in {RUNS - len(failures.get(key, []))}"
              f"/{RUNS} runs")
    summary = {k: f"{len(v)}/{RUNS} failed, first: {v[0]}" for k, v in failures.items()}
    assert not failures, summary


def test_failed_instantiation_message_with_logging_off(lifecycle_host: Path, extracted: Path,
                                                       tmp_path: Path) -> None:
    """A package the FMU needs is missing: fmi2Instantiate returns NULL after a Fatal
    message naming the package and the pip command, delivered although the host
    instantiated with loggingOn = false; the host then exits normally (code 2, its choice)."""
    d = tmp_path / "Pedestal"
    shutil.copytree(extracted / "Pedestal", d)
    cfg = d / "resources" / "axir_python.txt"
    cfg.write_text(cfg.read_text() + "require=axir_no_such_package\n")
    r = run(lifecycle_host, "once", [d])
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "[status 4][logStatusFatal]" in r.stderr
    assert "cannot import axir_no_such_package" in r.stderr
    assert "-m pip install numpy axir_no_such_package" in r.stderr
    assert "AXIR_FMU_PYTHON" in r.stderr
    assert "error: Pedestal: fmi2Instantiate failed" in r.stderr


def test_unusable_override_is_reported(lifecycle_host: Path, extracted: Path) -> None:
    r = run(lifecycle_host, "once", [extracted / "Pedestal"],
            {**CLEAN_ENV, "AXIR_FMU_PYTHON": "/nonexistent/python3"})
    assert r.returncode == 2
    assert "cannot run AXIR_FMU_PYTHON=/nonexistent/python3" in r.stderr


def test_override_with_the_build_python(lifecycle_host: Path, extracted: Path) -> None:
    """AXIR_FMU_PYTHON names an interpreter; the shim derives libpython, home and sys.path
    by running the FMU's probe script with it (here: the interpreter running the tests)."""
    import sys

    r = run(lifecycle_host, "pair", [extracted / "Tracker", extracted / "Pedestal"],
            {**CLEAN_ENV, "AXIR_FMU_PYTHON": sys.executable})
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[-1] == "lifecycle_host: pair done"
