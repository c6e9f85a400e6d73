"""The C shim (fmus/shim/axir_fmi2_shim.c) around pythonfmu's binary: fmi2Error for errors.

pythonfmu 0.7.0 cannot return fmi2Error; the shim returns it from any call during which the
FMU logged an Error-status message (see docs/fmu_build.md). Checked here through fmpy's
low-level API (directly and via the master's ``FmuInstance``): invalid parameters of all four
FMUs → fmi2ExitInitializationMode returns fmi2Error with a log message naming the parameter,
also with logging off (the host then gets no message), the host's debug-logging categories
are honoured, valid runs are bit-identical to the unshimmed FMU, every FMI 2.0 co-simulation
function is exported, a missing inner binary fails cleanly, several instances / all four FMUs
in one process exit with code 0, the build is byte-reproducible and falls back (with a
warning) when no compiler is available.
"""

from __future__ import annotations

import ctypes
import hashlib
import shutil
import subprocess
import sys
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.validation import validate_fmu

import axir.fmus.build as build
from axir.fmus import python_env, shim_sources, shim_win64
from axir.fmus.build import (
    INNER_SUFFIX,
    ShimUnavailableError,
    ShimWarning,
    build_fmu,
    compile_shim,
)
from axir.orchestrator.errors import FmiError
from axir.orchestrator.fmi import FmuInstance

FMUS = ("TargetGenerator", "Tracker", "Pedestal", "RadarManager")
#: A parameter value each FMU must reject (range checks of the models' PARAMS).
INVALID = {"TargetGenerator": ("rcs", -1.0), "Tracker": ("rate_per_volt", -1.0),
           "Pedestal": ("rate_per_volt", -1.0), "RadarManager": ("pri1_bins", 5)}
#: Every function of the FMI 2.0 co-simulation API (FMI 2.0.x standard, §2.1 and §4.2).
FMI2_CS_FUNCTIONS = (
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal",
    "fmi2GetInteger", "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger",
    "fmi2SetBoolean", "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate",
    "fmi2FreeFMUstate", "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate", "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives", "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus",
    "fmi2GetRealStatus", "fmi2GetIntegerStatus", "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
)
FMI2_ERROR, FMI2_FATAL = 3, 4
DT = 1e-3  # Pedestal step [s]


def _is_shimmed(fmu: Path) -> bool:
    with zipfile.ZipFile(fmu) as z:
        return f"binaries/linux64/{fmu.stem}{INNER_SUFFIX}" in z.namelist()


@pytest.fixture(scope="module")
def shim_dir(fmu_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The four FMUs with the shim: the session's ``fmu_dir`` if it is shimmed (the default
    build), else built here with ``shim=True``."""
    try:
        compile_shim()
    except ShimUnavailableError as e:
        pytest.skip(f"the C shim cannot be built here: {e}")
    if all(_is_shimmed(fmu_dir / f"{n}.fmu") for n in FMUS):
        return fmu_dir
    d = tmp_path_factory.mktemp("shimmed")
    build.build_all(d, shim=True)
    return d


@pytest.fixture(scope="module")
def plain_pedestal(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Pedestal.fmu with pythonfmu's binary only."""
    return build_fmu("Pedestal", tmp_path_factory.mktemp("plain"), shim=False)


@contextmanager
def raw(fmu: Path, logging_on: bool = True, unzip: str | None = None) -> Iterator[Any]:
    """fmpy's FMU2Slave, instantiated with a logger collecting (status, category, message);
    always freed (fmpy 0.3.32: freeInstance also frees the library)."""
    md = read_model_description(str(fmu))
    f = FMU2Slave(guid=md.guid, unzipDirectory=unzip or extract(str(fmu)),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="raw")
    f.logs = []
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(
        lambda env, name, status, cat, msg: f.logs.append(
            (status, (cat or b"").decode(), msg.decode())))
    f.instantiate(loggingOn=logging_on, callbacks=cb)
    f.vr = {v.name: v.valueReference for v in md.modelVariables}
    f.cb = cb  # keep the thunk alive while the instance lives
    try:
        yield f
    finally:
        f.freeInstance()


# ------------------------------------------------------------------ archive layout
def test_archive_holds_shim_and_pythonfmu_binary(shim_dir: Path) -> None:
    import pythonfmu

    original = (Path(pythonfmu.__file__).parent / "resources" / "binaries" / "linux64"
                / "libpythonfmu-export.so").read_bytes()
    lib = compile_shim()
    for name in FMUS:
        with zipfile.ZipFile(shim_dir / f"{name}.fmu") as z:
            names = set(z.namelist())
            assert z.read(f"binaries/linux64/{name}{INNER_SUFFIX}") == original
            assert z.read(f"binaries/linux64/{name}.so") == lib
            assert f"binaries/win64/{name}.dll" in names
            win64 = f"binaries/win64/{name}{shim_win64.INNER_SUFFIX}" in names
        md = read_model_description(str(shim_dir / f"{name}.fmu"))
        # platform-exact claim: the win64 shim is there only when mingw-w64 was found
        assert md.generationTool.endswith(
            "axir fmi2 shim (linux64, win64)" if win64 else "axir fmi2 shim (linux64 only)")


def test_win64_shim(shim_dir: Path, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """The win64 DLL is the shim (cross-compiled with mingw-w64): it exports exactly the 34
    FMI 2.0 co-simulation functions, needs only KERNEL32.dll and msvcrt.dll, is
    byte-reproducible; pythonfmu's DLL is shipped as <id>_pythonfmu.dll. (Not run on Windows
    here.)"""
    import pythonfmu

    try:
        lib = shim_win64.compile_shim_win64()
    except ShimUnavailableError as e:
        pytest.skip(f"no win64 shim here: {e}")
    objdump = shutil.which("x86_64-w64-mingw32-objdump")
    original = (Path(pythonfmu.__file__).parent / "resources" / "binaries" / "win64"
                / "pythonfmu-export.dll").read_bytes()
    for name in FMUS:
        with zipfile.ZipFile(shim_dir / f"{name}.fmu") as z:
            assert z.read(f"binaries/win64/{name}.dll") == lib
            assert z.read(f"binaries/win64/{name}{shim_win64.INNER_SUFFIX}") == original
    monkeypatch.setattr(shim_sources, "_CACHE", {})
    assert shim_win64.compile_shim_win64() == lib and lib[:2] == b"MZ"
    if objdump is None:
        return
    with zipfile.ZipFile(shim_dir / "Pedestal.fmu") as z:
        z.extract("binaries/win64/Pedestal.dll", tmp_path)
    out = subprocess.run([objdump, "-p", str(tmp_path / "binaries" / "win64" / "Pedestal.dll")],
                         capture_output=True, text=True, timeout=60).stdout
    exports = {line.split()[-1] for line in out.splitlines()
               if line.strip().startswith("[") and "fmi2" in line}
    assert exports == set(FMI2_CS_FUNCTIONS)
    dlls = {line.split(":")[1].strip() for line in out.splitlines() if "DLL Name:" in line}
    assert dlls == {"KERNEL32.dll", "msvcrt.dll"}


def test_shim_exports_every_fmi2_cs_function(shim_dir: Path) -> None:
    d = extract(str(shim_dir / "Pedestal.fmu"))
    lib = ctypes.CDLL(str(Path(d) / "binaries" / "linux64" / "Pedestal.so"))
    missing = [f for f in FMI2_CS_FUNCTIONS if not hasattr(lib, f)]
    assert missing == []
    lib.fmi2GetVersion.restype = lib.fmi2GetTypesPlatform.restype = ctypes.c_char_p
    assert lib.fmi2GetVersion() == b"2.0"
    assert lib.fmi2GetTypesPlatform() == b"default"


@pytest.mark.parametrize("name", FMUS)
def test_fmpy_validate(shim_dir: Path, name: str) -> None:
    assert validate_fmu(str(shim_dir / f"{name}.fmu")) == []


def test_fmutool_check(shim_dir: Path) -> None:
    exe = shutil.which("fmutool") or str(Path(sys.executable).parent / "fmutool")
    if not Path(exe).exists():
        pytest.skip("fmu-manipulation-toolbox (fmutool) not installed")
    for name in FMUS:
        r = subprocess.run([exe, "-input", str(shim_dir / f"{name}.fmu"), "-check"],
                           capture_output=True, text=True, timeout=120)
        text = r.stdout + r.stderr
        assert r.returncode == 0 and "compliant with FMI-2.0" in text, text
        assert "ERROR" not in text.upper().replace("NO SEMANTIC ERROR", ""), text


# ------------------------------------------------------------------ fmi2Error
@pytest.mark.parametrize("name", FMUS)
def test_invalid_parameter_error_at_exit_initialization(shim_dir: Path, name: str) -> None:
    pname, value = INVALID[name]
    with FmuInstance(shim_dir / f"{name}.fmu", name, logging_on=True) as inst:
        inst.setup(0.0)
        inst.set_parameter(pname, value)
        inst.enter_init()  # parameters are validated at exit
        with pytest.raises(FmiError) as e:
            inst.exit_init()
        assert e.value.status == FMI2_ERROR, e.value
        assert e.value.function == "fmi2ExitInitializationMode"
        assert f"{name}: fmi2ExitInitializationMode returned error" in str(e.value)
        assert pname in str(e.value) and "invalid parameter" in str(e.value)
        errors = [m for m in inst.log if m.startswith("[ERROR]")]
        assert len(errors) == 1 and pname in errors[0], inst.log
        with pytest.raises(FmiError) as e:  # the instance keeps refusing to step
            inst.do_step(0.0, 1e-4)
        assert e.value.status == FMI2_ERROR
        assert not [m for m in inst.log if m.startswith("[FATAL]")], inst.log


def test_error_without_logging_and_category_filter(shim_dir: Path) -> None:
    """The shim sees the Error message even when the host turned logging off (pythonfmu would
    drop it) and forwards messages only as the host's logging settings allow."""
    fmu = shim_dir / "Pedestal.fmu"
    for logging_on, categories, forwarded in ((False, None, False),
                                              (True, ["logStatusWarning"], False),
                                              (True, ["logStatusError"], True)):
        with raw(fmu, logging_on=logging_on) as f:
            if categories is not None:
                f.setDebugLogging(True, categories)
            f.setupExperiment(startTime=0.0)
            f.enterInitializationMode()
            f.setReal([f.vr["rate_per_volt"]], [-1.0])
            with pytest.raises(FMICallException) as e:
                f.exitInitializationMode()
            assert e.value.status == FMI2_ERROR
            got = [m for s, _, m in f.logs if s == FMI2_ERROR and "rate_per_volt" in m]
            assert bool(got) == forwarded, (logging_on, categories, f.logs)
            if not forwarded:
                assert f.logs == []
            else:
                assert {c for _, c, _ in f.logs} == {"logStatusError"}


def test_other_logged_errors_return_error(shim_dir: Path) -> None:
    """Any call that logs an Error answers fmi2Error: a fixed parameter set after
    initialization (value ignored), a value reference of the wrong type; a NaN input only
    warns (fmi2Warning: tests/test_fmu_shim_shared.py)."""
    with raw(shim_dir / "Pedestal.fmu") as f:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.exitInitializationMode()
        with pytest.raises(FMICallException) as e:
            f.setReal([f.vr["rate_per_volt"]], [5.0])
        assert e.value.status == FMI2_ERROR
        assert f.getReal([f.vr["rate_per_volt"]]) == [0.1]  # the default, unchanged
        with pytest.raises(FMICallException) as e:
            f.getReal([f.vr["input.invalid.count"]])  # an Integer
        assert e.value.status == FMI2_ERROR
        f.logs.clear()
        f.setReal([f.vr["cmd.az"]], [float("nan")])
        f.doStep(0.0, DT)  # fmpy raises on anything above fmi2Warning
        assert [s for s, _, _ in f.logs] == [1] and "cmd.az" in f.logs[0][2]
        f.setReal([f.vr["cmd.az"]], [0.5])
        f.doStep(DT, DT)
        assert f.getBoolean([f.vr["input.invalid"]]) == [False]


def test_status_getters_and_unsupported_functions(shim_dir: Path) -> None:
    with raw(shim_dir / "Pedestal.fmu") as f:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.exitInitializationMode()
        f.doStep(0.0, DT)
        lib = f.dll  # the shim's ctypes functions (fmpy's wrappers raise on errors)
        value = ctypes.c_double()
        assert lib.fmi2GetRealStatus(f.component, 2, ctypes.byref(value)) == 0  # last time
        assert value.value == DT
        assert lib.fmi2CancelStep(f.component) == FMI2_ERROR  # not supported by pythonfmu
        vr = (ctypes.c_uint * 1)(f.vr["az"])
        dv = (ctypes.c_double * 1)(1.0)
        out = (ctypes.c_double * 1)()
        assert lib.fmi2GetDirectionalDerivative(f.component, vr, 1, vr, 1, dv, out) == FMI2_ERROR
        assert sum("not supported" in m for _, _, m in f.logs) == 2, f.logs


# ------------------------------------------------------------------ valid runs unchanged
def _run_pedestal(fmu: Path, n: int) -> list[tuple[list[float], int]]:
    with raw(fmu) as f:
        f.setupExperiment(startTime=0.0)
        f.enterInitializationMode()
        f.setInteger([f.vr["seed"]], [3])
        f.exitInitializationMode()
        ins = [f.vr[k] for k in ("cmd.az", "cmd.el", "bandwidth")]
        outs = [v for k, v in f.vr.items() if k in ("az", "el", "pot.az.a", "az.rate")]
        res = []
        for k in range(n):
            f.setReal(ins, [0.5 + 0.001 * k, -0.2, 2.0])
            f.doStep(k * DT, DT)
            res.append((f.getReal(outs), f.getInteger([f.vr["input.invalid.count"]])[0]))
        assert not [m for s, _, m in f.logs if s >= FMI2_ERROR], f.logs
    return res


def test_valid_run_bit_identical_to_unshimmed(shim_dir: Path, plain_pedestal: Path) -> None:
    a = _run_pedestal(shim_dir / "Pedestal.fmu", 200)
    b = _run_pedestal(plain_pedestal, 200)
    assert len({tuple(x[0]) for x in a}) > 100, "outputs must move"
    assert a == b


# ------------------------------------------------------------------ loading, process exit
LOAD_SCRIPT = """
import sys
from pathlib import Path
from fmpy import extract
from axir.orchestrator.fmi import FmuInstance
d = Path(sys.argv[1])
names = ("TargetGenerator", "Tracker", "Pedestal", "RadarManager")
for rnd in range(2):
    insts = [FmuInstance(d / f"{n}.fmu", f"{n}{rnd}") for n in names]
    insts.append(FmuInstance(d / "Pedestal.fmu", f"second{rnd}"))  # same FMU twice
    for i in insts:
        i.setup(0.0); i.enter_init(); i.exit_init()
    for k in range(5):
        for i in insts:
            i.do_step(k * 1e-4, 1e-4)
    for i in insts:
        i.close()
bad = FmuInstance(d / "Pedestal.fmu", "bad", logging_on=True)
bad.setup(0.0); bad.set_parameter("rate_per_volt", -1.0); bad.enter_init()
try:
    bad.exit_init()
except Exception as e:
    print("refused", e.status)
bad.close()
print("OK")
"""


def test_all_four_and_twice_in_one_process_exit_code(shim_dir: Path) -> None:
    for _ in range(3):
        r = subprocess.run([sys.executable, "-c", LOAD_SCRIPT, str(shim_dir)],
                           capture_output=True, text=True, timeout=300)
        assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
        assert "refused 3" in r.stdout and "OK" in r.stdout, r.stdout


def test_two_extractions_in_one_process(shim_dir: Path, tmp_path: Path) -> None:
    """Two extraction folders of one FMU: two shim libraries, each loading its own inner
    binary; both instances step."""
    fmu = shim_dir / "Pedestal.fmu"
    dirs = []
    for sub in ("x", "y"):
        with zipfile.ZipFile(fmu) as z:
            z.extractall(tmp_path / sub)
        dirs.append(str(tmp_path / sub))
    with raw(fmu, unzip=dirs[0]) as a, raw(fmu, unzip=dirs[1]) as b:
        for f in (a, b):
            f.setupExperiment(startTime=0.0)
            f.enterInitializationMode()
            f.exitInitializationMode()
        for k in range(3):
            a.doStep(k * DT, DT)
            b.doStep(k * DT, DT)
        assert a.getReal([a.vr["az"]]) == b.getReal([b.vr["az"]])


@pytest.mark.parametrize("logging_on", [True, False])
def test_missing_inner_binary_fails_instantiation(shim_dir: Path, tmp_path: Path,
                                                  logging_on: bool) -> None:
    """fmi2Instantiate returns NULL after a Fatal message, also with logging off."""
    fmu = shim_dir / "Pedestal.fmu"
    with zipfile.ZipFile(fmu) as z:
        z.extractall(tmp_path)
    (tmp_path / "binaries" / "linux64" / f"Pedestal{INNER_SUFFIX}").unlink()
    md = read_model_description(str(fmu))
    logs: list[tuple[int, bytes]] = []
    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(lambda e, n, s, c, m: logs.append((s, m)))
    f = FMU2Slave(guid=md.guid, unzipDirectory=str(tmp_path), modelIdentifier="Pedestal")
    with pytest.raises(Exception, match="instantiate"):
        f.instantiate(loggingOn=logging_on, callbacks=cb)
    f.freeLibrary()
    assert logs and logs[0][0] == FMI2_FATAL
    assert f"Pedestal{INNER_SUFFIX}".encode() in logs[0][1], logs


# ------------------------------------------------------------------ the FMU's Python
def test_recorded_python(shim_dir: Path) -> None:
    """resources/axir_python.txt: the build interpreter as the shipped probe reports it, and
    the third-party modules the bundled code imports."""
    expected_requires = {"TargetGenerator": ["numpy"],  # no scipy.signal since session 6
                         "Tracker": ["numpy", "scipy"],  # filterpy: require_if filter_*=imm
                         "Pedestal": ["numpy"],
                         "RadarManager": ["numpy", "scipy"]}  # no filterpy since the filters split
    for name in FMUS:
        with zipfile.ZipFile(shim_dir / f"{name}.fmu") as z:
            text = z.read(f"resources/{python_env.CONFIG_NAME}").decode()
            probe = z.read(f"resources/{python_env.PROBE_NAME}").decode()
        assert probe == python_env.PROBE
        lines = [x for x in text.splitlines() if not x.startswith("#")]
        requires = [x.split("=", 1)[1] for x in lines if x.startswith("require=")]
        assert requires == expected_requires[name], (name, requires)
        conditional = sorted(x.split("=", 1)[1] for x in lines if x.startswith("require_if="))
        assert conditional == (
            [f"filterpy filter_{a}=imm" for a in ("az", "el", "range", "x", "y", "z")]
            if name == "Tracker" else []), (name, conditional)
        keys = dict(x.split("=", 1) for x in lines
                    if not x.startswith(("path=", "require=", "require_if=")))
        assert keys["format"] == "axir-python 1"
        assert keys["executable"] == sys.executable
        assert keys["version"] == f"{sys.version_info[0]}.{sys.version_info[1]}"
        assert keys["home"] == sys.base_prefix
        assert Path(keys["libpython"]).is_file()
        paths = [x[5:] for x in lines if x.startswith("path=")]
        import numpy

        assert str(Path(numpy.__file__).parents[1]) in paths  # site-packages
        assert keys["stdlib"] in paths


def test_probe_script_matches_record(shim_dir: Path, tmp_path: Path) -> None:
    """The shim runs the shipped probe as ``$AXIR_FMU_PYTHON -E axir_python_probe.py``: for
    the build interpreter that gives exactly the recorded settings."""
    with zipfile.ZipFile(shim_dir / "Pedestal.fmu") as z:
        z.extractall(tmp_path)
    res = tmp_path / "resources"
    r = subprocess.run([sys.executable, "-E", str(res / python_env.PROBE_NAME)],
                       capture_output=True, timeout=120, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    recorded = [x for x in (res / python_env.CONFIG_NAME).read_bytes().splitlines()
                if not x.startswith((b"#", b"require="))]
    assert r.stdout.splitlines() == recorded


PYTHON_HOST = """
import sys
from pathlib import Path
from axir.orchestrator.fmi import FmuInstance
d = Path(sys.argv[1])
insts = [FmuInstance(d / f"{n}.fmu", n) for n in ("Tracker", "Pedestal")]
for i in insts:
    i.setup(0.0); i.enter_init(); i.exit_init()
for k in range(3):
    for i in insts:
        i.do_step(k * 1e-4, 1e-4)
maps = {line.split()[-1] for line in open("/proc/self/maps") if "libpython" in line}
print("libpython", sorted(maps))
for i in insts:
    i.close()
print("OK")
"""


def test_python_host_uses_its_own_interpreter(shim_dir: Path) -> None:
    """In a Python host the shim finds the running interpreter (Py_IsInitialized is in the
    process) and neither loads nor initializes another: AXIR_FMU_PYTHON naming a missing
    interpreter is never looked at, one libpython is mapped, the process exits with 0 (it
    runs Python's normal finalization, no os._exit)."""
    import os

    env = {**os.environ, "AXIR_FMU_PYTHON": "/nonexistent/python3"}
    r = subprocess.run([sys.executable, "-c", PYTHON_HOST, str(shim_dir)], env=env,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr)
    assert "OK" in r.stdout
    maps = eval(r.stdout.split("libpython ", 1)[1].splitlines()[0])
    assert len(maps) <= 1, maps  # 0: a Python linked statically


def test_required_modules() -> None:
    entries = {"resources/a.py": b"import numpy as np\nimport os\nfrom scipy.stats import chi2\n",
               "resources/_pkg/b.py": b"from . import x\nimport _pkg\ndef f():\n    import lark\n",
               "resources/mod.py": b"from __future__ import annotations\nimport mod\n"}
    assert python_env.required_modules(entries) == ["lark", "numpy", "scipy"]


# ------------------------------------------------------------------ build
def test_compile_is_reproducible(monkeypatch: pytest.MonkeyPatch) -> None:
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    monkeypatch.setattr(shim_sources, "_CACHE", {})
    a = compile_shim()
    shim_sources._CACHE.clear()
    b = compile_shim()
    assert a == b and a[:4] == b"\x7fELF"


def test_build_reproducible_with_shim(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if shutil.which("gcc") is None:
        pytest.skip("gcc not installed")
    monkeypatch.setattr(shim_sources, "_CACHE", {})
    a = build_fmu("Pedestal", tmp_path / "a", shim=True)
    shim_sources._CACHE.clear()  # compile again
    b = build_fmu("Pedestal", tmp_path / "b", shim=True)
    assert _is_shimmed(a)
    assert hashlib.sha256(a.read_bytes()).digest() == hashlib.sha256(b.read_bytes()).digest()


def test_fallback_without_compiler(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                   plain_pedestal: Path) -> None:
    monkeypatch.setenv("CC", str(tmp_path / "no-such-gcc"))
    monkeypatch.setattr(shim_sources, "_CACHE", {})
    with pytest.warns(ShimWarning, match=r"fmi2Discard .* instead of fmi2Error"):
        out = build_fmu("Pedestal", tmp_path, shim=True)
    assert not _is_shimmed(out)
    assert out.read_bytes() == plain_pedestal.read_bytes()  # exactly the unshimmed build


def test_win64_fallback_without_mingw(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """No mingw-w64: the FMU is built (Linux shim only) with one warning, the win64 DLL is
    pythonfmu's and the generationTool says so."""
    import pythonfmu

    monkeypatch.setenv("AXIR_MINGW_CC", str(tmp_path / "no-such-mingw-gcc"))
    monkeypatch.setattr(shim_win64, "_WARNED", [])
    with pytest.warns(ShimWarning, match="win64 binaries are pythonfmu's"):
        out = build_fmu("Pedestal", tmp_path, shim=True)
    original = (Path(pythonfmu.__file__).parent / "resources" / "binaries" / "win64"
                / "pythonfmu-export.dll").read_bytes()
    with zipfile.ZipFile(out) as z:
        assert z.read("binaries/win64/Pedestal.dll") == original
        assert f"binaries/win64/Pedestal{shim_win64.INNER_SUFFIX}" not in z.namelist()
    assert read_model_description(str(out)).generationTool.endswith("shim (linux64 only)")
    assert _is_shimmed(out)


def test_shim_default_env(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("AXIR_FMU_SHIM", "0")
    assert build.shim_default() is False
    monkeypatch.setenv("AXIR_FMU_SHIM", "1")
    assert build.shim_default() is True
    monkeypatch.delenv("AXIR_FMU_SHIM")
    assert build.shim_default() is build.SHIM_DEFAULT
