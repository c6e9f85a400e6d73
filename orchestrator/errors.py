"""Errors the user can act on. The CLI prints them without a traceback and exits with code 2."""

from __future__ import annotations


class AxirError(Exception):
    """Base class of errors with a clear message for the user (exit code 2)."""

    exit_code = 2


class ScenarioError(AxirError):
    """A scenario file is missing, malformed or inconsistent (message names file and key)."""


class SystemDescriptionError(AxirError):
    """The system description does not match the FMUs (unknown variable, type mismatch…)."""


class FmiError(AxirError):
    """An FMI call failed; names the instance, the function, the status and the FMU's log."""

    def __init__(self, instance: str, function: str, status: int, log: list[str]) -> None:
        labels = ["ok", "warning", "discard", "error", "fatal", "pending"]
        label = labels[status] if 0 <= status < len(labels) else "illegal status"
        msg = f"{instance}: {function} returned {label}"
        if log:
            msg += ": " + " | ".join(log[-5:])
        super().__init__(msg)
        self.instance, self.function, self.status, self.log = instance, function, status, log
