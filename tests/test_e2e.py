"""End to end through the four FMUs: the built-in ``closed-loop`` scenario, shortened and
seeded, run by ``run_scenario`` (master + recorder + results.csv/summary.json).

Durations are short (≈ 9000 macro steps per simulated second at ≈ 0.4–0.8 ms per step).
"""

from __future__ import annotations

import copy
import json
import math
import zipfile
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fmpy.util import read_csv

import axir.orchestrator.run as run_mod
from axir.orchestrator.errors import AxirError
from axir.orchestrator.master import Master
from axir.orchestrator.metrics import angle_between
from axir.orchestrator.run import run_scenario
from axir.orchestrator.scenario import Scenario, load_scenario

SEED = 1
DURATION = 1.5  # [s] long enough to acquire (≈ 0.2 s) and hold the confirmed track
BIN_M = 75.0  # range bin [m]
BEAMWIDTH = math.radians(2.5)  # 3 dB beamwidth of each beam (SYSTEM.md)
#: Pointing bound: the target stays inside the 3 dB half-beamwidth (1.25°) of boresight
#: whenever the track is confirmed ("well inside the 2.5° beam").
POINTING_BOUND = BEAMWIDTH / 2


def scenario(**params: dict[str, Any]) -> Scenario:
    """The built-in closed loop with per-unit parameter overrides (``Tracker={...}``)."""
    sc = load_scenario("closed-loop")
    units = copy.deepcopy(sc.units)
    for unit, extra in params.items():
        units[unit].setdefault("parameters", {}).update(extra)
    return replace(sc, units=units)


def run(fmu_dir: Path, out: Path | None, sc: Scenario | None = None, **kw: Any):
    return run_scenario(sc or scenario(), fmu_dir, out, progress=False, **kw)


# ------------------------------------------------------------------ the reference run
@pytest.fixture(scope="module")
def closed_loop(fmu_dir: Path, tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("closed_loop")
    summary, rec = run(fmu_dir, out, seed=SEED, duration=DURATION)
    return summary, rec, out


def test_closed_loop_acquires_and_confirms(closed_loop) -> None:
    summary, rec, out = closed_loop
    assert summary["complete"] is True and summary["error"] is None
    assert summary["end_time"] == pytest.approx(DURATION, abs=1e-9)
    assert summary["seed"] == SEED and summary["scenario"] == "closed-loop"
    assert summary["lock_time"] is not None and summary["lock_time"] < 1.0, summary
    assert summary["final_mode"] == "confirmed", summary
    assert summary["time_in_mode"]["confirmed"] > 0.5 * DURATION, summary
    assert json.loads((out / "summary.json").read_text()) == summary
    # variable step: the master follows the manager's PRI (≈ 100–112 µs), not a fixed step
    pri = rec.column("RadarManager.pri")
    assert pri.min() > 0.9e-4 and pri.max() < 1.2e-4
    assert summary["steps"] == pytest.approx(DURATION / np.mean(pri), rel=0.05)


def test_closed_loop_range_error_below_one_bin(closed_loop) -> None:
    summary = closed_loop[0]
    assert summary["rms_range_error_m"] is not None
    assert summary["rms_range_error_m"] < BIN_M, summary


def test_closed_loop_pointing_inside_beam(closed_loop) -> None:
    """Whenever the track is confirmed, the antenna points within half the 3 dB beamwidth
    (1.25°) of the target, and the confirmed track is never dropped once acquired."""
    summary, rec, _ = closed_loop
    c = rec.column
    conf = c("RadarManager.mode") == 2
    err = angle_between(c("Pedestal.az"), c("Pedestal.el"), c("TargetGenerator.truth.az"),
                        c("TargetGenerator.truth.el"))
    assert summary["max_pointing_error_rad"] == pytest.approx(err[conf].max())
    assert summary["max_pointing_error_rad"] < POINTING_BOUND, (
        f"max pointing error {math.degrees(summary['max_pointing_error_rad']):.2f}° "
        f"(bound {math.degrees(POINTING_BOUND):.2f}°)")
    first = int(np.argmax(conf))
    assert conf[first:].all(), "the confirmed track was dropped"


def test_results_csv_readable_by_fmpy(closed_loop) -> None:
    summary, rec, out = closed_loop
    data = read_csv(str(out / "results.csv"))
    assert data.dtype.names[0] == "time"
    assert list(data.dtype.names[1:]) == rec.variables
    assert len(data) == rec.n == summary["samples"]
    assert np.all(np.diff(data["time"]) > 0)
    assert data["time"][0] == 0.0 and data["time"][-1] == pytest.approx(DURATION)
    np.testing.assert_array_equal(data["Tracker.track.range"], rec.column("Tracker.track.range"))
    assert set(np.unique(data["RadarManager.mode"])) <= {0, 1, 2}


# ------------------------------------------------------------------ determinism
def test_same_seed_byte_identical_other_seed_differs(fmu_dir: Path, tmp_path: Path) -> None:
    outs = {}
    for tag, seed in (("a", 7), ("b", 7), ("c", 8)):
        run(fmu_dir, tmp_path / tag, seed=seed, duration=0.25)
        outs[tag] = (tmp_path / tag / "results.csv").read_bytes()
    assert outs["a"] == outs["b"], "same scenario and seed must give a byte-identical results.csv"
    assert outs["a"] != outs["c"], "a different seed must change the results"


# ------------------------------------------------------------------ master variants
def test_jacobi_and_gauss_seidel(fmu_dir: Path, tmp_path: Path) -> None:
    """Both orders run the loop and acquire the target.

    Jacobi needs the Tracker parameter ``gate_latency = 2``: in Jacobi every unit takes its
    inputs from the outputs at t, so the TargetGenerator forms a PRI's beams with the
    ``gate.start`` the Tracker output one step earlier, and those beams reach the Tracker one
    step later still: the beams the Tracker processes were formed with the gate it output
    *two* steps before (Gauss-Seidel, generator stepped just before the tracker: one step).
    The Tracker turns the bin index into a range with that gate, so with the wrong latency
    every gate jump (search windows, ambiguity offsets, 75 m bins) is mis-attributed.
    """
    d = 0.5
    gs, _ = run(fmu_dir, tmp_path / "gs", duration=d)
    sc = replace(scenario(Tracker={"gate_latency": 2}), algorithm="jacobi")
    jac, _ = run(fmu_dir, tmp_path / "jacobi", sc, duration=d)
    for s in (gs, jac):
        assert s["complete"] and s["error"] is None
        assert s["lock_time"] is not None and s["lock_time"] < d, s
        assert s["rms_range_error_m"] < BIN_M, s
    assert gs["algorithm"] == "gauss-seidel" and jac["algorithm"] == "jacobi"
    assert (tmp_path / "gs" / "results.csv").read_bytes() != (
        tmp_path / "jacobi" / "results.csv").read_bytes()


FIXED = 0.4  # [s] simulated time of the fixed-step run


@pytest.fixture(scope="module")
def fixed_step_run(fmu_dir: Path):
    return run(fmu_dir, None, replace(scenario(), step=1e-4), duration=FIXED)


def test_fixed_step(fixed_step_run) -> None:
    """A fixed communication step (1e-4 s, not the manager's PRI) runs the loop: exact
    time grid, no FMU error, the target is acquired and the final mode is confirmed."""
    summary, rec = fixed_step_run
    assert summary["complete"] and summary["error"] is None
    assert summary["steps"] == round(FIXED / 1e-4)
    t = rec.data[:, 0]
    np.testing.assert_allclose(np.diff(t[:-1]), 1e-4 * rec.decimation, rtol=0, atol=1e-12)
    assert t[-1] == pytest.approx(FIXED)
    assert summary["lock_time"] is not None and summary["lock_time"] < FIXED, summary


def test_fixed_step_range_accuracy(fixed_step_run) -> None:
    """SYSTEM.md: every FMU must also run *correctly* at any fixed step."""
    summary, _ = fixed_step_run
    assert summary["rms_range_error_m"] < BIN_M, summary


# ------------------------------------------------------------------ failures and interrupts
def test_out_of_range_parameter_refused_before_the_run(fmu_dir: Path, tmp_path: Path) -> None:
    """A parameter outside the range its model declares (Param, here rate_per_volt > 0) is
    refused before any FMU is loaded, naming unit and parameter; nothing is written."""
    sc = scenario(Tracker={"rate_per_volt": -1.0})
    with pytest.raises(AxirError) as e:
        run(fmu_dir, tmp_path / "out", sc, duration=0.1)
    msg = str(e.value)
    assert "Tracker.rate_per_volt = -1.0 is out of range" in msg, msg
    assert not (tmp_path / "out").exists()


def test_fmu_failure_at_initialization_partial_results(fmu_dir: Path, tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """Past the pre-run checks, an FMU refusing its parameters (the FMU's own check, here
    reached by skipping the pre-run value check) still leaves a summary saying why."""
    monkeypatch.setattr(run_mod, "check_values", lambda *a, **k: None)
    sc = scenario(Tracker={"rate_per_volt": -1.0})
    with pytest.raises(AxirError) as e:
        run(fmu_dir, tmp_path, sc, duration=0.1)
    msg = str(e.value)
    assert "rate_per_volt" in msg, msg
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["complete"] is False and summary["status"] == "failed"
    assert "rate_per_volt" in summary["error"]
    assert (tmp_path / "results.csv").read_text().startswith('"time",')
    with zipfile.ZipFile(fmu_dir / "Tracker.fmu") as z:
        if "binaries/linux64/Tracker_pythonfmu.so" in z.namelist():
            # the C shim (default build) answers fmi2Error at initialization: nothing ran
            assert msg.startswith("Tracker: fmi2ExitInitializationMode returned error"), msg
            assert summary["steps"] == 0
        else:
            assert msg.startswith("Tracker: fmi2DoStep returned discard"), msg


class _InterruptAfter:
    """Stands in for run.Progress: raises KeyboardInterrupt (Ctrl-C) after ``N`` steps."""

    N = 500

    def __init__(self, duration: float, enabled: bool | None = None) -> None:
        self.steps = 0

    def start(self, master: Master) -> None:
        pass

    def step(self, master: Master, t_ns: int) -> None:
        self.steps += 1
        if self.steps == self.N:
            raise KeyboardInterrupt

    def finish(self, master: Master, complete: bool) -> None:
        self.finished = complete


def test_ctrl_c_writes_partial_results(fmu_dir: Path, tmp_path: Path,
                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(run_mod, "Progress", _InterruptAfter)
    summary, rec = run_scenario(scenario(), fmu_dir, tmp_path, duration=1.0, progress=True)
    assert summary["complete"] is False and summary["error"] is None
    assert summary["steps"] == _InterruptAfter.N
    on_disk = json.loads((tmp_path / "summary.json").read_text())
    assert on_disk["complete"] is False
    data = read_csv(str(tmp_path / "results.csv"))
    assert len(data) == rec.n >= 2
    assert 0.0 < data["time"][-1] < 1.0  # the state at the interrupt is the last row
    assert data["time"][-1] == pytest.approx(summary["end_time"])
