"""Progress-bar observer of the master (tqdm over simulated time)."""

from __future__ import annotations

from .master import NS, Master


class Progress:
    """tqdm progress bar over simulated time (updated every ~0.5 % of the run)."""

    def __init__(self, duration: float, enabled: bool | None = None) -> None:
        self.duration = duration
        self.enabled = enabled
        self._bar = None
        self._last = 0.0

    def start(self, master: Master) -> None:
        from tqdm import tqdm

        # enabled None: show only on a terminal (tqdm's disable=None)
        disable = None if self.enabled is None else not self.enabled
        self._bar = tqdm(total=round(self.duration, 6), unit="s", disable=disable,
                         bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s sim "
                                    "[{elapsed}<{remaining}]")
        self._every = max(self.duration / 200.0, 1e-9)

    def step(self, master: Master, t_ns: int) -> None:
        t = t_ns / NS
        if t - self._last >= self._every:
            self._bar.update(t - self._last)
            self._last = t

    def finish(self, master: Master, complete: bool) -> None:
        if self._bar is not None:
            self._bar.update(master.t_ns / NS - self._last)
            self._bar.close()
