"""The four built FMUs through fmpy's low-level API (via the master's ``FmuInstance``).

Per FMU: fmpy validation, fmutool check, modelDescription content (units, ModelStructure,
discrete Integer/Boolean, structured array names, capability flags), FMU state save/restore and
serialisation (bit-identical continuation), several instances in one process, invalid parameter
(fmi2ExitInitializationMode → fmi2Error with an Error log naming it, through the C shim; an FMU
built without the shim, when no gcc is available, answers fmi2Discard at the next doStep
instead, see docs/fmu_build.md) and NaN inputs (Warning log, no crash). Also: the committed
``docs/interfaces.md`` matches the FMUs built from the working tree.

Every instance is freed through ``FmuInstance`` (context manager: fmi2FreeInstance then
freeLibrary, once each; the pythonfmu exit-crash trap).
"""

from __future__ import annotations

import ctypes
import math
import re
import shutil
import subprocess
import sys
import zipfile
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import fmi2FMUstate
from fmpy.validation import validate_fmu

from axir.fmus.build import INNER_SUFFIX, shim_default
from axir.models.system import UNITS, initial_pri
from axir.orchestrator.docs import REGENERATE, render
from axir.orchestrator.errors import FmiError
from axir.orchestrator.fmi import FmuInstance

FMUS = UNITS
REPO = Path(__file__).resolve().parents[1]
ELEMENT = re.compile(r"^(?P<base>.+)\[(?P<idx>\d+(?:,\d+)*)\]$")
PRI = initial_pri()  # PRI 1 of the manager (200 bins of 0.5 µs)
STEP = {"TargetGenerator": PRI, "Tracker": PRI, "Pedestal": 1e-3, "RadarManager": PRI}

# the default target (models/radar/trajectory.py): start (-6000, 12000, 1500) m
TARGET_AZ = math.atan2(-6000.0, 12000.0) % (2 * math.pi)  # 333.43°
TARGET_EL = math.asin(1500.0 / math.sqrt(6000.0**2 + 12000.0**2 + 1500.0**2))  # 6.38°
TARGET_R = math.sqrt(6000.0**2 + 12000.0**2 + 1500.0**2)  # 13.5 km
GATE = TARGET_R - 6 * 75.0  # bin 7 on the target


# ------------------------------------------------------------------ plausible inputs
def _beams(k: int) -> np.ndarray:
    """(4, 16, 3) beam magnitudes: noise floor + a target echo in bins 6-8, slightly off
    boresight (up > down, right > left), deterministic in k."""
    rng = np.random.default_rng(1000 + k)
    b = 1.0 + 0.2 * rng.random((4, 16, 3))
    echo = np.array([0.3, 1.0, 0.4])[:, None] * np.array([0.5, 1.0, 0.5])[None, :]
    for i, g in enumerate((60.0, 55.0, 50.0, 52.0)):  # up, right, down, left
        b[i, 5:8, :] += g * echo * (1.0 + 0.05 * rng.standard_normal())
    return b


def _sum(k: int) -> np.ndarray:
    return _beams(k).sum(axis=0)


FEEDS: dict[str, Callable[[int], dict[str, Any]]] = {
    "TargetGenerator": lambda k: {
        "antenna.az": TARGET_AZ + 2e-4 * math.sin(0.1 * k), "antenna.el": TARGET_EL,
        "gate.start": GATE - 0.2 * k, "doppler.centre": 0.0, "pri": PRI},
    "Tracker": lambda k: {
        "beam.up": _beams(k)[0], "beam.right": _beams(k)[1], "beam.down": _beams(k)[2],
        "beam.left": _beams(k)[3], "ped.az": TARGET_AZ + 1e-4 * k, "ped.el": TARGET_EL,
        "mode": 0 if k < 3 else 1 if k < 8 else 2, "alpha": 0.0, "beta": 0.0,
        "range.offset": 0.0, "gate.command": GATE, "meas.range": 0.0, "meas.az": 0.0,
        "meas.el": 0.0, "meas.valid": 0.0, "meas.new": 0.0,
        "doppler.range_rate": -200.0, "doppler.resolved": k >= 8},
    "Pedestal": lambda k: {
        "cmd.az": 3.0 * math.sin(0.01 * k), "cmd.el": -2.0 + 0.002 * k,
        "bandwidth": 1.0 + 0.5 * math.cos(0.003 * k)},
    "RadarManager": lambda k: {
        "sum": _sum(k), "gate.start": GATE, "track.range": TARGET_R - 0.02 * k,
        "track.range_rate": -200.0, "maneuver": k % 17 == 0},
}
#: A parameter value each FMU must reject (range check in the model's PARAMS).
INVALID = {"TargetGenerator": ("rcs", -1.0), "Tracker": ("rate_per_volt", -1.0),
           "Pedestal": ("rate_per_volt", -1.0), "RadarManager": ("pri1_bins", 5)}
#: The Real input made NaN in the NaN test.
NAN_INPUT = {"TargetGenerator": "antenna.az", "Tracker": "ped.az", "Pedestal": "cmd.az",
             "RadarManager": "track.range"}
#: Parameters of every instance in these tests: the manager searches around the target.
PARAMS: dict[str, dict[str, Any]] = {"RadarManager": {"designation_range": TARGET_R}}
#: (warm-up steps, compared steps) of the state tests: the manager works in dwells of 16 PRIs.
STATE_STEPS = {"TargetGenerator": (12, 20), "Tracker": (12, 20), "Pedestal": (12, 20),
               "RadarManager": (40, 60)}
ARRAYS = {"TargetGenerator": ("beam.up[1,1]", "beam.left[16,3]"),
          "Tracker": ("beam.up[1,1]", "beam.right[8,2]", "beam.left[16,3]", "sum[1,1]",
                      "sum[16,3]"),
          "Pedestal": (),
          "RadarManager": ("sum[1,1]", "sum[16,3]")}


class Driver:
    """Feeds ``FEEDS[name](k)`` to an instance and steps it; outputs as raw bytes."""

    def __init__(self, inst: FmuInstance, name: str) -> None:
        self.inst, self.name, self.h = inst, name, STEP[name]
        md = inst.md
        self.inputs: dict[str, list[tuple[str, str | None, tuple[int, ...]]]] = {}
        outs: dict[str, list[str]] = {}
        for v in md.modelVariables:
            if v.causality == "input":
                m = ELEMENT.match(v.name)
                ref = (v.name, m["base"], tuple(int(i) - 1 for i in m["idx"].split(","))) \
                    if m else (v.name, None, ())
                self.inputs.setdefault(v.type, []).append(ref)
            elif v.causality == "output":
                outs.setdefault(v.type, []).append(v.name)
        self.in_ports = {t: inst.port([r[0] for r in refs]) for t, refs in self.inputs.items()}
        self.out_ports = [inst.port(names) for _, names in sorted(outs.items())]

    def set_inputs(self, k: int, override: dict[str, float] | None = None) -> None:
        feed = FEEDS[self.name](k) | (override or {})
        for kind, refs in self.inputs.items():
            self.in_ports[kind].write([feed[n] if base is None else feed[base][idx]
                                       for n, base, idx in refs])

    def step(self, k: int, override: dict[str, float] | None = None) -> None:
        self.set_inputs(k, override)
        self.inst.do_step(k * self.h, self.h)

    def outputs(self) -> bytes:
        return b"".join(bytes(p.read()) for p in self.out_ports)

    def run(self, k0: int, n: int) -> list[bytes]:
        res = []
        for k in range(k0, k0 + n):
            self.step(k)
            res.append(self.outputs())
        return res

    def output_values(self) -> dict[str, float]:
        out: dict[str, float] = {}
        for p in self.out_ports:
            out.update(zip(p.names, p.read(), strict=True))
        return out


@contextmanager
def opened(fmu_dir: Path, name: str, instance: str | None = None,
           params: dict[str, Any] | None = None, init: bool = True) -> Iterator[FmuInstance]:
    """Instantiate (loggingOn), set parameters, initialise; always freed on exit."""
    with FmuInstance(fmu_dir / f"{name}.fmu", instance or name, logging_on=True) as inst:
        if init:
            inst.setup(0.0)
            for k, v in (PARAMS.get(name, {}) | (params or {})).items():
                inst.set_parameter(k, v)
            inst.enter_init()
            inst.exit_init()
        yield inst


# ------------------------------------------------------------------ FMU state via FmuInstance
def get_state(inst: FmuInstance) -> fmi2FMUstate:
    s = fmi2FMUstate()
    inst.call("fmi2GetFMUstate", ctypes.byref(s))
    return s


def free_state(inst: FmuInstance, s: fmi2FMUstate) -> None:
    inst.call("fmi2FreeFMUstate", ctypes.byref(s))


def serialize(inst: FmuInstance, s: fmi2FMUstate) -> bytes:
    size = ctypes.c_size_t()
    inst.call("fmi2SerializedFMUstateSize", s, ctypes.byref(size))
    buf = ctypes.create_string_buffer(size.value)
    inst.call("fmi2SerializeFMUstate", s, buf, size)
    return buf.raw


def deserialize(inst: FmuInstance, data: bytes) -> fmi2FMUstate:
    s = fmi2FMUstate()
    buf = ctypes.create_string_buffer(data, len(data))
    inst.call("fmi2DeSerializeFMUstate", buf, len(data), ctypes.byref(s))
    return s


def _md(fmu_dir: Path, name: str) -> Any:
    return read_model_description(str(fmu_dir / f"{name}.fmu"))


def shimmed(fmu_dir: Path, name: str) -> bool:
    """True if the FMU carries the C shim (fmi2Error support). The session's FMUs are built
    with the default; without gcc the build falls back to pythonfmu's binary alone."""
    with zipfile.ZipFile(fmu_dir / f"{name}.fmu") as z:
        has = f"binaries/linux64/{name}{INNER_SUFFIX}" in z.namelist()
    if shim_default() and shutil.which("gcc") is not None:
        assert has, f"{name}.fmu was built without the shim although gcc is available"
    return has


def exit_init_invalid(inst: FmuInstance, shim: bool) -> None:
    """fmi2ExitInitializationMode after an invalid parameter: fmi2Error with the shim; OK
    without it (pythonfmu 0.7.0; the next doStep answers fmi2Discard)."""
    if not shim:
        inst.exit_init()
        return
    with pytest.raises(FmiError) as e:
        inst.exit_init()
    assert e.value.status == 3 and e.value.function == "fmi2ExitInitializationMode", e.value


# ------------------------------------------------------------------ modelDescription
@pytest.mark.parametrize("name", FMUS)
def test_fmpy_validate(fmu_dir: Path, name: str) -> None:
    assert validate_fmu(str(fmu_dir / f"{name}.fmu")) == []


@pytest.mark.parametrize("name", FMUS)
def test_fmutool_check(fmu_dir: Path, name: str) -> None:
    exe = shutil.which("fmutool") or str(Path(sys.executable).parent / "fmutool")
    if not Path(exe).exists():
        pytest.skip("fmu-manipulation-toolbox (fmutool) not installed: "
                    "pip install 'axir[test]' to run the FMI compliance check")
    r = subprocess.run([exe, "-input", str(fmu_dir / f"{name}.fmu"), "-check"],
                       capture_output=True, text=True, timeout=120)
    text = r.stdout + r.stderr
    assert r.returncode == 0, text
    assert "compliant with FMI-2.0" in text, text
    assert "ERROR" not in text.upper().replace("NO SEMANTIC ERROR", ""), text


@pytest.mark.parametrize("name", FMUS)
def test_model_description_content(fmu_dir: Path, name: str) -> None:
    md = _md(fmu_dir, name)
    assert md.fmiVersion == "2.0" and md.modelName == name
    assert md.variableNamingConvention == "structured"
    # every Real has a unit, declared in UnitDefinitions
    units = {u.name for u in md.unitDefinitions}
    no_unit = [v.name for v in md.modelVariables if v.type == "Real" and not v.unit]
    assert no_unit == [], f"Reals without unit: {no_unit[:10]}"
    assert {v.unit for v in md.modelVariables if v.type == "Real"} <= units
    assert all(v.description for v in md.modelVariables), "every variable is documented"
    # Integer/Boolean inputs and outputs are discrete (parameters: fixed/tunable)
    bad = [(v.name, v.variability) for v in md.modelVariables
           if v.type in ("Integer", "Boolean") and v.causality != "parameter"
           and v.variability != "discrete"]
    assert bad == []
    # ModelStructure: Outputs = every output, in order; InitialUnknowns = exactly the outputs
    # whose initial value is computed (initial approx/calculated), FMI 2.0 §2.2.8
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert outputs, "an FMU without outputs"
    assert [u.variable.name for u in md.outputs] == [v.name for v in outputs]
    computed = [v.name for v in outputs if v.initial in ("approx", "calculated")]
    assert sorted(u.variable.name for u in md.initialUnknowns) == sorted(computed)
    # every output is calculated at initialization (model.outputs()), none has a start value
    assert len(md.initialUnknowns) == len(outputs)
    assert all(v.initial == "calculated" and v.start is None for v in outputs)
    # capabilities
    cs = md.coSimulation
    assert cs.canHandleVariableCommunicationStepSize
    assert cs.canGetAndSetFMUstate
    assert cs.canSerializeFMUstate


@pytest.mark.parametrize("name", FMUS)
def test_structured_array_names(fmu_dir: Path, name: str) -> None:
    names = {v.name for v in _md(fmu_dir, name).modelVariables}
    for n in ARRAYS[name]:
        assert n in names, n
    for base in {ELEMENT.match(n)["base"] for n in ARRAYS[name]}:
        grid = {f"{base}[{r},{f}]" for r in range(1, 17) for f in (1, 2, 3)}
        elements = {n for n in names if n.startswith(base + "[")}
        assert elements == grid, f"{base}: not the full 1-based [16,3] grid"
    assert not any("[0," in n or ",0]" in n for n in names), "indices are 1-based"


# ------------------------------------------------------------------ runtime
@pytest.mark.parametrize("name", FMUS)
def test_state_save_step_restore_bit_identical(fmu_dir: Path, name: str) -> None:
    n0, n = STATE_STEPS[name]
    with opened(fmu_dir, name) as inst:
        d = Driver(inst, name)
        d.run(0, n0)
        s = get_state(inst)
        first = d.run(n0, n)
        inst.call("fmi2SetFMUstate", s)
        again = d.run(n0, n)
        inst.call("fmi2SetFMUstate", s)  # a state can be restored more than once
        third = d.run(n0, n)
        free_state(inst, s)
    assert len(set(first)) > 1, "outputs must change over the steps (inputs not plausible?)"
    assert first == again == third


@pytest.mark.parametrize("name", FMUS)
def test_serialize_deserialize_round_trip(fmu_dir: Path, name: str) -> None:
    n0, n = STATE_STEPS[name]
    with opened(fmu_dir, name, "a") as a:
        da = Driver(a, name)
        da.run(0, n0)
        s = get_state(a)
        data = serialize(a, s)
        free_state(a, s)
        ref = da.run(n0, n)
        # back into the same instance, from bytes
        s = deserialize(a, data)
        a.call("fmi2SetFMUstate", s)
        free_state(a, s)
        assert da.run(n0, n) == ref
    assert isinstance(data, bytes) and data.startswith(b"AXIRFMUSTATE\n")
    with opened(fmu_dir, name, "b") as b:  # a fresh instance of the same FMU
        db = Driver(b, name)
        s = deserialize(b, data)
        b.call("fmi2SetFMUstate", s)
        free_state(b, s)
        assert db.run(n0, n) == ref
        assert not [m for m in b.log if m.startswith("[ERROR]")], b.log


@pytest.mark.parametrize("name", FMUS)
def test_two_instances_same_fmu(fmu_dir: Path, name: str) -> None:
    """Two live instances, stepped interleaved, behave exactly like one alone (separate
    models, buffers and random generators)."""
    with opened(fmu_dir, name, "solo") as solo:
        ref = Driver(solo, name).run(0, 25)
    with opened(fmu_dir, name, "a") as a, opened(fmu_dir, name, "b") as b:
        da, db = Driver(a, name), Driver(b, name)
        ra, rb = [], []
        for k in range(25):
            da.step(k)
            db.step(k)
            ra.append(da.outputs())
            rb.append(db.outputs())
    assert ra == ref and rb == ref


def test_seeded_instances_differ(fmu_dir: Path) -> None:
    """Same FMU, two live instances, different seeds → different noise."""
    with opened(fmu_dir, "TargetGenerator", "a", {"seed": 1}) as a, \
            opened(fmu_dir, "TargetGenerator", "b", {"seed": 2}) as b:
        ra, rb = Driver(a, "TargetGenerator").run(0, 5), Driver(b, "TargetGenerator").run(0, 5)
    assert ra != rb


def test_all_four_in_one_process(fmu_dir: Path) -> None:
    with ExitStack() as stack:
        insts = {n: stack.enter_context(opened(fmu_dir, n)) for n in FMUS}
        drivers = {n: Driver(i, n) for n, i in insts.items()}
        for k in range(10):
            for d in drivers.values():
                d.step(k)
        for n, inst in insts.items():
            assert not [m for m in inst.log if m.startswith(("[ERROR]", "[FATAL]"))], (n, inst.log)
        guids = {i.md.guid for i in insts.values()}
        assert len(guids) == 4
    mods = {m.split(".")[0] for m in sys.modules if m.startswith("_axir_")}
    assert mods, "the FMUs' bundled packages are loaded in this process"


@pytest.mark.parametrize("name", FMUS)
def test_invalid_parameter_error_at_initialization(fmu_dir: Path, name: str) -> None:
    """fmi2ExitInitializationMode → fmi2Error, log naming the parameter; every later doStep is
    refused (fmi2Error; fmi2Discard without the shim), never fmi2Fatal."""
    pname, value = INVALID[name]
    shim = shimmed(fmu_dir, name)
    with opened(fmu_dir, name, init=False) as inst:
        inst.setup(0.0)
        for k, v in (PARAMS.get(name, {}) | {pname: value}).items():
            inst.set_parameter(k, v)
        inst.enter_init()
        exit_init_invalid(inst, shim)
        errors = [m for m in inst.log if m.startswith("[ERROR]")]
        assert len(errors) == 1 and pname in errors[0], inst.log
        with pytest.raises(FmiError) as e:
            inst.do_step(0.0, STEP[name])
        assert e.value.status == (3 if shim else 2), e.value  # error (discard), not fatal
        assert name in str(e.value) and pname in str(e.value)
        with pytest.raises(FmiError):  # and it stays refused
            inst.do_step(0.0, STEP[name])
        assert not [m for m in inst.log if m.startswith("[FATAL]")]


@pytest.mark.parametrize("name", FMUS)
def test_nan_input_warns_no_crash(fmu_dir: Path, name: str) -> None:
    """A NaN input: Warning naming it, the step succeeds, and after valid inputs return no
    output is non-finite that is not also non-finite in a clean run (the manager reports
    NaN for quantities not estimated yet, e.g. ``threshold`` before the first dwell)."""
    bad = NAN_INPUT[name]

    def nonfinite(d: Driver) -> set[str]:
        return {n for n, v in d.output_values().items() if not math.isfinite(v)}

    with opened(fmu_dir, name, "clean") as inst:
        d = Driver(inst, name)
        d.run(0, 30)
        clean = nonfinite(d)
    with opened(fmu_dir, name) as inst:
        d = Driver(inst, name)
        d.run(0, 5)
        d.step(5, {bad: float("nan")})
        warnings = [m for m in inst.log if m.startswith("[WARNING]")]
        assert any(bad in m for m in warnings), inst.log
        assert not [m for m in inst.log if m.startswith(("[ERROR]", "[FATAL]"))], inst.log
        d.run(6, 24)  # valid inputs again: keeps stepping
        after = nonfinite(d)
    assert after <= clean, f"{name}: non-finite outputs after a NaN input: {sorted(after)}"


def test_log_routed_to_its_own_instance(fmu_dir: Path) -> None:
    with opened(fmu_dir, "Pedestal", "bad", init=False) as bad, \
            opened(fmu_dir, "Pedestal", "good") as good:
        bad.setup(0.0)
        bad.set_parameter("rate_per_volt", -1.0)
        bad.enter_init()
        exit_init_invalid(bad, shimmed(fmu_dir, "Pedestal"))  # logs an Error naming it
        assert not good.log, f"'good' received another instance's messages: {good.log}"
        assert any("rate_per_volt" in m for m in bad.log), bad.log


# ------------------------------------------------------------------ generated interface doc
def test_interfaces_doc_up_to_date(fmu_dir: Path) -> None:
    doc = REPO / "docs" / "interfaces.md"
    fresh = render(fmu_dir)
    assert "`beam.up[1..16,1..3]`" in fresh and "`sum[1..16,1..3]`" in fresh
    current = doc.read_text(encoding="utf-8") if doc.is_file() else ""
    if current != fresh:
        pytest.fail(f"{doc.relative_to(REPO)} is out of date with the FMUs built from the "
                    f"working tree; regenerate with:\n  axir build --out dist && "
                    f"{REGENERATE.replace('DIR', 'dist')}")
