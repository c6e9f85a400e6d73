"""Monte Carlo campaigns on Dask (issue 4). Placeholder: implemented in the campaign work."""

from __future__ import annotations

import click

from .errors import AxirError


@click.command()
@click.argument("scenario", required=False)
def montecarlo(scenario: str | None) -> None:
    """Run SCENARIO N times on Dask (not implemented yet)."""
    raise AxirError("axir montecarlo is not implemented yet")
