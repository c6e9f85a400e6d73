"""The radar across its engagement envelope (issue 11, point 5): run the envelope design
(orchestrator/envelope_run.py: a range × radial-speed plane plus elevation, RCS, maneuver and
slow-speed sweeps and target-free clutter runs) in the direct model loop on a process pool,
cached per cell in a CSV, then write the heat maps (docs/img/envelope_*.png) and the tables of
docs/envelope.md (between its ``<!-- envelope:begin -->`` / ``<!-- envelope:end -->`` marks).

Run: ``python benchmarks/bench_envelope.py [--csv out/envelope.csv] [--workers 2] [--seeds N]
[--quick] [--parts plane,lowplane,elevation,rcs,maneuver,slow,clutter] [--report-only] [--no-report]
[--fmu-check]``.

``--fmu-check`` runs the anchor cell (1.5 s) through the four FMUs (built into a temporary
directory) and through the direct loop and prints both summaries (they must agree).
Nothing is asserted: numbers only (goals in docs/envelope.md).
"""

from __future__ import annotations

import argparse
import signal
import sys
import time
from pathlib import Path

from axir.orchestrator.envelope_run import design, run_design

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--csv", type=Path, default=ROOT / "out" / "envelope.csv")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=None, help="seeds per part (default 2-3)")
    ap.add_argument("--quick", action="store_true", help="the 3-cell test subset")
    ap.add_argument("--parts", default="", help="run only these parts of the design "
                    "(comma-separated: plane, lowplane, elevation, rcs, maneuver, slow, clutter; "
                    "default all)")
    ap.add_argument("--report-only", action="store_true", help="only tables and figures")
    ap.add_argument("--no-report", action="store_true", help="only run the cells")
    ap.add_argument("--fmu-check", action="store_true", help="direct loop vs FMUs, one cell")
    ap.add_argument("--doc", type=Path, default=ROOT / "docs" / "envelope.md")
    a = ap.parse_args(argv)
    if a.workers < 1:
        print(f"--workers must be >= 1, got {a.workers}", file=sys.stderr)
        return 2
    if a.fmu_check:
        from envelope_report import fmu_check

        fmu_check()
        return 0
    # SIGTERM ends the run like Ctrl-C: the pool's workers are terminated, the CSV kept
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    cells = design(quick=a.quick, seeds=a.seeds)
    parts = {x.strip() for x in a.parts.split(",") if x.strip()}
    unknown = parts - {label for label, _ in cells}
    if unknown:
        print(f"--parts: unknown part(s) {', '.join(sorted(unknown))}", file=sys.stderr)
        return 2
    run_cells = [c for c in cells if not parts or c[0] in parts]
    if not a.report_only:
        t0 = time.perf_counter()

        def progress(row: dict, i: int, n: int) -> None:
            print(f"[{i}/{n} {time.perf_counter() - t0:7.0f} s] {row['design']} "
                  f"R={row['range_m']} v={row['speed']} el={row['el_deg']} rcs={row['rcs']} "
                  f"g={row['g']} seed={row['seed']}: lock={row['lock_time']} "
                  f"drops={row['drops']} false={row['false_confirmations']} "
                  f"cpu={row['cpu_s']} s", flush=True)

        rows = run_design(run_cells, a.csv, a.workers, progress)
        print(f"{len(rows)} cells in {a.csv} ({time.perf_counter() - t0:.0f} s wall this run)")
    if not a.no_report and not a.quick:
        from envelope_report import report

        report(a.csv, a.doc, cells)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    raise SystemExit(main())
