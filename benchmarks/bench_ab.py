"""Direct loops of two (or more) model trees run side by side in short turns, CPU µs per PRI.

Run::

    python benchmarks/bench_ab.py --tree main=DIR [--tree NAME=DIR ...] [--duration 1.5]
        [--segment 0.02] [--repeat 6]

Each ``DIR`` holds a ``models`` package (e.g. ``git archive <rev> models | tar -x -C DIR``, then
``DIR/models``; the tree of this checkout is always added as ``now``). Each is copied under its
own package name into a temporary directory and imported there, so the versions live in one
process. Per repeat, one fresh :class:`DirectLoop` per tree runs the closed-loop scenario
(parameters and seeds as ``bench_loop.py``) in turns of ``--segment`` simulated seconds
(≈ 200 PRIs), the order of the trees reversed every turn, until ``--duration``; the CPU time
of each turn (``time.process_time``) is summed per tree. A change of the machine's load
reaches every tree within one turn, finer than ``bench_units.py``'s whole runs (issue 14,
round 10: the VM shared with another engineer's jobs, load 3-4). Printed: µs per PRI per tree
and repeat, the ratios to the first tree, their median and the overall ratio. Numbers only.
"""

from __future__ import annotations

import argparse
import importlib
import shutil
import sys
import tempfile
import time
from pathlib import Path

from bench_loop import _scenario, direct_params


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tree", action="append", default=[], metavar="NAME=DIR",
                    help="a directory holding a 'models' package, or the package itself")
    ap.add_argument("--duration", type=float, default=1.5, help="simulated seconds [s]")
    ap.add_argument("--segment", type=float, default=0.02, help="simulated seconds per turn")
    ap.add_argument("--repeat", type=int, default=6)
    a = ap.parse_args()
    here = Path(__file__).resolve().parents[1] / "models"
    trees = [t.split("=", 1) for t in a.tree] + [["now", str(here)]]
    tmp = Path(tempfile.mkdtemp(prefix="bench_ab_"))
    sys.path.insert(0, str(tmp))
    loops_cls = {}
    try:
        for k, (name, d) in enumerate(trees):
            src = Path(d)
            src = src / "models" if (src / "models" / "loop.py").exists() else src
            shutil.copytree(src, tmp / f"ab_models_{k}")
            loops_cls[name] = importlib.import_module(f"ab_models_{k}.loop").DirectLoop
        params = direct_params(_scenario(a.duration))
        names = list(loops_cls)
        pc = time.process_time
        ratios: list[list[float]] = []
        total = {n: [0.0, 0] for n in names}
        for _ in range(a.repeat):
            loops = {n: loops_cls[n].from_params(params) for n in names}
            acc = {n: [0.0, 0] for n in names}
            t, turn = 0.0, 0
            while t < a.duration:
                t += a.segment
                for n in (names if turn % 2 == 0 else names[::-1]):
                    lp = loops[n]
                    s0, c0 = lp.steps, pc()
                    lp.run(t)
                    acc[n][0] += pc() - c0
                    acc[n][1] += lp.steps - s0
                turn += 1
            us = {n: acc[n][0] / acc[n][1] * 1e6 for n in names}
            for n in names:
                total[n][0] += acc[n][0]
                total[n][1] += acc[n][1]
            ratios.append([us[n] / us[names[0]] for n in names])
            print("  ".join(f"{n} {us[n]:7.2f}" for n in names), "  ratios",
                  " ".join(f"{r:.3f}" for r in ratios[-1]), flush=True)
        base = total[names[0]][0] / total[names[0]][1]
        for j, n in enumerate(names):
            rs = sorted(r[j] for r in ratios)
            print(f"{n}: overall {total[n][0] / total[n][1] * 1e6:.2f} µs per PRI, ratio "
                  f"{total[n][0] / total[n][1] / base:.4f} (median {rs[len(rs) // 2]:.4f}, "
                  f"{rs[0]:.4f} … {rs[-1]:.4f})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
