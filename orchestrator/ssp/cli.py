"""``axir export-ssp``: argument parsing only (the work is in :mod:`.export`)."""

from __future__ import annotations

from pathlib import Path

import click

from ..config import DEFAULT_FMU_DIR
from ..errors import AxirError
from ..scenario import load_scenario
from .export import DEFAULT_STEP, export_ssp_archive
from .validate import validate_ssp


@click.command("export-ssp")
@click.argument("scenario", required=False)
@click.option("-o", "--out", "out", type=click.Path(dir_okay=False, path_type=Path),
              help="The .ssp file to write (default: <scenario name>.ssp).")
@click.option("--fmu-dir", default=None, type=click.Path(file_okay=False, path_type=Path),
              help="Where the FMUs are (default: dist, or $AXIR_FMU_DIR).")
@click.option("--step", type=click.FloatRange(min=0, min_open=True),
              help=f"Fixed communication step [s] (default: the scenario's fixed step, else "
                   f"{DEFAULT_STEP}).")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True),
              help="Stop time [s] (default: the scenario's duration).")
@click.option("--seed", type=click.IntRange(min=0), help="Base seed (overrides the scenario).")
def export_ssp(scenario: str | None, out: Path | None, fmu_dir: Path | None,
               step: float | None, duration: float | None, seed: int | None) -> None:
    """Write SCENARIO (default: the closed loop) as an SSP 1.0 archive: SystemStructure.ssd,
    the FMUs and one .ssv parameter set per unit under resources/, a fixed-step Jacobi
    DefaultExperiment. Runs in libcosim and with `axir run OUT.ssp`."""
    sc = load_scenario(scenario)
    out = out or Path(f"{sc.name}.ssp")
    try:  # an unusable -o path: one line before any work
        out.parent.mkdir(parents=True, exist_ok=True)
        if out.is_dir():
            raise AxirError(f"-o {out}: is a folder, give the .ssp file to write")
        with open(out, "ab"):
            pass
    except OSError as e:
        raise AxirError(f"-o {out}: cannot write there ({e.strerror}: {e.filename})") from None
    path = export_ssp_archive(sc, fmu_dir or Path(DEFAULT_FMU_DIR), out, step=step,
                              duration=duration, seed=seed)
    problems = validate_ssp(path)
    if problems:
        raise AxirError(f"{path}: written archive fails the SSP 1.0 schemas: "
                        + "; ".join(problems[:5]))
    click.echo(f"wrote {path} (SSP 1.0, validated against the SSP 1.0 schemas)")


__all__ = ["export_ssp"]
