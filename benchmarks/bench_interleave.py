"""What interleaving the four units costs: each unit's CPU per step replayed alone, beside other
units (one step of each in turn, as the direct loop does), and beside a twin of itself.

Run::

    python benchmarks/bench_interleave.py [--duration 0.5] [--repeat 5]

The closed-loop scenario's per-unit inputs are recorded as ``bench_units.py`` does; each
combination below replays them into fresh units, stepping the units of the combination in turn
PRI after PRI, and times each ``step`` (``time.perf_counter`` around it, best of ``--repeat``;
the machine may be shared, see the load average). Issue 14, session 9 (branch spd13): the direct
loop costs ≈ 1.5 × the sum of the units replayed alone, and the excess appears when *different*
code is interleaved — a twin (a second instance of the same unit: twice the data, the same code)
adds nothing — so it is instruction-side (branch prediction, instruction caches), not data:
executing fewer bytecodes and fewer numpy calls per PRI is what reduces it. Numbers only.
"""

from __future__ import annotations

import argparse
import gc
import time

from bench_loop import _scenario, direct_params
from bench_units import UNITS, record, units_of

from axir.models.loop import DirectLoop

COMBOS = ("Pedestal", "TargetGenerator", "Tracker", "RadarManager", "Pedestal,Tracker",
          "TargetGenerator,Tracker", "Tracker,RadarManager", "Tracker,Tracker",
          "TargetGenerator,TargetGenerator", "Pedestal,TargetGenerator,Tracker,RadarManager")


def run(names: list[str], params: dict, rec: dict) -> list[float]:
    """µs per step of each entry of ``names`` (each a fresh instance), stepped in turn."""
    steps = []
    for name in names:
        steps.append((units_of(DirectLoop, params)[name].step, rec[name]))
    acc = [0.0] * len(names)
    pc = time.perf_counter
    n = len(rec[UNITS[0]])
    gc.disable()
    try:
        for k in range(n):
            for j, (step, seq) in enumerate(steps):
                h, inputs = seq[k]
                t0 = pc()
                step(h, inputs)
                acc[j] += pc() - t0
    finally:
        gc.enable()
    return [a / n * 1e6 for a in acc]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.5, help="simulated seconds [s]")
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    params = direct_params(_scenario(a.duration))
    rec = record(params, a.duration)
    best: dict[tuple[str, int], float] = {}
    for _ in range(a.repeat):
        for combo in COMBOS:
            for j, v in enumerate(run(combo.split(","), params, rec)):
                best[(combo, j)] = min(best.get((combo, j), float("inf")), v)
    alone = {c: best[(c, 0)] for c in COMBOS if "," not in c}
    print(f"µs per step, best of {a.repeat} ({len(rec[UNITS[0]])} steps); excess = the "
          "combination minus its units alone")
    for combo in COMBOS:
        names = combo.split(",")
        vals = [best[(combo, j)] for j in range(len(names))]
        excess = sum(vals) - sum(alone[n] for n in names)
        cells = "  ".join(f"{n[:3]} {v:6.2f}" for n, v in zip(names, vals, strict=True))
        print(f"  {combo:48s} {cells}   excess {excess:+6.2f}")


if __name__ == "__main__":
    main()
