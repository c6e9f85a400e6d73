"""A non-Python host: tests/c_host/fmu_host.c (dlopen + the FMI 2.0 C API, compiled with gcc)
runs Tracker.fmu on inputs recorded from our master and must reproduce its outputs exactly.

The inputs are the Tracker's 200 inputs (beams, pedestal angles, mode, gains, offsets, gate)
recorded at every step of the closed loop (our master, Gauss-Seidel, the manager's variable
PRI) for the first 0.06 s (≈ 550 steps: acquisition, tentative, confirmed); the outputs
compared are all 79 Tracker outputs at every step, bit for bit (the C host writes %.17g).

The host process gets nothing but PATH in its environment (no LD_PRELOAD, PYTHONHOME or
PYTHONPATH): the FMU's C shim loads and initializes the Python recorded at build time
(docs/other_tools.md). The host ends main with a plain ``return 0``.
"""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy

from axir.orchestrator.fmi import load_model_description
from axir.orchestrator.run import run_scenario
from axir.orchestrator.scenario import load_scenario

DURATION = 0.06  # [s] ≈ 550 PRI steps
KIND = {"Real": "R", "Integer": "I", "Boolean": "B", "String": "S"}

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not found")


def host_environment() -> dict[str, str]:
    """What a non-Python host needs to run the axir FMUs: nothing (docs/other_tools.md)."""
    return {"PATH": "/usr/bin:/bin"}


def legacy_environment() -> dict[str, str]:
    """The three variables non-Python hosts needed before the shim loaded Python itself."""
    libpython = Path(sysconfig.get_config_var("LIBDIR")) / sysconfig.get_config_var(
        "INSTSONAME")
    site = {str(Path(m.__file__).parent.parent) for m in (np, scipy)}
    return {
        "PATH": "/usr/bin:/bin",
        "LD_PRELOAD": str(libpython),
        "PYTHONHOME": sys.base_prefix,
        "PYTHONPATH": os.pathsep.join(sorted(site)),
    }


@pytest.fixture(scope="module")
def host(c_host) -> Path:
    return c_host("fmu_host")


@pytest.fixture(scope="module")
def recorded(fmu_dir: Path, tmp_path_factory: pytest.TempPathFactory):
    """Our master's run: the Tracker's inputs and outputs at every step, written as the C
    host's input files. Row k of the record holds the inputs used during step k (set just
    before the Tracker stepped) and the outputs after it."""
    work = tmp_path_factory.mktemp("c_host_run")
    md = load_model_description(fmu_dir / "Tracker.fmu")
    ins = [v for v in md.modelVariables if v.causality == "input"]
    outs = [v for v in md.modelVariables if v.causality == "output"]
    sc = load_scenario("closed-loop")
    sc = replace(sc, record=[f"Tracker.{v.name}" for v in ins + outs], decimation=1)
    _, rec = run_scenario(sc, fmu_dir, None, duration=DURATION, progress=False)
    d = rec.data
    variables = {v.name: v for v in md.modelVariables}
    with open(work / "params.txt", "w") as f:
        for name, value in sc.units["Tracker"]["parameters"].items():
            v = variables[name]
            text = str(int(value)) if v.type in ("Integer", "Boolean") else repr(float(value))
            f.write(f"{KIND[v.type]} {v.valueReference} {text}\n")
    with open(work / "inputs.csv", "w") as f:
        f.write(",".join(["time", *(f"{KIND[v.type]}{v.valueReference}" for v in ins)]) + "\n")
        for k in range(1, rec.n):  # step k runs from t_{k-1} to t_k with the inputs of row k
            f.write(",".join(repr(float(x)) for x in [d[k - 1, 0], *d[k, 1:1 + len(ins)]])
                    + "\n")
    with open(work / "outputs.txt", "w") as f:
        f.writelines(f"{KIND[v.type]} {v.valueReference} {v.name}\n" for v in outs)
    with zipfile.ZipFile(fmu_dir / "Tracker.fmu") as z:
        z.extractall(work / "Tracker")
    expected = np.column_stack([d[1:, 0], d[1:, 1 + len(ins):]])
    return work, md, [v.name for v in outs], repr(float(d[-1, 0])), expected


def run_host(host: Path, work: Path, md, stop: str, env: dict[str, str]
             ) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(host), str(work / "Tracker"), md.coSimulation.modelIdentifier, md.guid,
         "params.txt", "inputs.csv", "outputs.txt", stop, "out.csv"],
        cwd=work, env=env, capture_output=True, text=True, timeout=300)


def test_c_host_reproduces_our_master_bit_for_bit(host: Path, recorded) -> None:
    work, md, names, stop, expected = recorded
    r = run_host(host, work, md, stop, host_environment())
    assert r.returncode == 0, r.stderr[-2000:]
    n = len(expected)
    assert f"fmu_host: {n} steps" in r.stderr
    assert n > 400
    with open(work / "out.csv", newline="") as f:
        header = next(csv.reader(f))
    assert header == ["time", *names]
    got = np.loadtxt(work / "out.csv", delimiter=",", skiprows=1, ndmin=2)
    assert got.shape == expected.shape
    np.testing.assert_array_equal(got[:, 0], expected[:, 0])
    differing = [names[j] for j in range(len(names))
                 if not np.array_equal(got[:, 1 + j], expected[:, 1 + j])]
    assert differing == []
    # the inputs covered the acquisition -> confirmed sequence, so the outputs moved
    mode_col = np.loadtxt(work / "inputs.csv", delimiter=",", skiprows=1, ndmin=2)[
        :, 1 + [v.name for v in md.modelVariables if v.causality == "input"].index("mode")]
    assert set(np.unique(mode_col)) == {0, 1, 2}
    assert got[:, 1 + names.index("track.valid")].any()


def test_legacy_environment_still_works(host: Path, recorded) -> None:
    """A host set up for the old FMUs (LD_PRELOAD of libpython, PYTHONHOME, PYTHONPATH) runs
    the new ones too: the shim finds libpython's symbols in the process, initializes that
    Python with the recorded settings (the variables are ignored) and the outputs are the
    same."""
    work, md, _, stop, expected = recorded
    r = run_host(host, work, md, stop, legacy_environment())
    assert r.returncode == 0, r.stderr[-2000:]
    got = np.loadtxt(work / "out.csv", delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_array_equal(got, expected)
