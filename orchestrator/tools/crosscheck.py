"""FMI Cross-Check artifacts: ``axir crosscheck -o DIR``.

Writes, for each of the four FMUs, the exporter layout of the FMI Cross-Check repository
(https://github.com/modelica/fmi-cross-check, FMI-CROSS-CHECK-RULES.md §9.1.4-9.1.5)::

    DIR/fmus/2.0/cs/linux64/axir/<axir version>/<Model>/
        <Model>.fmu        the FMU, byte for byte
        <Model>_in.csv     every input of the FMU (names exactly as in modelDescription.xml)
        <Model>_ref.csv    about 10 key outputs computed by axir from those inputs
        <Model>_ref.opt    StartTime, StopTime, StepSize, RelTol
        README.md          what the files are and how they were made

How the files are made (decisions, also in each README):

- **Inputs**: recorded from the closed loop of :func:`crosscheck_scenario` run by our master
  at a fixed step h (:data:`STEP`) for :data:`DURATION` s (acquisition → tentative →
  confirmed): the values each unit received for each step. Row k of ``_in.csv`` is the
  communication point t_k = k·h and the inputs applied during the step from t_k to t_{k+1};
  the last row (t_N) repeats the last values. Reals are written with 9 significant digits
  (the 1 MB file limit of the rules; the reference is computed from the values as written).
- **Parameters**: none is set. A cross-check importer only has the FMU and these files, so
  the reference uses every parameter's start value from the modelDescription. The recorded
  loop is built around those start values (Tracker and RadarManager at start values), so the
  Tracker's and RadarManager's references are the loop's own closed-loop behaviour; the
  TargetGenerator (its start-value trajectory, not the loop's target) and the Pedestal
  (el0 = 0, not 0.1 rad) respond to the same inputs from their own initial states.
- **Reference**: computed by axir's own FMI 2.0 importer
  (:class:`~axir.orchestrator.fmi.FmuInstance` over fmpy's low-level API): setup,
  initialization, then at each t_k: set all inputs to row k, ``fmi2DoStep(t_k, t_{k+1} −
  t_k)``, get the key outputs. t_k = k·h in floating point, as fmpy's ``simulate_fmu`` computes
  its communication points, so a replay with fmpy is exact.
- **Names with commas**: FMI 2.0 structured names such as ``beam.up[7,2]`` contain commas;
  they are quoted in the header as the rules require (``"beam.up[7,2]"``). Readers that split
  the header at every comma (``fmpy.util.read_csv``) need a quote-aware CSV reader for the
  Tracker and RadarManager ``_in.csv``; the ``_ref.csv`` files hold scalar outputs only.
"""

from __future__ import annotations

import csv
import json
import math
import shutil
from dataclasses import replace
from importlib import metadata
from pathlib import Path
from typing import Any

import click
import numpy as np

from axir.models.system import UNITS

from ..config import DEFAULT_FMU_DIR
from ..errors import AxirError
from ..fmi import FmuInstance, load_model_description
from ..run import run_scenario
from ..scenario import load_scenario
from ..scenario_spec import Scenario

#: [s] fixed communication step of the recorded loop and of the reference
STEP = 1e-4
#: [s] recorded time: 400 steps; the Tracker's 200-input file stays below the 1 MB limit
DURATION = 0.04
MAX_CSV_BYTES = 1_000_000  # FMI-CROSS-CHECK-RULES.md Appendix B
#: the key outputs written to <Model>_ref.csv (≈ 10 per FMU, scalars only)
KEY_OUTPUTS: dict[str, tuple[str, ...]] = {
    "TargetGenerator": ("truth.x", "truth.y", "truth.z", "truth.range", "truth.az",
                        "truth.el", "truth.range_rate", "truth.apparent_range",
                        "truth.doppler", "truth.snr_db"),
    "Tracker": ("dev.az", "dev.el", "dev.range", "track.range", "track.az", "track.el",
                "cmd.az", "cmd.el", "gate.start", "track.valid"),
    "Pedestal": ("az", "el", "az.rate", "el.rate", "pot.az.a", "pot.az.b", "pot.el.a",
                 "pot.el.b"),
    "RadarManager": ("mode", "pri", "alpha", "beta", "bandwidth", "range.offset",
                     "gate.command", "detection", "dwell.done", "ambiguity.resolved"),
}
#: elevation [rad] of the Tracker's designation start value (models/tracker.py)
DESIGNATION_EL = 0.1
#: the recorded loop's target: 10.3 km out near the Tracker's and RadarManager's start-value
#: designation (az 0, el 0.1 rad, range 10 km), 100 m east of it (az ≈ 0.56°: the track
#: azimuth stays clear of the 0/2π wrap), flying east at 200 m/s and inbound at 250 m/s (a
#: radial speed clear of the RadarManager's clutter notch, which rejects targets within
#: ``clutter_notch_speed`` of zero Doppler as clutter, and of the blind speeds near ±150 m/s;
#: its folded Doppler is read without a Doppler peak search, so the loop confirms at
#: 0.0347 s, inside :data:`DURATION`; inbound at 150 m/s it confirms at 0.085 s)
TARGET = {"type": "piecewise",
          "position": [100.0, 10300.0 * math.cos(DESIGNATION_EL),
                       10300.0 * math.sin(DESIGNATION_EL)],
          "velocity": [200.0, -250.0, 0.0], "t0": 0.0,
          "segments": [{"type": "cv", "onset": 0.0}]}
PLATFORM = "linux64"
TOOL = "axir"
REL_TOL = 1e-4  # _ref.opt RelTol (required key; no solver inside these co-simulation FMUs)


def _fmt(kind: str, value: float) -> str:
    """A CSV number: C float literal (9 significant digits) or an integer (Integer/Boolean)."""
    if kind in ("Integer", "Boolean"):
        return str(int(value))
    return f"{value:.9g}"


def _write_csv(path: Path, names: list[str], rows: list[list[str]]) -> None:
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(",".join(f'"{n}"' for n in ["time", *names]) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")
    size = path.stat().st_size
    if size > MAX_CSV_BYTES:
        raise AxirError(f"{path}: {size} bytes, above the cross-check limit of 1 MB "
                        "(use a shorter --duration)")


def read_crosscheck_csv(path: Path) -> tuple[list[str], np.ndarray]:
    """(names without "time", values with time in column 0) of a cross-check CSV, read with a
    quote-aware reader (names may contain commas)."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows or rows[0][0] != "time":
        raise AxirError(f"{path}: the first column must be 'time'")
    return rows[0][1:], np.array([[float(x) for x in r] for r in rows[1:]], dtype=float)


def crosscheck_scenario(step: float = STEP) -> Scenario:
    """The loop the inputs are recorded from: the built-in ``closed-loop`` system (same
    connections, Gauss-Seidel order) at a fixed ``step``, with the Tracker and the
    RadarManager at their start values — designation azimuth 0, elevation 0.1 rad, range
    10 km — so that their references (computed with start values, as every cross-check
    importer runs them) are the loop itself; the target (:data:`TARGET`) is inside the beam
    at the designation and the pedestal starts on it (el0 = 0.1 rad); confirmed within
    :data:`DURATION` (seed 1; tests/test_crosscheck.py)."""
    sc = load_scenario("closed-loop")
    units = {name: {"fmu": spec.get("fmu", f"{name}.fmu"), "parameters": {}}
             for name, spec in sc.units.items()}
    units["TargetGenerator"]["parameters"]["trajectory"] = json.dumps(TARGET)
    units["Pedestal"]["parameters"]["el0"] = DESIGNATION_EL
    return replace(sc, name="crosscheck", units=units, step=step, decimation=1)


def record_inputs(fmu_dir: Path, duration: float, step: float, seed: int | None
                  ) -> dict[str, np.ndarray]:
    """Per unit, the inputs it received for each step of :func:`crosscheck_scenario`
    (N × n_inputs, modelDescription order): row k holds the inputs of the step from t_k to
    t_{k+1}."""
    inputs = {m: [v.name for v in load_model_description(Path(fmu_dir) / f"{m}.fmu")
                  .modelVariables if v.causality == "input"] for m in UNITS}
    refs = [f"{m}.{n}" for m in UNITS for n in inputs[m]]
    sc = replace(crosscheck_scenario(step), record=refs)
    _, rec = run_scenario(sc, Path(fmu_dir), None, seed=seed, duration=duration,
                          progress=False)
    data = rec.data[1:, 1:]  # the record after step k holds the inputs used in step k
    out, col = {}, 0
    for m in UNITS:
        out[m] = data[:, col:col + len(inputs[m])]
        col += len(inputs[m])
    return out


def reference(fmu: Path, in_names: list[str], inputs: np.ndarray, outputs: list[str],
              step: float) -> np.ndarray:
    """Outputs at t_0 … t_N of ``fmu`` (start values for every parameter) driven by ``inputs``
    (N+1 rows; row k is applied from t_k = k·step to t_{k+1}): (N+1) × (1 + len(outputs))."""
    n = len(inputs) - 1
    times = [k * step for k in range(n + 1)]
    out = np.empty((n + 1, 1 + len(outputs)))
    with FmuInstance(fmu, fmu.stem, logging_on=True) as inst:
        ports_in: dict[str, Any] = {}
        for j, name in enumerate(in_names):
            kind = inst.variable(name).type
            ports_in.setdefault(kind, ([], []))
            ports_in[kind][0].append(name)
            ports_in[kind][1].append(j)
        ins = [(inst.port(names), cols, kind != "Real")
               for kind, (names, cols) in ports_in.items()]
        kinds = {v: inst.variable(v).type for v in outputs}
        groups: dict[str, list[int]] = {}
        for i, v in enumerate(outputs):
            groups.setdefault(kinds[v], []).append(i)
        outs = [(inst.port([outputs[i] for i in idx]), [1 + i for i in idx])
                for idx in groups.values()]
        inst.setup(0.0, times[-1])
        inst.enter_init()
        inst.exit_init()

        def sample(k: int) -> None:
            out[k, 0] = times[k]
            for port, cols in outs:
                out[k, cols] = port.read()

        sample(0)
        for k in range(n):
            for port, cols, integral in ins:
                row = inputs[k, cols]
                port.write([int(x) for x in row] if integral else row.tolist())
            inst.do_step(times[k], times[k + 1] - times[k])
            sample(k + 1)
        inst.terminate()
    return out


NOTES = {
    "TargetGenerator": "Its start-value trajectory is not the loop's target (an aircraft "
                       "13.5 km away at azimuth 333°), so the beams hold noise and clutter "
                       "only; the truth outputs follow that start-value trajectory.",
    "Tracker": "The loop ran this unit with the same start values: the reference is the "
               "closed-loop track (inputs rounded to 9 digits).",
    "Pedestal": "The loop started the pedestal at el0 = 0.1 rad; with its start value "
                "el0 = 0 the reference responds to the same commands from elevation 0.",
    "RadarManager": "The loop ran this unit with the same start values: the reference is the "
                    "loop's mode sequence (acquisition, tentative, confirmed).",
}

README = """# {model} — axir {version} (pythonfmu {pythonfmu}), FMI 2.0 co-simulation, linux64

{description}

## Files

| file | content |
|---|---|
| `{model}.fmu` | the FMU as built by `axir build` (GUID `{guid}`) |
| `{model}_in.csv` | all {n_in} inputs of the FMU, {n_rows} rows, t = 0 … {stop} s every {step} s |
| `{model}_ref.csv` | {n_out} key outputs: {outputs} |
| `{model}_ref.opt` | StartTime, StopTime, StepSize (fixed communication step), RelTol |

## How the inputs and the reference were made

- Inputs: recorded from axir's closed tracking loop (the four FMUs, Gauss-Seidel, fixed
  step {step} s, seed {seed}): the Tracker and the RadarManager at their start values
  (designation azimuth 0, elevation 0.1 rad, range 10 km), a target 10.3 km away, 100 m east
  of the designation, flying east at 200 m/s and closing at 150 m/s, the pedestal starting on
  the designation (el0 = 0.1 rad). The radar goes acquisition → tentative → confirmed within
  the recorded time (checked by axir's tests/test_crosscheck.py). These are the values this
  unit received
  for each step: row k holds t_k = k·{step} s and the inputs applied during the step from t_k
  to t_(k+1) (sample and hold; the last row repeats the previous one). Reals: 9 significant
  digits.
- Parameters: none is set; every parameter keeps its start value from modelDescription.xml.
  {note}
- Reference: axir's FMI 2.0 importer: fmi2SetupExperiment(0, {stop}),
  fmi2EnterInitializationMode, fmi2ExitInitializationMode, output row at t = 0; then for each
  k: set all inputs to row k, fmi2DoStep(t_k, t_(k+1) − t_k), output row at t_(k+1).
  `python -c "import fmpy; fmpy.simulate_fmu('{model}.fmu', stop_time={stop},
  output_interval={step}, input=<_in.csv as a structured array>)"` reproduces it exactly.
- Names: FMI 2.0 structured names such as `beam.up[7,2]` contain a comma; they are quoted in
  the CSV header as the rules require. Read `_in.csv` with a quote-aware CSV reader (Python's
  `csv` module); `fmpy.util.read_csv` splits such names.

## Requirements of the importer

A pythonfmu FMU runs Python code: the importing process needs CPython 3.10+ with numpy and
scipy. A Python host (fmpy, libcosimpy, …) provides it; a non-Python host needs `LD_PRELOAD`
of libpython, `PYTHONHOME` and `PYTHONPATH` (see axir's docs/other_tools.md, "Using the FMUs
in other tools").
"""


def write_crosscheck(out_dir: Path, fmu_dir: Path, *, duration: float = DURATION,
                     step: float = STEP, seed: int | None = None) -> list[Path]:
    """Write the cross-check layout for the four FMUs under ``out_dir``; returns the model
    directories."""
    if not step > 0 or not duration >= step:
        raise AxirError(f"crosscheck: need 0 < step <= duration, got step {step}, "
                        f"duration {duration}")
    fmu_dir = Path(fmu_dir)
    for m in UNITS:
        if not (fmu_dir / f"{m}.fmu").is_file():
            raise AxirError(f"FMU file not found: {fmu_dir / f'{m}.fmu'}; run `axir build` "
                            "first or pass --fmu-dir")
    version = metadata.version("axir")
    pythonfmu = metadata.version("pythonfmu")
    recorded = record_inputs(fmu_dir, duration, step, seed)
    seed_used = load_scenario("closed-loop").seed if seed is None else seed
    dirs = []
    for m in UNITS:
        fmu = fmu_dir / f"{m}.fmu"
        md = load_model_description(fmu)
        ins = [v for v in md.modelVariables if v.causality == "input"]
        in_names = [v.name for v in ins]
        u = recorded[m]
        n = len(u)
        rows_in = []
        for k in range(n + 1):
            values = u[min(k, n - 1)]
            rows_in.append([repr(k * step)] + [_fmt(v.type, x) for v, x in zip(ins, values,
                                                                                  strict=True)])
        d = out_dir / "fmus" / "2.0" / "cs" / PLATFORM / TOOL / version / m
        d.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(fmu, d / f"{m}.fmu")
        _write_csv(d / f"{m}_in.csv", in_names, rows_in)
        # the reference is computed from the values exactly as written
        _, written = read_crosscheck_csv(d / f"{m}_in.csv")
        outputs = list(KEY_OUTPUTS[m])
        ref = reference(fmu, in_names, written[:, 1:], outputs, step)
        kinds = {v.name: v.type for v in md.modelVariables}
        _write_csv(d / f"{m}_ref.csv", outputs,
                   [[repr(float(r[0]))] + [repr(float(x)) if kinds[o] == "Real" else
                                           str(int(x)) for o, x in zip(outputs, r[1:],
                                                                       strict=True)]
                    for r in ref])
        stop = n * step
        (d / f"{m}_ref.opt").write_text(
            f"StartTime, 0.0\nStopTime, {stop!r}\nStepSize, {step!r}\nRelTol, {REL_TOL!r}\n")
        (d / "README.md").write_text(README.format(
            model=m, version=version, pythonfmu=pythonfmu, description=md.description,
            guid=md.guid, n_in=len(ins), n_rows=n + 1, stop=repr(stop), step=repr(step),
            n_out=len(outputs), outputs=", ".join(f"`{o}`" for o in outputs),
            seed=seed_used, note=NOTES[m]))
        dirs.append(d)
    return dirs


@click.command()
@click.option("-o", "--out", "out_dir", required=True,
              type=click.Path(file_okay=False, path_type=Path), help="Output directory.")
@click.option("--fmu-dir", default=None, type=click.Path(file_okay=False, path_type=Path),
              help="Where the FMUs are (default: dist, or $AXIR_FMU_DIR).")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True), default=DURATION,
              show_default=True, help="Recorded time [s].")
@click.option("--seed", type=click.IntRange(min=0), help="Base seed of the recorded loop.")
def crosscheck(out_dir: Path, fmu_dir: Path | None, duration: float, seed: int | None) -> None:
    """Write the FMI Cross-Check layout for the four FMUs under OUT:
    fmus/2.0/cs/linux64/axir/<version>/<Model>/ with <Model>.fmu, <Model>_in.csv (all
    inputs, recorded from the closed loop), <Model>_ref.csv (key outputs), <Model>_ref.opt
    and README.md."""
    for d in write_crosscheck(out_dir, fmu_dir or Path(DEFAULT_FMU_DIR), duration=duration,
                              seed=seed):
        click.echo(f"wrote {d}")


__all__ = ["KEY_OUTPUTS", "crosscheck", "read_crosscheck_csv", "reference",
           "write_crosscheck"]
