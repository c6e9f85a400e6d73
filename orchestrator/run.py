"""Run one scenario through the master and write ``results.csv`` and ``summary.json``: the
master steps, observers record (:mod:`.record`) and show progress (:mod:`.progress`),
:mod:`.metrics` turns the record into the summary figures."""

from __future__ import annotations

import json
import platform
import time
from collections.abc import Mapping
from importlib import metadata
from pathlib import Path
from typing import Any

from axir.models.system import unit_seed

from .archive import file_digest
from .errors import AxirError
from .fmi import FmuInstance
from .master import Master
from .metrics import summarize
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


def run_scenario(
    scenario: Scenario,
    fmu_dir: Path,
    out_dir: Path | None,
    *,
    seed: int | None = None,
    duration: float | None = None,
    progress: bool | None = None,
) -> tuple[dict[str, Any], Recorder]:
    """Run ``scenario``; write results.csv + summary.json into ``out_dir`` (if given).

    Returns the summary and the recorder. Results are written even when the run is
    interrupted (Ctrl-C) or an FMU fails at initialization or mid-run; the summary then says
    ``complete: false`` and gives the ``error``.
    """
    scenario = scenario.with_overrides(seed, duration)
    system = scenario.system(Path(fmu_dir))
    for spec in system.units.values():
        if not spec.fmu.is_file():
            raise AxirError(f"FMU file not found: {spec.fmu} (unit {spec.name}); "
                            "run `axir build` first or pass --fmu-dir")
    rec = Recorder(scenario.record, scenario.decimation)
    observers: list[Any] = [rec]
    if progress is not False:
        observers.append(Progress(scenario.duration, progress))
    wall0 = time.perf_counter()
    error: str | None = None
    complete = False
    with Master(system, algorithm=scenario.algorithm, order=scenario.order,
                step=scenario.step, step_from=scenario.step_from,
                initial_step=scenario.initial_step, logging_on=True) as master:
        try:  # an FMU refusing its parameters fails here: the summary still says why
            master.initialize(0.0, scenario.duration,
                              seeded_parameters(system, master.instances, scenario.seed))
            complete = master.run(scenario.duration, observers)
        except AxirError as e:
            error = str(e)
        steps = master.steps
        fmus = {n: {"file": str(i.path), "guid": i.md.guid, "sha256": file_digest(i.path)[:16]}
                for n, i in master.instances.items()}
    wall = time.perf_counter() - wall0
    summary: dict[str, Any] = {
        "scenario": scenario.name,
        "source": scenario.source,
        "seed": scenario.seed,
        "duration": scenario.duration,
        "complete": complete,
        "error": error,
        "algorithm": scenario.algorithm,
        "steps": steps,
        "wall_time_s": round(wall, 3),
        "us_per_step": round(1e6 * wall / max(steps, 1), 2),
        **summarize(rec),
        "versions": versions(),
        "fmus": fmus,
    }
    if out_dir is not None:
        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        write_csv(out_dir / "results.csv", rec)
        (out_dir / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    if error is not None:
        raise AxirError(error + (f" (partial results written to {out_dir})" if out_dir else ""))
    return summary, rec
