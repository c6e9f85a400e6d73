"""FMU build infrastructure: layout, modelDescription validity, reproducibility, isolation."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from axir.fmus._base import AxirSlave, FmuSpec, layout, model_description_xml
from axir.fmus.build import INNER_SUFFIX, build_fmu, collect_sources
from axir.models.radar.params import Param
from axir.models.radar.ports import Port
from axir.models.radar.unit import Unit

BEAMS = ("up", "right", "down", "left")


# ------------------------------------------------------------------ stand-in Tracker-sized unit
class StandIn(Unit):
    """Tiny stand-in model with Tracker-like arrays: sum = Σ beams · gain, plus a counter."""

    PARAMS = (
        Param("gain", 1.0, "1", "output gain", low=0.0, high=10.0),
        Param("n_max", 5, "1", "counter limit", low=1, high=100),
        Param("flag", False, "", "a Boolean parameter"),
    )

    INPUTS = (Port("beam", float, "1", "beam magnitudes", shape=(4, 16, 3), labels=BEAMS),
              Port("ped.az", float, "rad", "pedestal azimuth"))
    OUTPUTS = (Port("sum", float, "1", "beam sum", shape=(16, 3)),
               Port("dev.az", float, "rad", "azimuth deviation"),
               Port("count", int, "1", "steps"),
               Port("maneuver", bool, "1", "flag"))

    def reset(self) -> None:
        self.count = 0

    def step(self, dt: float, inputs: dict[str, Any]) -> dict[str, Any]:
        self.count = min(self.count + 1, self.n_max)
        s = self.gain * np.asarray(inputs["beam"]).sum(axis=0)
        return {"sum": s, "dev.az": float(inputs["ped.az"]) * 2.0, "count": self.count,
                "maneuver": bool(self.flag)}


SPEC = FmuSpec(
    name="StandIn",
    model=StandIn,
    tunable=frozenset({"gain"}),
)


class StandInSlave(AxirSlave):
    SPEC = SPEC


def test_layout_structured_names() -> None:
    rows = layout(SPEC)
    names = [r.name for r in rows]
    assert names[:3] == ["gain", "n_max", "flag"]
    assert names[3] == "beam.up[1,1]" and names[4] == "beam.up[1,2]"
    assert names[3 + 48] == "beam.right[1,1]" and names[3 + 191] == "beam.left[16,3]"
    assert names.index("sum[3,2]") == 3 + 192 + 1 + 2 * 3 + 1
    assert len(rows) == 3 + 193 + 48 + 3
    assert {r.kind for r in rows if r.name in ("count", "n_max")} == {"Integer"}


def test_standin_model_description_validates(tmp_path: Path) -> None:
    (tmp_path / "modelDescription.xml").write_text(
        model_description_xml(SPEC, "{00000000-0000-0000-0000-000000000000}", "0", "test"))
    assert validate_fmu(str(tmp_path)) == []
    md = read_model_description(str(tmp_path))
    reals = [v for v in md.modelVariables if v.type == "Real"]
    assert all(v.unit for v in reals)
    assert all(v.variability == "discrete" for v in md.modelVariables
               if v.type != "Real" and v.causality != "parameter")


def test_slave_vectorised_io_in_process() -> None:
    """The slave class alone (no FMU): vectorised get/set, step, state, speed."""
    s = StandInSlave(instance_name="x", resources=".")
    rows = layout(SPEC)
    vr = {r.name: i for i, r in enumerate(rows)}
    beam_vrs = [vr[f"beam.{b}[{r},{f}]"] for b in BEAMS for r in range(1, 17) for f in (1, 2, 3)]
    sum_vrs = [vr[f"sum[{r},{f}]"] for r in range(1, 17) for f in (1, 2, 3)]
    s.set_real([vr["gain"]], [2.0])
    s.exit_initialization_mode()
    beams = np.arange(192, dtype=float).reshape(4, 16, 3)
    s.set_real(beam_vrs, beams.ravel().tolist())
    s.set_real([vr["ped.az"]], [0.25])
    assert s.do_step(0.0, 0.1)
    assert s.get_real(sum_vrs) == (2.0 * beams.sum(axis=0)).ravel().tolist()
    assert s.get_integer([vr["count"]]) == [1]
    st = s._get_fmu_state()
    blob = StandInSlave._fmu_state_to_bytes(st)
    s.do_step(0.1, 0.1)
    s._set_fmu_state(StandInSlave._fmu_state_from_bytes(blob))
    assert s.get_integer([vr["count"]]) == [1]
    s.set_real([vr["gain"]], [20.0])  # tunable, invalid -> error log, old value kept
    s.do_step(0.1, 0.1)
    assert s.get_real([vr["gain"]]) == [2.0]
    assert any("gain" in m.msg for m in s.log_queue)
    s.get_real([vr["count"]])  # wrong type: logged, no exception
    n = 2000
    t0 = time.perf_counter()
    for k in range(n):
        s.set_real(beam_vrs, beams.ravel().tolist())
        s.do_step(k * 0.1, 0.1)
        s.get_real(sum_vrs)
    us = (time.perf_counter() - t0) / n * 1e6
    print(f"Tracker-sized slave (192 in, 48 out), Python side only: {us:.1f} us/step")
    assert us < 1000


# ------------------------------------------------------------------ real builds
@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    a = build_fmu("Pedestal", tmp_path_factory.mktemp("a"))
    b = build_fmu("Pedestal", tmp_path_factory.mktemp("b"))
    return a, b


def test_fmpy_validate_no_problems(built: tuple[Path, Path]) -> None:
    assert validate_fmu(str(built[0])) == []


def test_reproducible_build_same_guid(built: tuple[Path, Path]) -> None:
    a, b = built
    assert a.read_bytes() == b.read_bytes()
    ga, gb = read_model_description(str(a)).guid, read_model_description(str(b)).guid
    assert ga == gb and ga.startswith("{")


def test_archive_content(built: tuple[Path, Path]) -> None:
    with zipfile.ZipFile(built[0]) as z:
        names = z.namelist()
        module = z.read("resources/slavemodule.txt").decode().strip()
    assert names[0] == "modelDescription.xml"
    assert module.startswith("axir_pedestal_") and f"resources/{module}.py" in names
    h8 = module.rsplit("_", 1)[1]
    assert f"resources/_axir_{h8}/models/pedestal.py" in names
    assert f"resources/_axir_{h8}/fmus/_base.py" in names
    assert not any("__pycache__" in n or n.endswith(".pyc") for n in names)
    md = read_model_description(str(built[0]))
    cs = md.coSimulation
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canHandleVariableCommunicationStepSize


def test_closure_only_needed_models() -> None:
    src = collect_sources("pedestal_fmu")
    assert "models/pedestal.py" in src and "models/radar/unit.py" in src
    assert "models/radar/antenna.py" not in src  # not imported by the pedestal


def test_fmutool_check(built: tuple[Path, Path]) -> None:
    exe = shutil.which("fmutool") or str(Path(sys.executable).parent / "fmutool")
    if not Path(exe).exists():
        pytest.skip("fmu-manipulation-toolbox (fmutool) not installed")
    r = subprocess.run([exe, "-input", str(built[0]), "-check"], capture_output=True,
                       text=True, timeout=120)
    text = r.stdout + r.stderr
    assert r.returncode == 0, text
    assert "ERROR" not in text.upper().replace("NO SEMANTIC ERROR", ""), text


LOAD_SCRIPT = """
import sys
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
import axir.models.pedestal  # the host has axir.models imported: the FMU must not use it
path = sys.argv[1]
md = read_model_description(path)
for i in range(int(sys.argv[2])):
    d = extract(path)
    f = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier="Pedestal",
                  instanceName=f"p{i}")
    f.instantiate(loggingOn=True)
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    for k in range(10):
        f.doStep(k * 1e-3, 1e-3)
    f.terminate()
    f.freeInstance()  # fmpy 0.3.32: fmi2FreeInstance, then freeLibrary()
mods = [m for m in sys.modules if m.startswith("_axir_")]
assert all("models.pedestal" not in m or m.startswith("_axir_") for m in mods)
print("OK", len(mods))
"""


def test_load_free_exit_code_10x(built: tuple[Path, Path]) -> None:
    """10 fresh processes each load/step/free the FMU (3 times) and must exit with 0."""
    for _ in range(10):
        r = subprocess.run([sys.executable, "-c", LOAD_SCRIPT, str(built[0]), "3"],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
        assert "OK" in r.stdout


TAMPER_SCRIPT = """
import sys
sys.path.insert(0, sys.argv[2])
from fmu_probe import run
print(run(sys.argv[1]))
"""


def test_tampered_bundle_detected(built: tuple[Path, Path], tmp_path: Path) -> None:
    """A bundle whose sources do not hash to the built-in hash refuses to run (Fatal-status log
    naming both versions at instantiation, delivered by the first call, which the C shim turns
    into fmi2Error: fmi2SetupExperiment; without the shim every doStep → discard) instead of
    silently running other code."""
    d = tmp_path / "x"
    with zipfile.ZipFile(built[0]) as z:
        z.extractall(d)
    base = next(d.glob("resources/_axir_*/fmus/_base.py"))
    base.write_text(base.read_text() + "\n# tampered\n")
    probe = tmp_path / "fmu_probe.py"
    probe.write_text(
        "from fmpy import read_model_description\n"
        "from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE\n"
        "logs = []\n"
        "def run(d):\n"
        "    md = read_model_description(d)\n"
        "    cb = fmi2CallbackFunctions()\n"
        "    cb.logger = fmi2CallbackLoggerTYPE(lambda c, n, s, cat, m: logs.append(m))\n"
        "    f = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier='Pedestal')\n"
        "    f.instantiate(loggingOn=True, callbacks=cb)\n"
        "    calls = [('setup', lambda: f.setupExperiment(startTime=0.0)),\n"
        "             ('enter', f.enterInitializationMode), ('exit', f.exitInitializationMode),\n"
        "             ('step', lambda: f.doStep(0.0, 1e-3))]\n"
        "    st = 'stepped'\n"
        "    for name, call in calls:\n"
        "        try:\n"
        "            call()\n"
        "        except Exception as e:\n"
        "            st = f'{name} refused {e.status}'\n"
        "            break\n"
        "    f.freeInstance()\n"
        "    return st + ' | ' + ' '.join(m.decode() for m in logs)\n")
    r = subprocess.run([sys.executable, "-c", TAMPER_SCRIPT, str(d), str(tmp_path)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    with zipfile.ZipFile(built[0]) as z:
        shim = f"binaries/linux64/Pedestal{INNER_SUFFIX}" in z.namelist()
    expected = "setup refused 3" if shim else "step refused 2"
    assert expected in r.stdout and "bundled code mismatch" in r.stdout, r.stdout
