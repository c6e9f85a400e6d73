"""Bytecode instructions executed per PRI of the direct loop, per area and per function.

Run::

    python benchmarks/count_bytecodes.py [--steps 300] [--top 30] [--lines FILE_PART ...]
        [--by-unit] [--run]

The closed-loop scenario runs 0.1 s through :class:`axir.models.loop.DirectLoop`, then
``--steps`` PRIs under ``sys.settrace`` with opcode events: every bytecode instruction executed
is counted against its function (and with ``--lines``, against its source line, for files whose
path contains one of the given parts). A count, not a time: deterministic, whatever the load of
the machine, so it ranks what a change removes (issue 14, session 9: in the interleaved loop each
instruction costs ≈ 10-13 ns, each numpy call on a (4, 16, 3) array ≈ 0.6-2 µs, which this does
not count). Slow (tracing): a few seconds. ``--by-unit`` also counts per unit: every
instruction goes to the unit whose ``step`` is on the stack (the Tracker's geometry in
``radar/`` to the Tracker, the TargetGenerator's to the TargetGenerator), the rest to the loop.
"""

from __future__ import annotations

import argparse
import collections
import linecache
import sys
from typing import Any

from bench_loop import _scenario, direct_params

from axir.models.loop import DirectLoop


def _area(path: str) -> str:
    for key, name in (("target_generator", "TargetGenerator"), ("/radar/", "radar/ (TG, Tracker)"),
                      ("pedestal", "Pedestal"), ("/tracker/", "Tracker"),
                      ("/filters/", "filters/ (Tracker)"), ("/manager/", "RadarManager"),
                      ("loop.py", "loop"), ("<gs_step", "loop")):
        if key in path:
            return name
    return "other"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--top", type=int, default=30)
    ap.add_argument("--lines", nargs="*", default=[], help="per-line counts for these files")
    ap.add_argument("--by-unit", action="store_true",
                    help="also count per unit (the unit whose step is on the stack)")
    ap.add_argument("--run", action="store_true",
                    help="count DirectLoop.run (the written-out run loop that bench_loop.py "
                         "times) instead of DirectLoop.step: the PRIs of --steps × the "
                         "default PRI, per PRI actually run")
    a = ap.parse_args()
    loop = DirectLoop.from_params(direct_params(_scenario(1.0)))
    loop.run(0.1)
    funcs: collections.Counter[tuple[str, int, str]] = collections.Counter()
    lines: collections.Counter[tuple[str, int]] = collections.Counter()
    units: collections.Counter[str] = collections.Counter()
    unit_names = {id(u): type(u).__name__ for u in loop.units.values()}
    # the run loop may call the Tracker's input-mode step directly (Unit.run_step, round 10)
    core = getattr(loop.trk, "core", None)
    if core is not None:
        unit_names[id(core)] = "Tracker"

    def unit_of(frame: Any) -> str:
        f = frame
        while f is not None:
            if f.f_code.co_name == "step" and id(f.f_locals.get("self")) in unit_names:
                return unit_names[id(f.f_locals["self"])]
            f = f.f_back
        return "loop"

    def local(frame: Any, event: str, arg: Any) -> Any:
        if event == "opcode":
            co = frame.f_code
            funcs[(co.co_filename, co.co_firstlineno, co.co_name)] += 1
            if a.lines and any(p in co.co_filename for p in a.lines):
                lines[(co.co_filename, frame.f_lineno)] += 1
        return local

    def tracer(frame: Any, event: str, arg: Any) -> Any:
        frame.f_trace_opcodes = True
        frame.f_trace_lines = False
        if not a.by_unit:
            return local
        name = unit_of(frame)

        def local_unit(fr: Any, event: str, arg: Any) -> Any:
            if event == "opcode":
                units[name] += 1
            local(fr, event, arg)
            return local_unit
        return local_unit

    s0 = loop.steps
    sys.settrace(tracer)
    try:
        if a.run:
            loop.run(loop.t + a.steps * 1e-4)
        else:
            for _ in range(a.steps):
                loop.step()
    finally:
        sys.settrace(None)
    n = loop.steps - s0
    areas: collections.Counter[str] = collections.Counter()
    for (path, _, _), v in funcs.items():
        areas[_area(path)] += v
    print(f"bytecode instructions per PRI ({n} PRIs): total {sum(areas.values()) / n:.0f}")
    for name, v in areas.most_common():
        print(f"  {name:24s} {v / n:7.0f}")
    if a.by_unit:
        print("per unit (the unit whose step is on the stack):")
        for name, v in units.most_common():
            print(f"  {name:24s} {v / n:7.0f}")
    print("per function:")
    for (path, first, name), v in funcs.most_common(a.top):
        short = path.split("/models/")[-1]
        print(f"  {v / n:7.1f}  {short}:{first} {name}")
    for (path, line), v in sorted(lines.items(), key=lambda kv: (kv[0][0], kv[0][1] or 0)):
        text = linecache.getline(path, line).rstrip()[:100] if line else "(no line)"
        print(f"  {v / n:6.1f} {path.split('/models/')[-1]}:{line} {text}")


if __name__ == "__main__":
    main()
