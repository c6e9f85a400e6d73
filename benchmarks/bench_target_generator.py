"""Per-pulse cost of :meth:`axir.models.target_generator.TargetGenerator.step` [µs/pulse].

Run: ``python benchmarks/bench_target_generator.py [n_steps]``. Closed loop: the master steps
once per
PRI, so the one-pulse step (dt = pri, the scalar path) is the figure that matters (target
≲ 30 µs/pulse); longer steps use the vectorised path (N pulses per step). The default scenario
(target in its 3 g turn), thermal noise, clutter and Swerling 1 are on; the antenna moves
a little every step as a pedestal would.
"""

from __future__ import annotations

import sys
import time

from axir.models.radar.conventions import gate_start_for
from axir.models.target_generator import TargetGenerator


def bench(pulses_per_step: int, n_steps: int, **params: object) -> float:
    """Mean wall time per pulse [µs] over ``n_steps`` steps of ``pulses_per_step`` pulses."""
    pri = 100e-6
    gen = TargetGenerator(swerling=1, **params)
    gen.t = 18.0  # inside the default trajectory's turn
    inputs = [
        {"antenna.az": 5.95 + 1e-5 * i, "antenna.el": 0.12, "gate.start": gate_start_for(13_000.0),
         "doppler.centre": 1000.0, "pri": pri}
        for i in range(256)
    ]
    step, dt = gen.step, pulses_per_step * pri
    t0 = time.perf_counter()
    for i in range(n_steps):
        step(dt, inputs[i & 255])
    return (time.perf_counter() - t0) / (n_steps * pulses_per_step) * 1e6


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20_000
    bench(1, 500)  # warm-up (imports, caches)
    for pps in (1, 10, 100, 1000):
        steps = max(20, n // pps)
        for label, params in (("noise+clutter", {}), ("noise only   ", {"clutter": False})):
            us = bench(pps, steps, **params)
            print(f"TargetGenerator.step {pps:5d} pulse(s)/step  {label}: {us:7.2f} µs/pulse")
    us = bench(1, n, fidelity="measurement", meas_interval=1e-3)
    print(f"TargetGenerator.step measurement fidelity (1 step = 100 µs): {us:7.2f} µs/step")


if __name__ == "__main__":
    main()
