"""FMI Cross-Check artifacts (``axir crosscheck``): layout, file rules, and a replay of every
``<Model>_in.csv`` by fmpy's ``simulate_fmu`` (an importer that is not ours) against
``<Model>_ref.csv``.

Stated tolerance of the replay: none (identical values): fmpy computes the communication
points as k·h like the reference run, applies the inputs sampled at those points, and the FMUs
are deterministic. fmpy's own cross-check criterion (``fmpy.cross_check.validate_result``,
the epsilon band of the cross-check repository) is checked too.
"""

from __future__ import annotations

import math
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.cross_check import validate_result
from fmpy.cross_check.validate_vendor_repo import validate_test_fmu
from fmpy.util import read_ref_opt_file

from axir.models.system import UNITS
from axir.orchestrator.errors import AxirError
from axir.orchestrator.fmi import load_model_description
from axir.orchestrator.tools.crosscheck import (
    DURATION,
    KEY_OUTPUTS,
    MAX_CSV_BYTES,
    STEP,
    read_crosscheck_csv,
    write_crosscheck,
)

N = round(DURATION / STEP)


@pytest.fixture(scope="module")
def xc(fmu_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("crosscheck")
    dirs = write_crosscheck(out, fmu_dir)
    return {d.name: d for d in dirs}


def _structured(names: list[str], values: np.ndarray) -> np.ndarray:
    arr = np.zeros(len(values), dtype=[("time", float)] + [(n, float) for n in names])
    arr["time"] = values[:, 0]
    for j, n in enumerate(names):
        arr[n] = values[:, 1 + j]
    return arr


def test_layout(xc: dict[str, Path], fmu_dir: Path) -> None:
    version = metadata.version("axir")
    assert sorted(xc) == sorted(UNITS)
    for m, d in xc.items():
        assert d.parts[-7:] == ("fmus", "2.0", "cs", "linux64", "axir", version, m)
        assert {p.name for p in d.iterdir()} == {f"{m}.fmu", f"{m}_in.csv", f"{m}_ref.csv",
                                                 f"{m}_ref.opt", "README.md"}
        assert (d / f"{m}.fmu").read_bytes() == (fmu_dir / f"{m}.fmu").read_bytes()
        for f in (f"{m}_in.csv", f"{m}_ref.csv"):
            assert (d / f).stat().st_size <= MAX_CSV_BYTES, f
        readme = (d / "README.md").read_text()
        assert m in readme and "start value" in readme


def test_in_csv_holds_exactly_the_inputs(xc: dict[str, Path]) -> None:
    """Header: "time" then every input of the FMU, in modelDescription order, quoted; time
    k·h for k = 0 … N; Integer/Boolean inputs written as integers."""
    for m, d in xc.items():
        md = load_model_description(d / f"{m}.fmu")
        inputs = [v for v in md.modelVariables if v.causality == "input"]
        header = (d / f"{m}_in.csv").read_text().splitlines()[0]
        assert header == ",".join(f'"{n}"' for n in ["time", *(v.name for v in inputs)])
        names, u = read_crosscheck_csv(d / f"{m}_in.csv")
        assert names == [v.name for v in inputs]
        assert u.shape == (N + 1, 1 + len(inputs))
        assert u[:, 0].tolist() == [k * STEP for k in range(N + 1)]
        for j, v in enumerate(inputs):
            if v.type in ("Integer", "Boolean"):
                assert np.all(u[:, 1 + j] == np.round(u[:, 1 + j])), v.name
        np.testing.assert_array_equal(u[-1, 1:], u[-2, 1:])  # the last row holds


def test_ref_files(xc: dict[str, Path]) -> None:
    for m, d in xc.items():
        opt = read_ref_opt_file(str(d / f"{m}_ref.opt"))
        assert opt["StartTime"] == 0.0 and opt["StopTime"] == N * STEP
        assert opt["StepSize"] == STEP and opt["RelTol"] > 0
        names, ref = read_crosscheck_csv(d / f"{m}_ref.csv")
        assert names == list(KEY_OUTPUTS[m]) and 8 <= len(names) <= 12
        assert ref[0, 0] == opt["StartTime"] and ref[-1, 0] == opt["StopTime"]
        assert np.all(np.isfinite(ref))


def test_fmpy_vendor_repo_validator(xc: dict[str, Path]) -> None:
    """fmpy's validator of the cross-check repository (modelDescription schema, .opt, CSVs,
    sizes). Its CSV reader splits the header at every comma, so the Tracker's and the
    RadarManager's _in.csv, whose FMI 2.0 names hold commas (``beam.up[1,2]``), are the one
    problem it reports (documented in their README)."""
    for m, d in xc.items():
        problems = validate_test_fmu(str(d))
        if m in ("Tracker", "RadarManager"):
            assert len(problems) == 1 and f"{m}_in.csv" in problems[0], problems
            assert "columns instead of" in problems[0]
        else:
            assert problems == [], problems


@pytest.mark.parametrize("model", UNITS)
def test_fmpy_replay_matches_the_reference(xc: dict[str, Path], model: str) -> None:
    d = xc[model]
    names, u = read_crosscheck_csv(d / f"{model}_in.csv")
    out_names, ref = read_crosscheck_csv(d / f"{model}_ref.csv")
    opt = read_ref_opt_file(str(d / f"{model}_ref.opt"))
    res = fmpy.simulate_fmu(str(d / f"{model}.fmu"), start_time=opt["StartTime"],
                            stop_time=opt["StopTime"], output_interval=opt["StepSize"],
                            input=_structured(names, u), output=out_names)
    got = np.column_stack([res[n] for n in ["time", *out_names]])
    assert got.shape == ref.shape
    differing = [n for j, n in enumerate(["time", *out_names])
                 if not np.array_equal(got[:, j], ref[:, j])]
    assert differing == []
    assert validate_result(res, _structured(out_names, ref), opt["StartTime"],
                           opt["StopTime"]) is None


def test_references_are_meaningful(xc: dict[str, Path]) -> None:
    """The RadarManager's reference goes acquisition -> tentative -> confirmed and the
    Tracker's confirmed track sits on the 10.3 km target; the TargetGenerator flies its
    start-value trajectory, 13.5 km away (models/radar/trajectory.py DEFAULT_TRAJECTORY_SPEC)."""
    names, rm = read_crosscheck_csv(xc["RadarManager"] / "RadarManager_ref.csv")
    mode = rm[:, 1 + names.index("mode")]
    assert set(np.unique(mode)) == {0, 1, 2} and mode[-1] == 2
    names, tr = read_crosscheck_csv(xc["Tracker"] / "Tracker_ref.csv")
    valid = tr[:, 1 + names.index("track.valid")] == 1
    assert valid[-1]
    rng = tr[valid, 1 + names.index("track.range")][-50:]
    assert np.all(np.abs(rng - 10300.5) < 75.0)  # the target: sqrt(100² + 10300²) m
    names, tg = read_crosscheck_csv(xc["TargetGenerator"] / "TargetGenerator_ref.csv")
    # outputs are computed at initialization: at t = 0 the aircraft is at its start point
    # (-6000, 12000, 1500) m (13.5 km), after the first step at + (200, 0, 10) m/s · h
    t1 = tg[1, 0]
    assert tg[0, 0] == 0.0
    assert tg[0, 1 + names.index("truth.range")] == pytest.approx(13500.0, rel=1e-12)
    assert tg[1, 1 + names.index("truth.range")] == pytest.approx(
        math.dist((0, 0, 0), (-6000.0 + 200.0 * t1, 12000.0, 1500.0 + 10.0 * t1)), rel=1e-12)


def test_errors(fmu_dir: Path, tmp_path: Path) -> None:
    with pytest.raises(AxirError, match="FMU file not found"):
        write_crosscheck(tmp_path / "out", tmp_path)
    with pytest.raises(AxirError, match="above the cross-check limit of 1 MB"):
        write_crosscheck(tmp_path / "big", fmu_dir, duration=0.06)
    r = subprocess.run([sys.executable, "-m", "axir.orchestrator.cli", "crosscheck", "-o",
                        str(tmp_path / "x"), "--fmu-dir", str(tmp_path)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.startswith("error: FMU file not found")
