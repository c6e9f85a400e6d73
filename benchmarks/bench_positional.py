"""What the positional step calls save in the direct loop (issue 14, session 28).

Run: ``python benchmarks/bench_positional.py [--duration 1] [--repeat 4]``.

The direct loop (:class:`axir.models.loop.DirectLoop`, the built-in ``closed-loop`` scenario
as ``bench_loop.py`` runs it) calls the Pedestal, the TargetGenerator and the Tracker's beams
mode as ``step(h, None, *values)`` (round 11). This times ``DirectLoop.run`` with those calls
against the same run with every unit taking its input mapping (``models.loop._step_args``
answering None, as it does for a unit without ``STEP_ARGS``), after one uncounted warm-up
pass, in ``--repeat`` pairs whose order alternates, CPU time of this process; it prints the
best and every pass of each and the difference. The difference bounds what a positional call
from the FMUs' C shim could save (the shim builds its input dicts in C, cheaper than the
loop's Python dict displays). Nothing is asserted.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import axir.models.loop as loop_mod

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_loop import _scenario, direct_params, run_direct  # benchmarks/ (sys.path)


def one_pass(positional: bool, duration: float) -> float:
    """CPU µs per PRI of one direct-loop run of ``duration`` [s] (``bench_loop.run_direct``)."""
    orig = loop_mod._step_args
    if not positional:
        loop_mod._step_args = lambda unit, keys: None
    try:
        steps, _, cpu = run_direct(direct_params(_scenario(duration)), duration)
        return cpu / steps * 1e6
    finally:
        loop_mod._step_args = orig


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=1.0, help="simulated seconds per pass")
    ap.add_argument("--repeat", type=int, default=4, help="alternated pass pairs")
    a = ap.parse_args(argv)
    one_pass(True, min(a.duration, 0.1))  # warm-up (imports, caches): not counted
    got: dict[bool, list[float]] = {True: [], False: []}
    for k in range(a.repeat):  # the order alternates within the pairs too
        for positional in ((True, False) if k % 2 == 0 else (False, True)):
            got[positional].append(one_pass(positional, a.duration))
    for positional, name in ((True, "positional"), (False, "mapping   ")):
        print(f"{name}: best {min(got[positional]):6.1f} CPU µs/PRI  "
              f"(all: {', '.join(f'{x:.1f}' for x in got[positional])})")
    print(f"mapping − positional (best): {min(got[False]) - min(got[True]):.1f} µs/PRI")


if __name__ == "__main__":
    main()
