"""``axir montecarlo``: argument parsing only (the work is in :mod:`.runner`)."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import click

from ..config import DEFAULT_FMU_DIR
from ..errors import AxirError
from .runner import run_campaign
from .spec import parse_assignment


@click.command()
@click.argument("scenario", required=False)
@click.option("--runs", "-n", type=click.IntRange(min=1), required=True,
              help="Number of Monte Carlo runs (run i uses seed BASE + i).")
@click.option("--workers", "-w", type=click.IntRange(min=1), default=None,
              help="Worker processes of a local Dask cluster (default: CPU count).")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Use an existing Dask cluster (e.g. tcp://host:8786) instead.")
@click.option("--out", "out_dir", default="out/montecarlo", show_default=True,
              type=click.Path(file_okay=False, path_type=Path), help="Results directory.")
@click.option("--seed", type=click.IntRange(min=0), default=None,
              help="Base seed BASE (default: the scenario's seed).")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True),
              help="Simulated duration of each run [s] (overrides the scenario).")
@click.option("--set", "assignments", multiple=True, metavar="UNIT.PARAM=VALUE",
              help="Override a unit parameter for every run (repeatable).")
@click.option("--fmu-dir", default=None, type=click.Path(file_okay=False, path_type=Path),
              help="Where the FMUs are (default: $AXIR_FMU_DIR or dist).")
@click.option("--plot/--no-plot", default=True, show_default=True,
              help="Write campaign.png.")
@click.option("--progress/--no-progress", default=None, help="Progress bar (default: on a tty).")
@click.option("--long", "long_ok", is_flag=True,
              help="Allow a campaign estimated to take more than a day of wall time.")
def montecarlo(scenario: str | None, runs: int, workers: int | None, scheduler: str | None,
               out_dir: Path, seed: int | None, duration: float | None,
               assignments: tuple[str, ...], fmu_dir: Path | None, plot: bool,
               progress: bool | None, long_ok: bool) -> None:
    """Run SCENARIO (a .toml file or a built-in name; default: the closed loop) --runs times
    on Dask and write aggregates.csv, runs.csv, campaign.json and campaign.png.

    Exit status: 0 when every run succeeded, 1 when some failed (reported on stderr and in
    runs.csv; the others are aggregated), 2 on a usage or scenario error or when every run
    failed.
    """
    if workers is not None and scheduler is not None:
        raise click.UsageError("--workers and --scheduler are mutually exclusive")
    params: dict[str, dict[str, Any]] = {}
    for a in assignments:
        unit, name, value = parse_assignment(a)
        params.setdefault(unit, {})[name] = value
    res = run_campaign(scenario, fmu_dir or Path(DEFAULT_FMU_DIR), runs, workers=workers,
                       scheduler=scheduler, seed=seed, duration=duration, parameters=params,
                       progress=progress, out_dir=out_dir, plot=plot, long_ok=long_ok)
    files = res.files
    s = res.summary
    click.echo("wrote " + ", ".join(str(f) for f in files))
    keys = ("scenario", "runs", "succeeded", "failed", "seeds", "executed_on", "wall_time_s",
            "runs_per_s", *(k for k in s if k.startswith(("rms_", "nees_"))))
    click.echo(json.dumps({k: s.get(k) for k in keys}, indent=1))
    if s["succeeded"] == 0:
        raise AxirError(f"every run failed; first error: {s['failures'][0]['error']}")
    if s["failed"]:
        click.echo(f"{s['failed']} of {s['runs']} runs failed (see runs.csv)", err=True)
        sys.exit(1)
