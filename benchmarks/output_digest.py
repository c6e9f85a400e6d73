"""SHA-256 of every output of every unit at every step of a direct-loop run (issue 14).

Run::

    python benchmarks/output_digest.py [--duration 2] [--save OUT.npy] [--compare-to OLD.npy]
        [--run]

The built-in ``closed-loop`` scenario (or ``--scenario``; parameters and seeds as
``bench_loop.py``) runs through
:class:`axir.models.loop.DirectLoop`; after each step every output of the four units (arrays
included: beams, SUM) is fed to one SHA-256 as float64 bytes, units in the Gauss-Seidel order,
keys sorted by name. Two trees whose models do the same arithmetic print the same digest.
``--run``: each step taken by ``DirectLoop.run`` to the next float after ``t`` (one pass of the
written-out run loop, which ``bench_loop.py`` times: the units' positional steps, issue 14,
round 11) instead of ``DirectLoop.step``; the same digest.

``--save`` writes the scalar outputs as a float64 array of shape (steps, scalars) (columns:
``--save``'s name with ``.keys.txt``); ``--compare-to`` reads such a file (same duration) and
prints, per output, the largest absolute difference from this run (outputs that differ only),
the overall largest, and the steps where booleans/integers differ. A check, not a test:
numbers only.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from bench_loop import direct_params

from axir.models.loop import DirectLoop
from axir.orchestrator.scenario import load_scenario


def run(duration: float, keep: bool, scenario: str = "closed-loop", by_run: bool = False
        ) -> tuple[str, int, list[str], np.ndarray | None]:
    """(hex digest, steps, scalar column names, scalar outputs per step or None)."""
    sc = replace(load_scenario(scenario), duration=duration)
    loop = DirectLoop.from_params(direct_params(sc))
    h = hashlib.sha256()
    order = [name for name, _, _ in loop._plan]
    layout: list[tuple[str, list[str], list[str]]] | None = None  # unit, scalars, arrays
    rows: list[np.ndarray] = []
    while loop.t < duration:
        if by_run:
            loop.run(math.nextafter(loop.t, math.inf))  # one pass of the run loop
        else:
            loop.step()
        out = loop.out
        if layout is None:
            layout = []
            for u in order:
                keys = sorted(out[u])
                arrays = [k for k in keys if hasattr(out[u][k], "shape")]
                layout.append((u, [k for k in keys if k not in arrays], arrays))
        row = np.array([float(out[u][k]) for u, sc, _ in layout for k in sc], dtype=np.float64)
        h.update(row.tobytes())
        for u, _, arrs in layout:
            for k in arrs:
                h.update(np.ascontiguousarray(out[u][k], dtype=np.float64).tobytes())
        if keep:
            rows.append(row)
    names = [f"{u}.{k}" for u, sc, _ in (layout or []) for k in sc]
    return h.hexdigest(), loop.steps, names, (np.array(rows) if keep else None)


def compare(names: list[str], new: np.ndarray, old_path: Path) -> None:
    """Print the largest absolute difference per differing output against a saved run."""
    old = np.load(old_path)
    old_names = Path(str(old_path) + ".keys.txt").read_text().split()
    if old_names != names or old.shape != new.shape:
        print(f"cannot compare: {old_path} has {old.shape} {len(old_names)} columns, this run "
              f"{new.shape}")
        return
    both_nan = np.isnan(old) & np.isnan(new)
    diff = np.where(both_nan, 0.0, np.abs(new - old))
    worst = np.nanmax(np.where(np.isnan(diff), np.inf, diff), axis=0)
    print(f"largest |difference| over {new.shape[0]} steps (differing outputs only):")
    any_diff = False
    for name, d, col in zip(names, worst, range(new.shape[1]), strict=True):
        if d > 0.0:
            any_diff = True
            scale = np.nanmax(np.abs(old[:, col]))
            first = int(np.argmax(diff[:, col] > 0.0))
            print(f"  {name:40s} {d:.3e}  (max |value| {scale:.3e}, first at step {first})")
    print(f"overall largest |difference|: {float(np.max(worst)):.3e}" if any_diff
          else "no difference: every scalar output identical")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=2.0, help="simulated seconds [s]")
    ap.add_argument("--scenario", default="closed-loop",
                    help="a built-in scenario or .toml (its unit parameters and seeds)")
    ap.add_argument("--save", type=Path, default=None, help="write the scalar outputs (.npy)")
    ap.add_argument("--compare-to", type=Path, default=None,
                    help="a .npy written by --save (same duration) to compare with")
    ap.add_argument("--run", action="store_true",
                    help="step by DirectLoop.run (the run loop) instead of DirectLoop.step")
    a = ap.parse_args()
    if a.compare_to is not None and not a.compare_to.is_file():
        print(f"output_digest: --compare-to {a.compare_to}: no such file", file=sys.stderr)
        raise SystemExit(2)
    t0 = time.perf_counter()
    try:
        sc = load_scenario(a.scenario)
    except Exception as e:  # any failure to load it: one line naming it, exit 2
        print(f"output_digest: --scenario {a.scenario}: {e}", file=sys.stderr)
        raise SystemExit(2) from None
    if sc.algorithm != "gauss-seidel":
        print(f"note: the direct loop runs Gauss-Seidel; scenario {a.scenario} says "
              f"{sc.algorithm}", file=sys.stderr)
    digest, steps, names, rows = run(a.duration, a.save is not None or a.compare_to is not None,
                                     a.scenario, a.run)
    print(f"sha256 {digest}  ({a.scenario}, {steps} steps, {a.duration} s, "
          f"{time.perf_counter() - t0:.1f} s wall)")
    if a.save is not None:
        np.save(a.save, rows)
        Path(str(a.save) + ".keys.txt").write_text("\n".join(names) + "\n")
        print(f"saved {rows.shape} to {a.save}")
    if a.compare_to is not None:
        compare(names, rows, a.compare_to)


if __name__ == "__main__":
    main()
