"""Random off-grid engagements (issue 11): N seeded draws of :class:`Cell` over the envelope,
run in the direct loop (:func:`axir.orchestrator.envelope_run.run_design`, cached per cell in
a CSV), judged with the envelope benchmark's verdict (benchmarks/envelope_report.py) and
detectability criterion (orchestrator/envelope.py).

The design of bench_envelope.py holds azimuth, the radial-only flight and the maneuver onset
fixed; this draws them (# assumption: uniform draws, the ranges of issue 11 point 5):

- range 2-60 km, radial speed −1000..+1000 m/s, elevation 0.5-80°, RCS log-uniform
  0.1-10 m², azimuth 0-360°, tangential (horizontal, across the line of sight) 0-300 m/s;
- half the targets maneuver: a level turn of 0-7 g from 0.5-2 s (tangential then ≥ 100 m/s so
  that the turn has a horizontal velocity to turn);
- every ``free_every``-th cell is target-free (elevation 0.5-10°: the clutter regime);
- cell seeds 1-9; a draw that would pass within 1 km of the radar in the run is redrawn.

Run: ``python benchmarks/bench_envelope_random.py [--n 80] [--draw-seed 0]
[--csv out/envelope_random.csv] [--workers 2] [--duration 3] [--range-km 2 60]
[--el-deg 0.5 80]``. Prints the verdict counts and
every row that misses a goal; nothing asserted.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections import Counter
from pathlib import Path

import numpy as np

from axir.orchestrator.envelope import Cell
from axir.orchestrator.envelope_run import run_design

ROOT = Path(__file__).resolve().parents[1]
LABEL = "random"


def draw_cells(n: int, draw_seed: int = 0, duration: float = 3.0, free_every: int = 8,
               range_km: tuple[float, float] = (2.0, 60.0),
               el_deg: tuple[float, float] = (0.5, 80.0)) -> list[Cell]:
    """``n`` random cells (module docstring), reproducible from ``draw_seed``; ``range_km``
    and ``el_deg`` bound the range [km] and elevation [deg] draws."""
    rng = np.random.default_rng(draw_seed)
    out: list[Cell] = []
    while len(out) < n:
        r = float(rng.uniform(1000.0 * range_km[0], 1000.0 * range_km[1]))
        v = float(rng.uniform(-1000.0, 1000.0))
        el = float(rng.uniform(*el_deg))
        rcs = float(10.0 ** rng.uniform(-1.0, 1.0))
        az = float(rng.uniform(0.0, 360.0))
        tang = float(rng.uniform(0.0, 300.0))
        g = float(rng.uniform(0.0, 7.0)) if rng.random() < 0.5 else 0.0
        onset = float(rng.uniform(0.5, 2.0))
        seed = int(rng.integers(1, 10))
        if g > 0.0:
            tang = max(tang, 100.0)
        if (len(out) + 1) % free_every == 0:
            el = float(rng.uniform(el_deg[0], min(el_deg[1], 10.0)))
            rcs, g, v, tang = 0.0, 0.0, 0.0, 0.0
        if r + min(v, 0.0) * duration < 1_000.0:
            continue
        out.append(Cell(range_m=round(r, 1), speed=round(v, 2), el_deg=round(el, 2),
                        rcs=round(rcs, 3), g=round(g, 2), seed=seed, duration=duration,
                        az_deg=round(az, 2), tangential=round(tang, 1),
                        maneuver_onset=round(onset, 2)))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=80)
    ap.add_argument("--draw-seed", type=int, default=0)
    ap.add_argument("--duration", type=float, default=3.0)
    ap.add_argument("--csv", type=Path, default=ROOT / "out" / "envelope_random.csv")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--range-km", type=float, nargs=2, default=(2.0, 60.0),
                    help="range bounds of the draws [km]")
    ap.add_argument("--el-deg", type=float, nargs=2, default=(0.5, 80.0),
                    help="elevation bounds of the draws [deg]")
    a = ap.parse_args(argv)
    from envelope_report import verdict

    cells = [(LABEL, c) for c in draw_cells(a.n, a.draw_seed, a.duration,
                                            range_km=tuple(a.range_km),
                                            el_deg=tuple(a.el_deg))]

    def progress(row: dict, i: int, n: int) -> None:
        print(f"[{i}/{n}] {verdict({k: str(x) for k, x in row.items()}):12s} "
              f"R={row['range_m']} v={row['speed']} el={row['el_deg']} rcs={row['rcs']} "
              f"g={row['g']} s={row['seed']} lock={row['lock_time']} "
              f"false={row['false_confirmations']} cpu={row['cpu_s']}", flush=True)

    rows = run_design(cells, a.csv, a.workers, progress)
    counts = Counter(verdict(r) for r in rows)
    det = sum(r["detectable"] == "True" for r in rows)
    print(f"\n{len(rows)} cells ({det} detectable); verdicts: "
          + ", ".join(f"{k} {v}" for k, v in counts.most_common()))
    print(f"false confirmations: {sum(int(r['false_confirmations']) for r in rows)} in "
          f"{sum(int(r['false_confirmations']) > 0 for r in rows)} runs")
    cols = ("range_m", "speed", "el_deg", "rcs", "az_deg", "tangential", "g",
            "maneuver_onset", "seed", "snr_filtered_db", "clutter_loss_db", "lock_time",
            "held_fraction", "drops", "false_confirmations", "rms_range_error_m")
    print("\nverdict | " + " | ".join(cols))
    for r in sorted(rows, key=lambda r: (verdict(r), float(r["range_m"]))):
        v = verdict(r)
        if v not in ("ok", "n/d"):
            print(f"{v} | " + " | ".join(
                f"{float(r[c]):.3g}" if r[c] not in ("", None) and c != "seed"
                and not math.isnan(float(r[c])) else str(r[c]) for c in cols))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    raise SystemExit(main())
