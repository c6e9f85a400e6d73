"""Benchmark of the FMU runtime slave (fmus/slave.py) in process, Python side only: prints
µs per set-inputs + doStep + get-outputs for the Tracker declaration (192 beam inputs, the 48
SUM outputs), without pythonfmu's C binary or an importer (formerly a loose 1 ms bound in
tests/test_fmu_build.py; the FMU through fmpy, with and without the C shim:
benchmarks/bench_shim.py).

Run: ``python benchmarks/bench_fmu_slave.py [n_steps]``.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from axir.fmus.slave import AxirSlave
from axir.fmus.spec import layout
from axir.fmus.tracker_fmu import SPEC
from axir.models.radar.conventions import BEAMS


class TrackerSlave(AxirSlave):
    """The Tracker's slave, unbundled (no bundle check)."""

    SPEC = SPEC


def bench(n: int) -> float:
    """Mean wall time [µs] of set 192 beam inputs + do_step + get 48 SUM outputs."""
    s = TrackerSlave(instance_name="bench", resources=".")
    vr = {r.name: i for i, r in enumerate(layout(SPEC))}
    beam_vrs = [vr[f"beam.{b}[{r},{f}]"] for b in BEAMS for r in range(1, 17) for f in (1, 2, 3)]
    sum_vrs = [vr[f"sum[{r},{f}]"] for r in range(1, 17) for f in (1, 2, 3)]
    s.exit_initialization_mode()
    beams = np.random.default_rng(0).rayleigh(size=192).tolist()
    dt = 1e-4
    t0 = time.perf_counter()
    for k in range(n):
        s.set_real(beam_vrs, beams)
        s.do_step(k * dt, dt)
        s.get_real(sum_vrs)
    return (time.perf_counter() - t0) / n * 1e6


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 5000
    bench(200)  # warm-up
    print(f"Tracker slave, Python side only: {bench(n):.1f} µs per set 192 + doStep + get 48")


if __name__ == "__main__":
    main()
