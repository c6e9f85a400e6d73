"""Low-elevation engagements through ground clutter (issue 11, point 2: "ground clutter at low
elevation (down to 0.5°) must not make a confirmed track"): three sets of 1 m² targets, clutter
on, 3 s, run in the direct loop (:func:`axir.orchestrator.envelope.run_cell`) and counted as
``bench_envelope.py`` counts a cell (benchmarks/envelope_report.py ``verdict``: confirmed on
target within 1 s, held ≥ 99 %, no drop, RMS range ≤ 10 m, no false confirmation; a run below
the detection criterion is ok without a false confirmation).

- ``lowel``: 6 / 10 / 14 km × 1 / 2 / 3° × ±100 / ±125 / ±150 / ±180 m/s × seeds 1-2 (144
  runs; session 16's sweep of the same name, whose speeds "±100-180 m/s" were not recorded);
- ``lowel2``: 4 / 8 / 12 / 20 km × 0.5 / 1.5 / 2.5 / 4° × ±60 / ±220 / ±300 m/s × seeds 1-2
  (192 runs, session 16's);
- ``stress``: turning targets (session 10): 9 / 16 / 24 km × 1 / 2.5° × 5 / 7 g × ±215 m/s,
  150 m/s across, azimuth 60°, turn from 0.6 s, seed 3 (24 runs), and 2.5° / −215 m/s at
  16 km / 5 g and 24 km / 7 g with seeds 1-6 (12 runs; their seed 3 repeats two of the 24, as
  in session 10's count of 36);
- ``crossing`` (session 30, not in the default ``--sets``): targets flying straight past the
  radar toward the clutter notch: 3 / 6 / 12 / 20 km × 0.5 / 1 / 2 / 3 / 4° × 100 / 250 /
  400 m/s across × 1 / 10 m², radial speed −(a_r·1 s + 6 m/s) at the start (a_r = v²/r, the
  radial acceleration of straight flight: −4.9 to −6 m/s, the notch's edge, 1 s in), azimuth 30°,
  seed 1, 4 s (120 runs); the radial speed passes through 0 within the run in 90 of them
  (not at 100 m/s across from 6 km on, a_r ≤ 1.7 m/s²);
- ``longcross`` (session 31, not in the default ``--sets``): slow crossings, 5 and 10 s through
  the ±5 m/s notch: 6 / 12 / 20 km × 1 / 2 / 4° × 1 / 10 m², speed across √(10 m/s · r / T)
  (a_r = 10 m/s ÷ T; 110 / 155 / 200 m/s for T = 5 s, 77 / 110 / 141 m/s for 10 s), radial
  speed −(a_r·1 s + 6 m/s) at the start as ``crossing``, until +8 m/s (1 + 14 m/s ÷ a_r: 8
  and 15 s), azimuth 30°, seed 1 (36 runs).

Run: ``python benchmarks/bench_low_elevation.py [--sets lowel,lowel2,stress,crossing,longcross]
[--workers 2] [--jsonl FILE] [--tracker '{"pointing_gain": 3}'] [--manager '{...}']``; ≈ 10 min
on 2 cores (the crossing set ≈ 5 min more, longcross ≈ 5 min). Prints per set the
runs, verdicts, runs with a false confirmation (and their time off target), drops and runs
never confirmed, then every run that misses. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections import Counter
from multiprocessing import Pool
from pathlib import Path
from typing import Any

import axir.orchestrator.envelope as env
from axir.orchestrator.envelope import Cell

SETS = ("lowel", "lowel2", "stress")
ALL_SETS = (*SETS, "crossing", "longcross")


def cells(name: str) -> list[Cell]:
    """The cells of set ``name`` (module docstring)."""
    if name == "lowel":
        return [Cell(range_m=r, speed=s * v, el_deg=e, rcs=1.0, seed=seed)
                for r in (6000.0, 10000.0, 14000.0) for e in (1.0, 2.0, 3.0)
                for v in (100.0, 125.0, 150.0, 180.0) for s in (1.0, -1.0) for seed in (1, 2)]
    if name == "lowel2":
        return [Cell(range_m=r, speed=s * v, el_deg=e, rcs=1.0, seed=seed)
                for r in (4000.0, 8000.0, 12000.0, 20000.0) for e in (0.5, 1.5, 2.5, 4.0)
                for v in (60.0, 220.0, 300.0) for s in (1.0, -1.0) for seed in (1, 2)]
    if name == "stress":
        turn = {"rcs": 1.0, "tangential": 150.0, "az_deg": 60.0, "maneuver_onset": 0.6}
        out = [Cell(range_m=r, speed=v, el_deg=e, g=g, seed=3, **turn)
               for r in (9000.0, 16000.0, 24000.0) for e in (1.0, 2.5) for g in (5.0, 7.0)
               for v in (215.0, -215.0)]
        out += [Cell(range_m=r, speed=-215.0, el_deg=2.5, g=g, seed=seed, **turn)
                for r, g in ((16000.0, 5.0), (24000.0, 7.0)) for seed in range(1, 7)]
        return out
    if name == "crossing":
        return [Cell(range_m=r, speed=-round(v * v / r + 6.0, 2), el_deg=e, rcs=a, seed=1,
                     duration=4.0, tangential=v, az_deg=30.0)
                for r in (3000.0, 6000.0, 12000.0, 20000.0) for e in (0.5, 1.0, 2.0, 3.0, 4.0)
                for v in (100.0, 250.0, 400.0) for a in (1.0, 10.0)]
    if name == "longcross":
        out = []
        for r in (6000.0, 12000.0, 20000.0):
            for t_band in (5.0, 10.0):
                v = round(math.sqrt(10.0 * r / t_band))
                a_r = v * v / r
                out += [Cell(range_m=r, speed=-round(a_r + 6.0, 2), el_deg=e, rcs=a, seed=1,
                             duration=round(1.0 + 14.0 / a_r, 1), tangential=float(v),
                             az_deg=30.0)
                        for e in (1.0, 2.0, 4.0) for a in (1.0, 10.0)]
        return out
    raise ValueError(f"unknown set {name!r} (known: {', '.join(ALL_SETS)})")


def run_one(job: tuple[str, Cell, dict[str, Any], dict[str, Any]]) -> dict[str, Any]:
    """One run: (set, cell, Tracker overrides, RadarManager overrides) → its summary
    figures."""
    name, cell, tracker, manager = job
    s = env.run_cell(cell, overrides={"Tracker": tracker, "RadarManager": manager})
    return {"set": name, "range_m": cell.range_m, "speed": cell.speed, "el_deg": cell.el_deg,
            "g": cell.g, "tangential": cell.tangential, "rcs": cell.rcs, "seed": cell.seed,
            "detectable": env.detectable(cell),
            "lock": s["lock_time"], "held": s["held_fraction"], "drops": s["drops"],
            "false": s["false_confirmations"], "t_false": s["time_false_confirmed_s"],
            "rms_m": s["rms_range_error_m"]}


def verdict(row: dict[str, Any]) -> str:
    """The envelope benchmark's verdict of a run (benchmarks/envelope_report.py)."""
    from envelope_report import run_verdict  # benchmarks/ (on sys.path)

    return run_verdict(row)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sets", default=",".join(SETS))
    ap.add_argument("--workers", type=int, default=2, choices=range(1, 65), metavar="N")
    ap.add_argument("--jsonl", default=None, help="also write every run as a JSON line")
    ap.add_argument("--tracker", default="{}", help="Tracker parameter overrides (JSON)")
    ap.add_argument("--manager", default="{}", help="RadarManager parameter overrides (JSON)")
    a = ap.parse_args(argv)
    names = [n for n in a.sets.split(",") if n]
    for n in names:
        if n not in ALL_SETS:
            ap.error(f"unknown set {n!r} (known: {', '.join(ALL_SETS)})")
    tracker, manager = json.loads(a.tracker), json.loads(a.manager)
    jobs = [(n, c, tracker, manager) for n in names for c in cells(n)]
    with Pool(a.workers) as pool:
        rows = pool.map(run_one, jobs)
    if a.jsonl:
        with open(a.jsonl, "w") as f:
            f.writelines(json.dumps(r) + "\n" for r in rows)
    print("set    | runs | verdicts | runs with a false confirmation (time off target [s]) | "
          "drops | never confirmed")
    for n in names:
        rs = [r for r in rows if r["set"] == n]
        v = Counter(verdict(r) for r in rs)
        print(f"{n:6} | {len(rs):4d} | {dict(sorted(v.items()))} | "
              f"{sum(r['false'] > 0 for r in rs)} ({sum(r['t_false'] for r in rs):.3f}) | "
              f"{sum(r['drops'] for r in rs)} | {sum(r['lock'] is None for r in rs)}")
    for r in rows:
        if verdict(r) not in ("ok", "n/d"):
            print(f"  {verdict(r):12} {r}")


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    main()
