"""Benchmark of RadarManager.step: prints µs/step on noise-only SUM arrays.

Run: ``python benchmarks/bench_manager.py [n_steps]``. The step runs once per radar PRI in the
closed loop (design goal ≲ 20 µs/step; formerly a loose 100 µs bound in a test).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from axir.models.manager import RadarManager


def bench(n: int) -> float:
    """Mean wall time of one ``step`` [µs] over ``n`` steps of random Rayleigh SUM arrays."""
    mgr = RadarManager(designation_range=37_000.0, search_extent=3_000.0, doppler_pole=0.0,
                       latency_pris=2)  # the configuration of tests/manager_scene.py
    rng = np.random.default_rng(0)
    sums = rng.rayleigh(size=(min(n, 2000), 16, 3)) * 4
    inp = {"sum": sums[0], "gate.start": 0.0, "track.range": 1e4, "track.range_rate": -100.0,
           "maneuver": False}
    t0 = time.perf_counter()
    for i in range(n):
        inp["sum"] = sums[i % len(sums)]
        mgr.step(1e-4, inp)
    return (time.perf_counter() - t0) / n * 1e6


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20_000
    bench(2000)  # warm-up (threshold-factor caches)
    print(f"RadarManager.step: {bench(n):.1f} µs/step ({n} steps)")


if __name__ == "__main__":
    main()
