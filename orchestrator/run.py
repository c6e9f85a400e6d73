"""Run one scenario through the master and write ``results.csv`` and ``summary.json``: the
master steps, observers record (:mod:`.record`) and show progress (:mod:`.progress`),
:mod:`.metrics` turns the record into the summary figures."""

from __future__ import annotations

import platform
import signal
import time
from collections.abc import Mapping
from importlib import metadata
from pathlib import Path
from typing import Any

from axir.models.system import unit_seed

from .archive import file_digest
from .errors import AxirError
from .fmi import FmuInstance
from .interrupt import StopOnSignal
from .master import Master
from .metrics import summarize
from .outdir import OutputFolder, claim, write_json_atomic
from .plot_probe import LockSnapshot, extra_recorder
from .plots import PLOT_FILES
from .preflight import check_duration, check_fmu_file, check_values
from .progress import Progress
from .record import Recorder, write_csv
from .scenario_spec import Scenario
from .system import SystemDescription


def versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("axir", "fmpy", "pythonfmu", "numpy"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def seeded_parameters(system: SystemDescription, instances: Mapping[str, FmuInstance],
                      seed: int) -> dict[str, dict[str, Any]]:
    """Parameter values per unit for a run with base ``seed``: the system description's values,
    plus ``seed = unit_seed(seed, unit)`` for every unit whose FMU has a ``seed`` parameter
    that the description does not set (an explicit unit seed wins). The description itself is
    not modified (campaigns initialise the same system with many seeds)."""
    out: dict[str, dict[str, Any]] = {}
    for name, inst in instances.items():
        params = dict(system.units[name].parameters)
        v = inst.variables.get("seed")
        if v is not None and v.causality == "parameter" and "seed" not in params:
            params["seed"] = unit_seed(seed, name)
        out[name] = params
    return out


#: the files a run writes into its output folder (what a reused folder may hold; cleared first)
RUN_FILES = ("results.csv", "summary.json", *PLOT_FILES)


def preflight(scenario: Scenario, system: SystemDescription, long_ok: bool = False) -> None:
    """Check before the run what can be checked (:mod:`.preflight`): the FMU files, the
    parameter/input values against their variables, the estimated wall time."""
    mds = {name: check_fmu_file(spec.fmu, name) for name, spec in system.units.items()}
    check_values({n: u.parameters for n, u in system.units.items()}, mds, scenario.source)
    check_duration(scenario.duration, scenario.step or scenario.initial_step, long_ok)


def run_scenario(
    scenario: Scenario,
    fmu_dir: Path,
    out_dir: Path | None,
    *,
    seed: int | None = None,
    duration: float | None = None,
    progress: bool | None = None,
    plot: bool = False,
    long_ok: bool = False,
) -> tuple[dict[str, Any], Recorder]:
    """Run ``scenario``; write results.csv + summary.json (+ the PNGs with ``plot``) into
    ``out_dir`` (if given).

    Before the run: :func:`preflight`, and the output folder is claimed (:mod:`.outdir`:
    created, locked for this run, an earlier run's files removed) and gets a ``summary.json``
    with ``"status": "running"``. During the run, rows stream into ``results.csv`` (flushed
    at least every second). At the end, ``summary.json`` is replaced atomically by the outcome.
    Results are written even when the run is interrupted (Ctrl-C, SIGTERM, SIGHUP) or an FMU
    fails at initialization or mid-run; the summary then says ``complete: false`` and gives
    the ``error`` or the ``signal``.
    """
    scenario = scenario.with_overrides(seed, duration)
    system = scenario.system(Path(fmu_dir))
    preflight(scenario, system, long_ok)
    folder = claim(Path(out_dir), RUN_FILES) if out_dir is not None else None
    try:
        return _run(scenario, system, folder, progress, plot)
    finally:
        if folder is not None:
            folder.release()


def _run(scenario: Scenario, system: SystemDescription, folder: OutputFolder | None,
         progress: bool | None, plot: bool) -> tuple[dict[str, Any], Recorder]:
    out_dir = folder.path if folder is not None else None
    head: dict[str, Any] = {
        "scenario": scenario.name,
        "source": scenario.source,
        "seed": scenario.seed,
        "duration": scenario.duration,
    }
    if out_dir is not None:
        write_json_atomic(out_dir / "summary.json",
                          {**head, "status": "running", "complete": False})
    rec = Recorder(scenario.record, scenario.decimation)
    if out_dir is not None:
        rec.stream_to(out_dir / "results.csv")
    wall0 = time.perf_counter()
    error: str | None = None
    complete = False
    steps = 0
    realtime = 0.0
    loop_s = 0.0
    fmus: dict[str, Any] = {}
    extra: Recorder | None = None
    snap = LockSnapshot()
    with StopOnSignal() as stop:
        observers: list[Any] = [rec]
        if progress is not False:
            observers.append(Progress(scenario.duration, progress))
        observers.append(stop)
        try:
            with Master(system, algorithm=scenario.algorithm, order=scenario.order,
                        step=scenario.step, step_from=scenario.step_from,
                        initial_step=scenario.initial_step, logging_on=True) as master:
                try:  # an FMU refusing its parameters fails here: the summary still says why
                    master.initialize(0.0, scenario.duration,
                                      seeded_parameters(system, master.instances,
                                                        scenario.seed))
                    if plot:  # what the plots need beyond results.csv (memory only)
                        extra = extra_recorder(master, scenario.decimation)
                        observers[1:1] = [extra, snap]
                    complete = master.run(scenario.duration, observers)
                finally:
                    steps = master.steps
                    realtime = round(master.realtime_factor, 3)
                    loop_s = master.run_wall_s
                    fmus = {n: {"file": str(i.path), "guid": i.md.guid,
                                "sha256": file_digest(i.path)[:16]}
                            for n, i in master.instances.items()}
        except AxirError as e:
            error = str(e)
        except KeyboardInterrupt:  # Ctrl-C while loading or initializing: still summarised
            complete = False
        signum = stop.signum
    wall = time.perf_counter() - wall0
    status = "complete" if complete else ("failed" if error else "interrupted")
    summary: dict[str, Any] = {
        **head,
        "status": status,
        "complete": complete,
        "error": error,
        "signal": signal.Signals(signum).name if signum else None,
        "algorithm": scenario.algorithm,
        "steps": steps,
        "wall_time_s": round(wall, 3),
        "us_per_step": round(1e6 * wall / max(steps, 1), 2),
        # the stepping loop alone (master.run: steps, recording, observers), without loading
        # and initializing the FMUs, the check before the run and the summary after it
        "loop_us_per_step": round(1e6 * loop_s / max(steps, 1), 2),
        "startup_s": round(max(wall - loop_s, 0.0), 3),
        "realtime_factor": realtime,
        **summarize(rec),
        "versions": versions(),
        "fmus": fmus,
    }
    if out_dir is not None:
        if not (out_dir / "results.csv").exists() or rec.n == 0:
            write_csv(out_dir / "results.csv", rec)  # the run never started: header only
        if plot and error is None and rec.n > 1:
            from .plots import plot_run

            summary["plots"] = [p.name for p in plot_run(rec, out_dir, extra, snap.snapshot,
                                                         snap.beamwidth)]
        write_json_atomic(out_dir / "summary.json", summary)
    if error is not None:
        raise AxirError(error + (f" (partial results written to {out_dir})" if out_dir else ""))
    return summary, rec
