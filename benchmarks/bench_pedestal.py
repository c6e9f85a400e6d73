"""Benchmark of Pedestal.step: prints µs/step for several communication steps.

Run: ``python benchmarks/bench_pedestal.py [n_steps]``. The step runs once per radar PRI in the
closed loop, so the small-dt figure is the one that matters (target ≲ 10 µs/step).
"""

from __future__ import annotations

import math
import sys
import time

from axir.models.pedestal import Pedestal


def bench(dt: float, n: int, pot_noise: float) -> float:
    """Mean wall time of one ``step`` [µs] over ``n`` steps with a slowly varying command."""
    p = Pedestal(pot_noise=pot_noise, rate_limit_az=3.0, accel_limit_az=10.0)
    inputs = [{"cmd.az": 40.0 * math.sin(0.001 * i), "cmd.el": 5.0, "bandwidth": 2.0}
              for i in range(1000)]
    step = p.step
    t0 = time.perf_counter()
    for i in range(n):
        step(dt, inputs[i % 1000])
    return (time.perf_counter() - t0) / n * 1e6


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    bench(1e-4, 2000, 0.005)  # warm-up
    for noise in (0.005, 0.0):
        for dt in (5e-5, 1e-4, 1e-3, 1e-2, 0.1):
            us = bench(dt, n, noise)
            print(f"Pedestal.step dt = {dt:8.0e} s  pot_noise = {noise:5.3f} V : {us:6.2f} µs/step")


if __name__ == "__main__":
    main()
