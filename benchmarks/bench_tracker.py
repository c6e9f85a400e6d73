"""Per-PRI cost of :meth:`axir.models.tracker.Tracker.step` [µs/step].

Run: ``python benchmarks/bench_tracker.py``. Builds noise-free beams of a target near boresight
(Gaussian monopulse pattern, triangular range response) and times steps in confirmed mode
(mode 2, the per-PRI steady state), tentative mode (mode 1) and acquisition (mode 0).
"""

from __future__ import annotations

import time

import numpy as np

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.radar.conventions import BIN_M
from axir.models.tracker import Tracker


def make_beams(lat: float, el: float, offset_m: float) -> np.ndarray:
    """Beams (4, 16, 3) of a point target ``offset_m`` beyond the bin-7 sample."""
    g = MonopulseAntenna().gains(lat, el)
    r = (np.arange(16) - 6) * BIN_M
    tri = np.clip(1.0 - np.abs(offset_m - r) / BIN_M, 0.0, None)
    dop = np.array([0.3, 1.0, 0.3])
    return 100.0 * g[:, None, None] * tri[None, :, None] * dop[None, None, :] + 0.1


def bench(mode: int, n: int = 20_000, **params: object) -> float:
    trk = Tracker(**params)
    beams = make_beams(1e-3, -5e-4, 10.0)
    inp = {"beam": beams, "ped.az": 0.3, "ped.el": 0.1, "mode": mode, "alpha": 0.5,
           "beta": 0.15, "range.offset": 0.0, "gate.command": 5000.0}
    for _ in range(100):
        trk.step(1e-3, inp)
    t0 = time.perf_counter()
    for _ in range(n):
        trk.step(1e-3, inp)
    return (time.perf_counter() - t0) / n * 1e6


if __name__ == "__main__":
    for mode, name in ((2, "confirmed"), (1, "tentative"), (0, "acquisition")):
        best = min(bench(mode) for _ in range(3))
        print(f"Tracker.step mode {mode} ({name}): {best:.1f} µs/step")
    best = min(bench(2, ddre_window=3) for _ in range(3))
    print(f"Tracker.step mode 2 with DDRE (ddre_window=3): {best:.1f} µs/step")
