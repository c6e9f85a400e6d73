"""Designation errors (issue 11): seven 1 m² engagements × seeds × designation offsets of up to
3.5°, run in the direct loop (:func:`axir.orchestrator.envelope.run_cell`), counted per offset
as ``bench_envelope.py`` counts a cell (its ``verdict``: confirmed on target within 1 s, held
≥ 99 %, no drop, RMS range ≤ 10 m, no false confirmation; a run not detectable by its
criterion is ok without a false confirmation), with the time confirmed off target and the
drops.

Run: ``python benchmarks/bench_designation.py [--seeds 1,2] [--workers 2] [--jsonl FILE]
[--tracker '{"report_inverts_pattern": false}'] [--offsets '4.5,0;0,-4']``. ≈ 3 min on 2 cores.
Nothing is asserted.

The offsets are added to the envelope's default designation error (+0.5° az, −0.3° el,
+300 m: ``envelope.DESIGNATION_ERROR``); the pedestal starts on the designation.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import defaultdict
from multiprocessing import Pool
from pathlib import Path
from typing import Any

import axir.orchestrator.envelope as env
from axir.orchestrator.envelope import Cell

#: (range [m], radial speed [m/s], elevation [deg], speed across the line of sight [m/s])
GEOMETRIES = (
    (10000.0, -53.0, 5.0, 0.0), (6000.0, -100.0, 1.0, 0.0), (2500.0, 0.0, 10.0, 300.0),
    (10000.0, 140.0, 2.0, 0.0), (8000.0, -300.0, 30.0, 0.0), (4000.0, 0.0, 60.0, 200.0),
    (10000.0, 250.0, 10.0, 0.0))
#: designation offsets (az, el) [deg] on top of the default error
OFFSETS = ((0.0, 0.0), (0.0, 3.0), (3.0, 0.0), (-2.0, -2.0), (0.0, -2.5), (-2.0, 0.0),
           (0.0, 2.0), (1.5, 1.5))


def run_one(job: tuple[Any, ...]) -> dict[str, Any]:
    """One run: (geometry, offset, seed, Tracker overrides) → its summary figures."""
    (r, v, el, across), (d_az, d_el), seed, tracker = job
    base = env.DESIGNATION_ERROR
    cell = Cell(range_m=r, speed=v, el_deg=el, rcs=1.0, seed=seed, duration=3.0,
                tangential=across)
    env.DESIGNATION_ERROR = (base[0] + d_az, base[1] + d_el, base[2])
    try:
        s = env.run_cell(cell, overrides={"Tracker": tracker})
    finally:
        env.DESIGNATION_ERROR = base
    return {"range_m": r, "speed": v, "el_deg": el, "across": across, "d_az": d_az,
            "d_el": d_el, "seed": seed, "detectable": env.detectable(cell),
            "lock": s["lock_time"], "held": s["held_fraction"],
            "drops": s["drops"], "false": s["false_confirmations"],
            "t_false": s["time_false_confirmed_s"], "rms_m": s["rms_range_error_m"]}


def ok(row: dict[str, Any]) -> bool:
    """The envelope benchmark's verdict (benchmarks/envelope_report.py ``verdict``) is "ok",
    or "n/d" (a run not detectable by the envelope's criterion, without a false confirmation:
    the crossing targets of radial speed 0, in the clutter notch)."""
    from envelope_report import run_verdict  # benchmarks/ (on sys.path when run as a script)

    return run_verdict(row) in ("ok", "n/d")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--workers", type=int, default=2, choices=range(1, 65), metavar="N")
    ap.add_argument("--jsonl", default=None, help="also write every run as a JSON line")
    ap.add_argument("--tracker", default="{}", help="Tracker parameter overrides (JSON)")
    ap.add_argument("--offsets", default=None,
                    help="designation offsets instead of OFFSETS: 'az,el;az,el;…' [deg]")
    a = ap.parse_args(argv)
    tracker = json.loads(a.tracker)
    offsets = (OFFSETS if a.offsets is None else
               [tuple(float(x) for x in o.split(",")) for o in a.offsets.split(";")])
    jobs = [(g, o, int(s), tracker) for o in offsets for g in GEOMETRIES
            for s in a.seeds.split(",")]
    with Pool(a.workers) as pool:
        rows = pool.map(run_one, jobs)
    if a.jsonl:
        with open(a.jsonl, "w") as f:
            f.writelines(json.dumps(r) + "\n" for r in rows)
    by: dict[tuple[float, float], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        by[(r["d_az"], r["d_el"])].append(r)
    print("offset (az, el) [deg] | runs | ok | runs with a false confirmation | "
          "time confirmed off target [s] | drops | never confirmed")
    for key in [*by, "all"]:
        rs = rows if key == "all" else by[key]
        print(f"{key!s:>21} | {len(rs):4d} | {sum(map(ok, rs)):3d} | "
              f"{sum(r['false'] > 0 for r in rs):3d} | {sum(r['t_false'] for r in rs):.3f} | "
              f"{sum(r['drops'] for r in rs):3d} | {sum(r['lock'] is None for r in rs):3d}")


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    main()
