"""Per-unit cost of the direct loop's models [µs per PRI step], before/after in one run.

Run::

    python benchmarks/bench_units.py [--duration 1.5] [--repeat 3] [--before DIR]

The built-in ``closed-loop`` scenario (parameters and seeds as ``bench_loop.py``) runs once
through :class:`axir.models.loop.DirectLoop` to record every unit's ``(dt, inputs)`` per
step; each unit's recorded sequence is then replayed into a fresh instance and timed. With
``--before DIR`` (a directory holding an older ``models`` package, e.g. made with
``git archive <rev> models | tar -x -C DIR``) the same sequences are replayed into that
version's units too, alternating chunks of ``--chunk`` steps between the two versions so that
both see the same machine load; the whole direct loop of both versions is also timed,
alternating. Times are CPU time of this process (``time.process_time``: robust to other
processes on a shared machine), best of ``--repeat``. Nothing is asserted: numbers only.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import sys
import time
from typing import Any

from bench_loop import _scenario, direct_params

from axir.models.loop import DirectLoop
from axir.models.system import STEP_SOURCE

UNITS = ("TargetGenerator", "Tracker", "Pedestal", "RadarManager")
Record = dict[str, list[tuple[float, dict[str, Any]]]]


def record(params: dict[str, dict[str, Any]], duration: float) -> Record:
    """Each unit's (dt, inputs) per step of a direct-loop run of ``duration`` [s]."""
    rec: Record = {n: [] for n in UNITS}
    loop = DirectLoop.from_params(params)
    o = loop.out
    while loop.t < duration:
        h = float(o[STEP_SOURCE[0]][STEP_SOURCE[1]])
        for name, unit, wires in loop._plan:
            inputs = {key: o[src][skey] for key, src, skey in wires}
            rec[name].append((h, inputs))
            o[name] = unit.step(h, inputs)
        loop.t += h
    return rec


def units_of(loop_cls: type, params: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Fresh units of a DirectLoop class (any version), by name."""
    loop = loop_cls.from_params(params)
    return dict(zip(UNITS, (loop.gen, loop.trk, loop.ped, loop.mgr), strict=True))


def replay(versions: dict[str, type], params: dict[str, dict[str, Any]], rec: Record,
           repeat: int, chunk: int, names: tuple[str, ...] = UNITS
           ) -> dict[tuple[str, str], float]:
    """Best-of-``repeat`` CPU µs per step of each unit of each version (chunks alternate)."""
    pc = time.process_time
    best: dict[tuple[str, str], float] = {}
    for _ in range(repeat):
        units = {label: units_of(cls, params) for label, cls in versions.items()}
        for name in names:
            seq = rec[name]
            acc = dict.fromkeys(versions, 0.0)
            gc.disable()
            try:
                for c0 in range(0, len(seq), chunk):
                    part = seq[c0:c0 + chunk]
                    for label in versions:
                        step = units[label][name].step
                        t0 = pc()
                        for h, inputs in part:
                            step(h, inputs)
                        acc[label] += pc() - t0
            finally:
                gc.enable()
            for label, s in acc.items():
                key = (name, label)
                best[key] = min(best.get(key, float("inf")), s / len(seq) * 1e6)
    return best


def whole_loop(versions: dict[str, type], params: dict[str, dict[str, Any]], duration: float,
               repeat: int) -> dict[str, tuple[float, float]]:
    """Best-of-``repeat`` (wall, CPU) µs per PRI of each version's DirectLoop, alternating."""
    best: dict[str, tuple[float, float]] = {}
    for _ in range(repeat):
        for label, cls in versions.items():
            loop = cls.from_params(params)
            gc.collect()
            w0, c0 = time.perf_counter(), time.process_time()
            loop.run(duration)
            w = (time.perf_counter() - w0) / loop.steps * 1e6
            c = (time.process_time() - c0) / loop.steps * 1e6
            b = best.get(label, (float("inf"), float("inf")))
            best[label] = (min(b[0], w), min(b[1], c))
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=1.5, help="simulated seconds [s]")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--chunk", type=int, default=500, help="steps per alternating chunk")
    ap.add_argument("--before", default=None,
                    help="directory holding an older 'models' package to compare with")
    ap.add_argument("--units", default=",".join(UNITS),
                    help="comma-separated units to replay (default: all four)")
    ap.add_argument("--no-loop", action="store_true", help="skip the whole-loop timing")
    a = ap.parse_args()
    names = tuple(a.units.split(","))
    if not names or any(n not in UNITS for n in names):
        print(f"bench_units: --units {a.units!r}: choose among {', '.join(UNITS)}",
              file=sys.stderr)
        raise SystemExit(2)
    params = direct_params(_scenario(a.duration))
    versions: dict[str, type] = {}
    if a.before:
        sys.path.insert(0, a.before)
        versions["before"] = importlib.import_module("models.loop").DirectLoop
    versions["after" if a.before else "now"] = DirectLoop
    rec = record(params, a.duration)
    best = replay(versions, params, rec, a.repeat, a.chunk, names)
    n = len(rec[UNITS[0]])
    print(f"per unit, CPU µs per step ({n} steps of the closed-loop scenario, "
          f"{a.duration} s, best of {a.repeat}, alternating chunks of {a.chunk})")
    for name in (*names, "sum"):
        cells = []
        for label in versions:
            v = (sum(best[(u, label)] for u in names) if name == "sum"
                 else best[(name, label)])
            cells.append(f"{label} {v:7.2f}")
        print(f"  {name:16s} " + "  ".join(cells))
    if a.no_loop:
        return
    loops = whole_loop(versions, params, a.duration, a.repeat)
    print(f"direct loop µs per PRI (best of {a.repeat}, alternating):")
    for label, (w, c) in loops.items():
        print(f"  {label:7s} wall {w:7.2f}  CPU {c:7.2f}")
    if a.before:
        print(f"  ratio after/before (CPU): {loops['after'][1] / loops['before'][1]:.3f}")


if __name__ == "__main__":
    main()
