"""Our master vs libcosim on the same system: µs per step of the closed loop from one SSP file.

Run: ``python benchmarks/bench_libcosim.py [--duration 1] [--step 1e-4] [--repeat 3]
[--fmu-dir DIR]``.

The built-in ``closed-loop`` scenario is exported with ``axir export-ssp`` (fixed step,
Jacobi, the four FMUs built into a temporary directory unless ``--fmu-dir`` is given) and the
archive is run by

(a) our master (:class:`axir.orchestrator.master.Master`, the scenario read back by
    :func:`axir.orchestrator.ssp.importer.load_ssp`, Jacobi, no observers), and
(b) libcosim (PyPI ``libcosimpy``: ``CosimExecution.from_ssp_file``, its fixed-step
    algorithm, no observers, ``simulate_until``).

Both run in this process (pythonfmu slaves need a Python interpreter; libcosim calls them
from its worker thread, taking the GIL). Only the stepping is timed: instantiation,
initialization and the first step are done before the clock starts. Timed passes alternate
(a) and (b) ``--repeat`` times and the best of each is printed with the ratio (the machine
may be shared). Nothing is asserted; tests/test_libcosim.py checks that both give identical
results.
"""

from __future__ import annotations

import argparse
import gc
import tempfile
import time
from pathlib import Path

from axir.models.system import unit_seed
from axir.orchestrator.master import Master
from axir.orchestrator.scenario import load_scenario
from axir.orchestrator.ssp.export import export_ssp_archive
from axir.orchestrator.ssp.importer import load_ssp


def run_ours(path: Path) -> tuple[int, float]:
    """(timed steps, wall seconds) of our master on the archive."""
    sc = load_ssp(path)
    system = sc.system(Path("."))  # FMU paths in the scenario are absolute
    with Master(system, algorithm=sc.algorithm, order=sc.order, step=sc.step) as master:
        for name, inst in master.instances.items():  # the seeds load_ssp re-derives
            v = inst.variables.get("seed")
            params = system.units[name].parameters
            if v is not None and v.causality == "parameter" and "seed" not in params:
                params["seed"] = unit_seed(sc.seed, name)
        master.initialize(0.0, sc.duration)
        master.step(master.next_step_ns())
        steps0 = master.steps
        t0 = time.perf_counter()
        master.run(sc.duration)
        wall = time.perf_counter() - t0
        return master.steps - steps0, wall


def run_libcosim(path: Path) -> tuple[int, float]:
    """(timed steps, wall seconds) of libcosim on the archive."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.WARNING)
    sc = load_ssp(path)
    step_ns = round(sc.step * 1e9)
    stop_ns = round(sc.duration * 1e9)
    ex = CosimExecution.from_ssp_file(str(path))
    try:
        if not ex.step(1):  # initialization + first step, untimed
            raise RuntimeError(f"libcosim: first step failed: {ex.status()}")
        t0 = time.perf_counter()
        if not ex.simulate_until(stop_ns):
            raise RuntimeError(f"libcosim: simulate_until failed: {ex.status()}")
        wall = time.perf_counter() - t0
        steps = (ex.status().current_time - step_ns) // step_ns
    finally:
        del ex
    return steps, wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=1.0, help="simulated time [s]")
    ap.add_argument("--step", type=float, default=1e-4, help="fixed step [s]")
    ap.add_argument("--repeat", type=int, default=3, help="timed passes of each")
    ap.add_argument("--fmu-dir", type=Path, help="use these FMUs instead of building them")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        fmu_dir = args.fmu_dir
        if fmu_dir is None:
            from axir.fmus.build import build_all

            fmu_dir = Path(tmp) / "fmus"
            build_all(fmu_dir)
        path = export_ssp_archive(load_scenario("closed-loop"), fmu_dir,
                                  Path(tmp) / "radar.ssp", step=args.step,
                                  duration=args.duration)
        best: dict[str, float] = {}
        for _ in range(args.repeat):
            for name, fn in (("our master", run_ours), ("libcosim", run_libcosim)):
                gc.collect()
                steps, wall = fn(path)
                us = 1e6 * wall / steps
                best[name] = min(best.get(name, us), us)
                print(f"  {name:<11} {steps} steps {wall:7.3f} s  {us:7.1f} µs/step")
    print(f"closed loop, {args.duration} s at a fixed {args.step} s step (Jacobi), best of "
          f"{args.repeat}:")
    for name, us in best.items():
        print(f"  {name:<11} {us:7.1f} µs/step")
    print(f"  ratio libcosim / our master = {best['libcosim'] / best['our master']:.2f}")


if __name__ == "__main__":
    main()
    import os
    import sys

    sys.stdout.flush()
    os._exit(0)  # pythonfmu exit trap (see orchestrator/cli.py:main)
