"""``axir requirements``: what a host Python needs to run the FMUs of a configuration.

Each axir FMU records, at build time, the Python it was built with and the third-party
packages its code imports (``resources/axir_python.txt``, :mod:`axir.fmus.python_env`):
``require=`` lines for every configuration, ``require_if=`` lines for packages only some
parameter values need (the Tracker's IMM filter: filterpy). This command reads those records
(data only) and the scenario's parameters (plus ``--set``) and prints, per FMU and in total,
the packages a host Python must have. A host without them fails at ``fmi2Instantiate`` (a
``require=`` package) or at ``fmi2ExitInitializationMode`` (a ``require_if=`` package), with a
message naming the package.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import click

from axir.fmus.python_env import CONFIG_NAME, ENV_VAR, packages_needed

from .campaign.spec import parse_assignment
from .config import DEFAULT_FMU_DIR
from .errors import AxirError
from .scenario import load_scenario


def fmu_requirements(fmu: Path, parameters: dict[str, object]) -> tuple[list[str], dict]:
    """(packages, recorded interpreter) of one FMU file for ``parameters`` (FMI name ->
    value); :class:`AxirError` naming the file when it is not a readable axir FMU."""
    try:
        with zipfile.ZipFile(fmu) as z:
            settings = z.read(f"resources/{CONFIG_NAME}")
    except FileNotFoundError:
        raise AxirError(f"FMU file not found: {fmu}") from None
    except KeyError:
        raise AxirError(f"{fmu}: no resources/{CONFIG_NAME} (not an axir FMU built with the "
                        f"shim; run `axir build`)") from None
    except (OSError, zipfile.BadZipFile) as e:
        raise AxirError(f"{fmu}: cannot read the FMU ({e})") from None
    text = {k: str(v).lower() if isinstance(v, bool) else str(v) for k, v in parameters.items()}
    try:
        return packages_needed(settings, text)
    except ValueError as e:
        raise AxirError(f"{fmu}: resources/{CONFIG_NAME}: {e}") from None


@click.command()
@click.argument("scenario", required=False)
@click.option("--set", "assignments", multiple=True, metavar="UNIT.PARAM=VALUE",
              help="Override a unit parameter (repeatable), e.g. Tracker.filter_x=imm.")
@click.option("--fmu-dir", default=DEFAULT_FMU_DIR, show_default=True,
              type=click.Path(file_okay=False, path_type=Path), help="Where the FMUs are.")
def requirements(scenario: str | None, assignments: tuple[str, ...], fmu_dir: Path) -> None:
    """Print what a host Python needs to run SCENARIO's FMUs (default: the closed loop).

    Only needed when the host is itself a Python program (fmpy, libcosimpy) or when an FMU
    runs on another Python than the one it was built with (AXIR_FMU_PYTHON): non-Python hosts
    on the build machine need nothing."""
    sc = load_scenario(scenario)
    params = {name: dict(spec.get("parameters", {})) for name, spec in sc.units.items()}
    for text in assignments:
        unit, name, value = parse_assignment(text)
        if unit not in params:
            raise AxirError(f"--set {text!r}: unknown unit {unit!r} (scenario units: "
                            f"{', '.join(params)})")
        params[unit][name] = value
    total: list[str] = []
    versions: set[str] = set()
    for name, spec in sc.units.items():
        fmu = Path(fmu_dir) / spec.get("fmu", f"{name}.fmu")
        packages, recorded = fmu_requirements(fmu, params[name])
        versions.add(f"{recorded.get('implementation', 'cpython')} "
                     f"{recorded.get('version', '?')}")
        click.echo(f"{name}: {' '.join(packages) or '(standard library only)'}"
                   f"   [{fmu}, built on {recorded.get('executable', '?')}]")
        total += [p for p in packages if p not in total]
    click.echo(f"host Python: {' or '.join(sorted(versions))} with a shared libpython, plus: "
               f"pip install {' '.join(total)}")
    click.echo(f"(non-Python hosts on this machine need nothing; elsewhere set {ENV_VAR}="
               f"/path/to/python3 of such a Python: docs/other_tools.md)")
