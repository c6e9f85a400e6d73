"""Built FMUs (fmus/build.py): validity, reproducibility, archive content, isolation, bundle check.

The adapter's parts are tested per module: test_fmu_spec.py, test_fmu_model_description.py,
test_fmu_slave.py, test_fmu_bundle.py.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from axir.fmus.build import INNER_SUFFIX, build_fmu


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
    assert f"resources/_axir_{h8}/fmus/slave.py" in names
    assert not any("__pycache__" in n or n.endswith(".pyc") for n in names)
    md = read_model_description(str(built[0]))
    cs = md.coSimulation
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canHandleVariableCommunicationStepSize


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
    base = next(d.glob("resources/_axir_*/fmus/slave.py"))
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
