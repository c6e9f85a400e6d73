"""SSP 1.0 export and import (``axir export-ssp``, ``axir run radar.ssp``).

The archive is checked by tools that are not ours: the SSP 1.0 XML schemas and fmpy's SSP
reader (``fmpy.ssp.ssd.read_ssd``, which validates the .ssd and every referenced .ssv against
the schemas). Running it in libcosim is tests/test_libcosim.py.
"""

from __future__ import annotations

import copy
import re
import subprocess
import sys
import zipfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssd

from axir.models.system import unit_seed
from axir.orchestrator.errors import AxirError, ScenarioError
from axir.orchestrator.fmi import load_model_description
from axir.orchestrator.run import run_scenario
from axir.orchestrator.scenario import load_scenario
from axir.orchestrator.ssp.export import DEFAULT_STEP, export_ssp_archive
from axir.orchestrator.ssp.importer import load_ssp
from axir.orchestrator.ssp.validate import validate_ssp
from axir.orchestrator.system import expand_connections

UNITS = ("Pedestal", "TargetGenerator", "Tracker", "RadarManager")
DURATION = 0.5  # [s] stop time written into the archive


@pytest.fixture(scope="module")
def archive(fmu_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("ssp") / "radar.ssp"
    return export_ssp_archive(load_scenario("closed-loop"), fmu_dir, out, duration=DURATION)


def test_archive_layout_and_fmus_byte_identical(archive: Path, fmu_dir: Path) -> None:
    with zipfile.ZipFile(archive) as z:
        names = set(z.namelist())
        assert names == {"SystemStructure.ssd", *(f"resources/{u}.fmu" for u in UNITS),
                         *(f"resources/{u}.ssv" for u in UNITS)}
        for u in UNITS:
            assert z.read(f"resources/{u}.fmu") == (fmu_dir / f"{u}.fmu").read_bytes()


def test_archive_passes_the_ssp_schemas(archive: Path) -> None:
    assert validate_ssp(archive) == []


def test_fmpy_reads_the_archive(archive: Path, fmu_dir: Path) -> None:
    """fmpy's SSP reader (schema-validating) sees the system, the connections and the
    parameter sets: the scenario's values, the per-unit seeds and the Jacobi gate latency."""
    ssd = read_ssd(str(archive), validate=True)
    assert ssd.version == "1.0" and ssd.name == "closed-loop"
    comps = {c.name: c for c in ssd.system.elements}
    assert list(comps) == list(UNITS)
    assert {c.source for c in comps.values()} == {f"resources/{u}.fmu" for u in UNITS}
    sc = load_scenario("closed-loop")
    mds = {u: load_model_description(fmu_dir / f"{u}.fmu") for u in UNITS}
    expected, problems = expand_connections(sc.connections, mds)
    assert problems == []
    got = {(c.startElement, c.startConnector, c.endElement, c.endConnector)
           for c in ssd.system.connections}
    assert got == {(c.src_unit, c.src_var, c.dst_unit, c.dst_var) for c in expected}
    assert len(got) == len(expected) > 240  # 192 beams + 48 sums + the scalar loop
    for u in UNITS:
        (binding,) = comps[u].parameterBindings
        assert binding.source == f"resources/{u}.ssv"
        params = {p.name: p.value for s in binding.parameterValues for p in s.parameters}
        want = {k: v for k, v in sc.units[u]["parameters"].items()}
        if any(v.name == "seed" for v in mds[u].modelVariables):
            want["seed"] = unit_seed(sc.seed, u)
        if u == "Tracker":
            assert sc.units[u]["parameters"]["gate_latency"] == 1  # the TOML: Gauss-Seidel
            want["gate_latency"] = 2  # the archive: Jacobi
        assert set(params) == set(want), u
        for k, v in want.items():
            assert float(params[k]) == float(v), (u, k)


def test_export_is_reproducible(archive: Path, fmu_dir: Path, tmp_path: Path) -> None:
    again = export_ssp_archive(load_scenario("closed-loop"), fmu_dir, tmp_path / "again.ssp",
                               duration=DURATION)
    assert again.read_bytes() == archive.read_bytes()


def test_import_gives_the_scenario(archive: Path) -> None:
    sc = load_scenario(archive)  # load_scenario dispatches .ssp to load_ssp
    toml = load_scenario("closed-loop")
    assert sc.name == "closed-loop" and sc.source == str(archive)
    assert sc.algorithm == "jacobi" and sc.step == DEFAULT_STEP and sc.duration == DURATION
    assert sc.order == list(UNITS) and sc.record == toml.record
    assert sc.decimation == toml.decimation and sc.seed == toml.seed
    for u in UNITS:
        assert Path(sc.units[u]["fmu"]).name == f"{u}.fmu"
        want = dict(toml.units[u]["parameters"])
        if u == "Tracker":
            want["gate_latency"] = 2
        # the derived seeds are dropped again (re-derived by the master: --seed works)
        assert sc.units[u]["parameters"] == want, u


def test_ssd_in_a_directory_loads_too(archive: Path, tmp_path: Path) -> None:
    with zipfile.ZipFile(archive) as z:
        z.extractall(tmp_path)
    a, b = load_scenario(tmp_path / "SystemStructure.ssd"), load_ssp(archive)
    assert a.units.keys() == b.units.keys() and a.connections == b.connections
    assert a.units["Tracker"]["parameters"] == b.units["Tracker"]["parameters"]


def test_our_master_runs_the_archive_as_the_scenario(archive: Path, fmu_dir: Path) -> None:
    """``axir run radar.ssp`` = the TOML scenario run fixed-step Jacobi with the Jacobi gate
    latency: byte-identical records (same FMUs, parameters, seeds, connections, order)."""
    d = 0.05
    from_ssp = load_scenario(archive)
    toml = load_scenario("closed-loop")
    units = copy.deepcopy(toml.units)
    units["Tracker"]["parameters"]["gate_latency"] = 2
    toml = replace(toml, units=units, algorithm="jacobi", step=DEFAULT_STEP)
    _, rec_ssp = run_scenario(from_ssp, Path("/nonexistent"), None, duration=d, progress=False)
    _, rec_toml = run_scenario(toml, fmu_dir, None, duration=d, progress=False)
    assert rec_ssp.variables == rec_toml.variables
    assert rec_ssp.n == rec_toml.n > 1
    np.testing.assert_array_equal(rec_ssp.data, rec_toml.data)


# ------------------------------------------------------------------ errors
def test_export_errors_name_the_problem(fmu_dir: Path, tmp_path: Path) -> None:
    sc = load_scenario("closed-loop")
    with pytest.raises(AxirError, match=r"FMU file not found: .*\.fmu \(unit "):
        export_ssp_archive(sc, tmp_path, tmp_path / "x.ssp")
    with pytest.raises(AxirError, match=r"must end in \.ssp"):
        export_ssp_archive(sc, fmu_dir, tmp_path / "x.zip")
    units = copy.deepcopy(sc.units)
    units["Tracker"]["parameters"]["no_such_parameter"] = 1.0
    with pytest.raises(AxirError, match="Tracker: 'no_such_parameter' is not a parameter"):
        export_ssp_archive(replace(sc, units=units), fmu_dir, tmp_path / "x.ssp")
    units = copy.deepcopy(sc.units)
    units["Tracker"]["parameters"]["n_max"] = 2.5
    with pytest.raises(AxirError, match=r"Tracker\.n_max: Integer parameter, got 2\.5"):
        export_ssp_archive(replace(sc, units=units), fmu_dir, tmp_path / "x.ssp")


def _edited(archive: Path, tmp_path: Path, old: str, new: str) -> Path:
    with zipfile.ZipFile(archive) as z:
        z.extractall(tmp_path)
    ssd = tmp_path / "SystemStructure.ssd"
    text = ssd.read_text()
    assert old in text
    ssd.write_text(text.replace(old, new, 1))
    return ssd


@pytest.mark.parametrize(("old", "new", "message"), [
    ('baseStepSize="0.0001"', 'baseStepSize="-1"', "no fixed step"),
    ('startTime="0.0"', 'startTime="1.0"', "startTime 1.0"),
    ('source="resources/Tracker.fmu"', 'source="resources/Missing.fmu"',
     "component Tracker: FMU not found: resources/Missing.fmu"),
    ('startConnector="cmd.az"', 'startConnector="cmd.azz"',
     "component Tracker declares no connector 'cmd.azz'"),
    ('source="resources/Tracker.ssv"', 'source="resources/Nope.ssv"',
     "parameter set of Tracker not found"),
])
def test_import_errors_name_the_problem(archive: Path, tmp_path: Path, old: str, new: str,
                                        message: str) -> None:
    ssd = _edited(archive, tmp_path, old, new)
    with pytest.raises(ScenarioError, match=re.escape(message)):
        load_ssp(ssd)


def test_import_rejects_transformations_and_non_archives(archive: Path, tmp_path: Path) -> None:
    ssd = _edited(archive, tmp_path, 'endConnector="cmd.az"/>',
                  'endConnector="cmd.az"><ssc:LinearTransformation factor="2"/>'
                  "</ssd:Connection>")
    with pytest.raises(ScenarioError, match="transformations are not supported"):
        load_ssp(ssd)
    bad = tmp_path / "bad.ssp"
    bad.write_text("not a zip")
    with pytest.raises(ScenarioError, match="not an SSP archive"):
        load_ssp(bad)
    with pytest.raises(ScenarioError, match="SSP file not found"):
        load_ssp(tmp_path / "missing.ssp")


def test_cli_export_ssp(fmu_dir: Path, tmp_path: Path) -> None:
    axir = [sys.executable, "-m", "axir.orchestrator.cli"]
    out = tmp_path / "radar.ssp"
    r = subprocess.run([*axir, "export-ssp", "-o", str(out), "--fmu-dir", str(fmu_dir),
                        "--duration", "0.2", "--step", "5e-5"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "validated against the SSP 1.0 schemas" in r.stdout
    sc = load_ssp(out)
    assert sc.step == 5e-5 and sc.duration == 0.2
    r = subprocess.run([*axir, "export-ssp", "-o", str(out), "--fmu-dir", str(tmp_path)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.startswith("error: FMU file not found")
    assert "Traceback" not in r.stderr
