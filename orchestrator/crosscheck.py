"""FMI cross-check artifacts (issue 5). Placeholder: implemented in the interoperability work."""

from __future__ import annotations

import click

from .errors import AxirError


@click.command()
def crosscheck() -> None:
    """Write the FMI cross-check layout for the four FMUs (not implemented yet)."""
    raise AxirError("axir crosscheck is not implemented yet")
