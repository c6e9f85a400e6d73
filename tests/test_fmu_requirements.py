"""Each FMU runs on a Python that has only what ``axir requirements`` says it needs.

A fresh venv of the build interpreter's base Python (no pip, no site-packages of ours) gets
exactly the packages the FMU's recorded requirements name for a configuration, linked from
this environment; the FMU then runs in a non-Python C host (tests/c_host/fmu_host.c, nothing
in the environment but ``PATH`` and ``AXIR_FMU_PYTHON``). The negative cases show the
environment really is minimal and that a missing package is named: the default Tracker must
not need filterpy (it did: issue 10), an IMM Tracker must, and says so.
"""

from __future__ import annotations

import importlib.metadata
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

from axir.models.system import UNITS
from axir.orchestrator.fmi import load_model_description
from axir.orchestrator.requirements import fmu_requirements

STEPS = 10

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not found")]


def minimal_python(root: Path, packages: list[str]) -> Path:
    """A venv at ``root`` whose only third-party packages are ``packages`` (with their
    top-level folders such as ``numpy.libs``), linked from this environment; its python."""
    subprocess.run([sys._base_executable, "-m", "venv", "--without-pip", str(root)],
                   check=True, capture_output=True, timeout=300)
    lib = root / "linked"
    lib.mkdir()
    dists = importlib.metadata.packages_distributions()
    for pkg in packages:
        for dist in dists[pkg]:
            files = importlib.metadata.distribution(dist).files or []
            for top in {f.parts[0] for f in files if f.parts[0] != ".."}:
                src = Path(sysconfig.get_paths()["purelib"]) / top
                if src.exists() and not (lib / top).exists():
                    (lib / top).symlink_to(src)
    site = next((root / "lib").glob("python3*/site-packages"))
    (site / "axir_test_minimal.pth").write_text(f"{lib}\n")
    return root / "bin" / "python"


@pytest.fixture(scope="module")
def fmu_host(c_host) -> Path:
    return c_host("fmu_host")


def run_fmu(host: Path, fmu: Path, work: Path, python: Path, params: dict[str, str]
            ) -> subprocess.CompletedProcess[str]:
    """``STEPS`` steps of ``fmu`` with String ``params`` in the C host on ``python``."""
    md = load_model_description(fmu)
    d = work / md.modelName
    if not d.exists():
        with zipfile.ZipFile(fmu) as z:
            z.extractall(d)
    refs = {v.name: v.valueReference for v in md.modelVariables}
    (work / "params.txt").write_text("".join(f"S {refs[k]} {v}\n" for k, v in params.items()))
    (work / "inputs.csv").write_text("time\n" + "".join(f"{k * 1e-4!r}\n" for k in range(STEPS)))
    out = next(v for v in md.modelVariables if v.causality == "output" and v.type == "Real")
    (work / "outputs.txt").write_text(f"R {out.valueReference} {out.name}\n")
    return subprocess.run(
        [str(host), str(d), md.coSimulation.modelIdentifier, md.guid, "params.txt",
         "inputs.csv", "outputs.txt", repr(STEPS * 1e-4), "out.csv"], cwd=work,
        env={"PATH": "/usr/bin:/bin", "AXIR_FMU_PYTHON": str(python)},
        capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("name", UNITS)
def test_each_fmu_runs_on_exactly_its_requirements(fmu_dir: Path, fmu_host: Path,
                                                   tmp_path: Path, name: str) -> None:
    packages, _ = fmu_requirements(fmu_dir / f"{name}.fmu", {})
    assert "numpy" in packages and "filterpy" not in packages
    python = minimal_python(tmp_path / "py", packages)
    r = run_fmu(fmu_host, fmu_dir / f"{name}.fmu", tmp_path, python, {})
    assert r.returncode == 0, r.stderr[-2000:]
    assert f"fmu_host: {STEPS} steps" in r.stderr
    # the environment really lacks what was not asked for
    probe = subprocess.run([str(python), "-c", "import filterpy"], capture_output=True)
    assert probe.returncode != 0


def test_missing_required_package_is_named(fmu_dir: Path, fmu_host: Path,
                                           tmp_path: Path) -> None:
    python = minimal_python(tmp_path / "py", ["numpy"])  # Tracker also needs scipy
    r = run_fmu(fmu_host, fmu_dir / "Tracker.fmu", tmp_path, python, {})
    assert r.returncode != 0
    assert "scipy" in r.stderr


def test_imm_tracker_needs_filterpy_and_says_so(fmu_dir: Path, fmu_host: Path,
                                                tmp_path: Path) -> None:
    fmu = fmu_dir / "Tracker.fmu"
    imm = {"filter_x": "imm"}
    packages, _ = fmu_requirements(fmu, imm)
    assert "filterpy" in packages
    base = [p for p in packages if p != "filterpy"]
    python = minimal_python(tmp_path / "without", base)
    r = run_fmu(fmu_host, fmu, tmp_path, python, imm)
    assert r.returncode != 0
    assert "filterpy" in r.stderr and "pip install filterpy" in r.stderr
    python = minimal_python(tmp_path / "with", packages)
    r = run_fmu(fmu_host, fmu, tmp_path, python, imm)
    assert r.returncode == 0, r.stderr[-2000:]
