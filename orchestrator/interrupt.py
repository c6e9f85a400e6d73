"""SIGTERM and SIGHUP handled like Ctrl-C (a ``timeout``, ``docker stop``, a batch scheduler,
a closed terminal): the signal is recorded, the run stops at the next macro step with its
partial results flushed and ``"complete": false``, and the CLI exits with 128 + the signal.

While a run is stepping, the master itself turns SIGINT into a flag (an exception raised inside
an FMU's Python code would kill the instance); :class:`StopOnSignal` does the same for SIGTERM
and SIGHUP, from the moment the run starts loading its FMUs, and stops the master between two
macro steps (as an observer raising ``KeyboardInterrupt``, which the master treats as Ctrl-C).
"""

from __future__ import annotations

import signal
import threading
from typing import Any

#: handled like Ctrl-C (SIGINT is the master's own)
STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP)

#: the signal that stopped the last run of this process (None: none)
_RECEIVED: list[int] = []


def received() -> int | None:
    """The stop signal received by this process, if any."""
    return _RECEIVED[-1] if _RECEIVED else None


class StopSignal(KeyboardInterrupt):
    """SIGTERM/SIGHUP outside a run's stepping: unwinds like Ctrl-C (every ``finally`` runs:
    FMUs freed, temp files removed); the CLI exits with 128 + ``signum``."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)


def _raise(signum: int, frame: Any) -> None:
    _RECEIVED.append(signum)
    raise StopSignal(signum)


def raise_on_stop_signals() -> None:
    """Process-wide (the CLI's entry point): SIGTERM and SIGHUP raise :class:`StopSignal`
    (a run's stepping defers them with :class:`StopOnSignal`)."""
    for s in STOP_SIGNALS:
        signal.signal(s, _raise)


def exit_code(signum: int) -> int:
    """The shell's convention: 128 + signal number (SIGTERM 143, SIGHUP 129, SIGINT 130)."""
    return 128 + int(signum)


class StopOnSignal:
    """Context manager recording SIGTERM/SIGHUP into a flag, and an observer of the master
    that stops the run at the next step once the flag is set. Outside the main thread (a
    Dask worker) it does nothing."""

    def __init__(self) -> None:
        self.signum: int | None = None
        self._previous: dict[int, Any] = {}

    def _handler(self, signum: int, frame: Any) -> None:
        self.signum = signum
        _RECEIVED.append(signum)

    def __enter__(self) -> StopOnSignal:
        if threading.current_thread() is threading.main_thread():
            for s in STOP_SIGNALS:
                self._previous[s] = signal.signal(s, self._handler)
        return self

    def __exit__(self, *exc: object) -> None:
        for s, h in self._previous.items():
            signal.signal(s, h)
        self._previous.clear()

    # -- observer protocol of orchestrator/master.py --------------------------------------
    def start(self, master: Any) -> None:
        """Nothing to prepare."""

    def step(self, master: Any, t_ns: int) -> None:
        """Stop the master (as Ctrl-C does) once a stop signal arrived."""
        if self.signum is not None:
            raise KeyboardInterrupt

    def finish(self, master: Any, complete: bool) -> None:
        """Nothing to finish."""
