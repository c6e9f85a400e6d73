"""SSP 1.0 export and import (issue 5). Placeholder: implemented in the interoperability work."""

from __future__ import annotations

import click

from .errors import AxirError


@click.command("export-ssp")
@click.argument("scenario", required=False)
def export_ssp(scenario: str | None) -> None:
    """Write SCENARIO as an SSP 1.0 archive (not implemented yet)."""
    raise AxirError("axir export-ssp is not implemented yet")
