"""The envelope design and its resumable runner (issue 11, point 5).

A full factorial grid over range × radial speed × elevation × RCS × maneuver × seeds is far
too expensive on 2 cores (a 3 s engagement costs ≈ 3.4 s CPU in the direct loop), so the
benchmark uses a design (:func:`design`):

- ``plane``: range × radial speed at elevation 5°, RCS 10 m², no maneuver, seeds 1-2. Ranges
  2, 5, 10, 20, 30, 42, 60 km (up to four unambiguous ranges of the 10 kHz acquisition PRF,
  Ru = 15 km); radial speeds: 29 evenly spaced in −1000..+1000 m/s (71.4 m/s apart: 0.45 of
  the acquisition PRI's blind-speed interval λ·PRF/2 = 159.6 m/s, so the folded Dopplers
  spread over the band, v = 0 included) plus two just beside a blind speed (folded Doppler
  ≈ 250 Hz from the clutter line on the acquisition PRI). Closing cells that would pass
  within 500 m of the radar during the run are left out.
- one-factor sweeps about an anchor at 10 km, radial speed −53.15 m/s (folded Doppler on the
  centre of Doppler filter 3, PRF/3 = 3333 Hz, on the acquisition PRI), el 5°, 10 m², seeds
  1-3: ``elevation`` 0.5-80°; ``rcs`` 0.1-10 m² at 30 km (where 0.1 m² falls below the
  detectability criterion); ``maneuver`` 0-7 g (a level turn from 1.0 s, with 250 m/s of
  horizontal speed across the line of sight so that the turn has a velocity to turn);
  ``slow``: radial speeds ±5.5-9.5 m/s, just outside the manager's ±5 m/s clutter notch
  (session 27: the speed grid's 71.4 m/s steps never sample them, and such targets were never
  confirmed: docs/clutter.md "The notch test on the resolved Doppler").
- ``lowplane``: the same plane at elevation 1° (main-beam clutter, MTI on), every other
  speed of the plane, ranges 5, 10, 20, 30, 42 km, seed 1.
- ``clutter``: target-free runs (RCS 0) at 0.5-10° elevation, 10 s each, seeds 1-2, and one
  of 100 s at 0.5°.

Every cell runs in the direct loop (:func:`.envelope.run_cell`) in a process pool; each
finished cell is appended to a CSV at once (the cache): a re-run skips the cells already in
it, so an interrupted run resumes and a changed design only runs its new cells.
"""

from __future__ import annotations

import csv
import math
import multiprocessing as mp
from collections.abc import Callable, Iterable
from dataclasses import asdict, fields, replace
from pathlib import Path
from typing import Any

from axir.models.radar.conventions import BIN_S
from axir.models.target_generator import TargetGenerator

from .envelope import (
    Cell,
    clutter_loss_db,
    detectable,
    detection_snr_db,
    required_snr_db,
    run_cell,
)

RANGES_KM = (2.0, 5.0, 10.0, 20.0, 30.0, 42.0, 60.0)
N_SPEEDS = 29
ANCHOR = Cell(range_m=10_000.0, speed=-53.15, el_deg=5.0, rcs=10.0)
ELEVATIONS = (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 40.0, 60.0, 80.0)
RCS_VALUES = (0.1, 0.3, 1.0, 3.0, 10.0)
RCS_RANGE = 30_000.0
MANEUVERS = (0.0, 1.0, 3.0, 5.0, 7.0)
CLUTTER_ELEVATIONS = (0.5, 1.0, 2.0, 5.0, 10.0)
SLOW_SPEEDS = (-9.5, -7.5, -6.5, -5.5, 5.5, 6.5, 7.5, 9.5)  # [m/s] beside the ±5 m/s notch
LOWPLANE_EL = 1.0  # [deg] the low-elevation plane: the beams see the ground in their main lobe
LOWPLANE_RANGES_KM = (5.0, 10.0, 20.0, 30.0, 42.0)
MIN_PASS_RANGE = 500.0  # [m] closing cells must stay beyond this range during the run
ACQ_PRI_BINS = 200  # the manager's default acquisition PRI in bins (models/manager/params.py)

#: summary keys written per cell (besides the cell's fields and the design labels)
METRICS = ("lock_time", "first_confirmed_time", "held_fraction", "drops",
           "false_confirmations", "first_false_confirmation_time", "time_false_confirmed_s",
           "rms_range_error_m", "rms_angle_error_rad", "tentatives", "final_mode", "steps")
#: the detectability columns: judged from the cell alone, re-judged whenever rows are read
JUDGED = ("detectable", "snr_filtered_db", "clutter_loss_db")
COLUMNS = ("design", *(f.name for f in fields(Cell)), *JUDGED, *METRICS, "cpu_s")


def blind_speed() -> float:
    """Blind-speed interval λ·PRF/2 [m/s] of the acquisition PRI."""
    lam = TargetGenerator.defaults()["wavelength"]
    return lam / (2.0 * ACQ_PRI_BINS * BIN_S)


def plane_speeds() -> list[float]:
    """Radial speeds [m/s] of the range × speed plane (module docstring)."""
    even = [-1000.0 + 2000.0 * i / (N_SPEEDS - 1) for i in range(N_SPEEDS)]
    vb = blind_speed()
    near = [2.0 * vb + 4.0, -(5.0 * vb + 4.0)]  # ≈ 250 Hz beside the clutter line
    return sorted(round(v, 2) for v in even + near)


def design(quick: bool = False, seeds: int | None = None) -> list[tuple[str, Cell]]:
    """The cells of the benchmark as (design label, cell); ``quick``: a 3-cell subset with
    short runs (the test's); ``seeds`` overrides the number of seeds of every part."""
    if quick:
        return [
            ("quick", replace(ANCHOR, duration=1.5)),
            ("quick", replace(ANCHOR, range_m=60_000.0, rcs=0.1, duration=0.6)),
            ("quick", Cell(range_m=20_000.0, speed=0.0, el_deg=0.5, rcs=0.0, duration=1.0)),
        ]
    s2 = range(1, 1 + (seeds or 2))
    s3 = range(1, 1 + (seeds or 3))
    out: list[tuple[str, Cell]] = []
    for r in RANGES_KM:
        for v in plane_speeds():
            c = replace(ANCHOR, range_m=1000.0 * r, speed=v)
            if c.range_m + min(v, 0.0) * c.duration < MIN_PASS_RANGE:
                continue
            out += [("plane", replace(c, seed=s)) for s in s2]
    for s in s3:
        out += [("elevation", replace(ANCHOR, el_deg=e, seed=s)) for e in ELEVATIONS]
        out += [("rcs", replace(ANCHOR, range_m=RCS_RANGE, rcs=x, seed=s)) for x in RCS_VALUES]
        out += [("maneuver", replace(ANCHOR, g=g, tangential=250.0, maneuver_onset=1.0, seed=s))
                for g in MANEUVERS]
        out += [("slow", replace(ANCHOR, speed=v, seed=s)) for v in SLOW_SPEEDS]
    for r in LOWPLANE_RANGES_KM:  # main-beam clutter (docs/clutter.md), one seed unless asked
        for v in plane_speeds()[::2]:
            c = replace(ANCHOR, range_m=1000.0 * r, speed=v, el_deg=LOWPLANE_EL)
            if c.range_m + min(v, 0.0) * c.duration < MIN_PASS_RANGE:
                continue
            out += [("lowplane", replace(c, seed=s)) for s in range(1, 1 + (seeds or 1))]
    for s in s2:
        out += [("clutter", Cell(range_m=20_000.0, speed=0.0, el_deg=e, rcs=0.0, seed=s,
                                 duration=10.0)) for e in CLUTTER_ELEVATIONS]
    out.append(("clutter", Cell(range_m=20_000.0, speed=0.0, el_deg=0.5, rcs=0.0, seed=1,
                                duration=100.0)))
    return out


def _row_key(design_label: str, cell: Cell) -> tuple:
    return (design_label, *(str(v) for v in asdict(cell).values()))


def _csv_key(row: dict[str, str]) -> tuple:
    return (row["design"], *(row[f.name] for f in fields(Cell)))


def _job(item: tuple[str, Cell]) -> dict[str, Any]:
    import time

    label, cell = item
    c0 = time.process_time()
    s = run_cell(cell)
    row: dict[str, Any] = {"design": label, **asdict(cell), **judge(cell)}
    for k in METRICS:
        v = s.get(k)
        row[k] = "" if v is None else v
    row["cpu_s"] = round(time.process_time() - c0, 2)
    return row


def judge(cell: Cell) -> dict[str, str]:
    """The cell's detectability columns (:data:`JUDGED`, as CSV text): the criterion of
    :mod:`.envelope` (filtered SNR less the clutter loss ≥ Albersheim's SNR)."""
    snr = detection_snr_db(cell)
    return {"detectable": str(detectable(cell)),
            "snr_filtered_db": f"{snr:.2f}" if math.isfinite(snr) else "",
            "clutter_loss_db": f"{clutter_loss_db(cell):.2f}"}


def _cell_of(row: dict[str, str]) -> Cell:
    kw: dict[str, Any] = {}
    for f in fields(Cell):
        v = row[f.name]
        kw[f.name] = (v == "True") if f.type in ("bool", bool) else (
            int(v) if f.type in ("int", int) else float(v))
    return Cell(**kw)


def read_rows(path: Path) -> list[dict[str, str]]:
    """The cached rows of a results CSV (empty when absent), their detectability columns
    re-judged from the cell with the current criterion (a CSV written under an older
    criterion, or without a column, reads the same as a fresh one)."""
    if not Path(path).is_file():
        return []
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r.update(judge(_cell_of(r)))
    return rows


def _upgrade(csv_path: Path) -> None:
    """Rewrite a cache whose header is not :data:`COLUMNS` (an older layout) in the current
    layout, so rows appended to it stay aligned with its header."""
    with open(csv_path, newline="") as f:
        header = next(csv.reader(f), None)
    if header is None or tuple(header) == COLUMNS:
        return
    rows = read_rows(csv_path)
    tmp = csv_path.with_suffix(csv_path.suffix + ".tmp")
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, restval="", extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    tmp.replace(csv_path)


def run_design(cells: Iterable[tuple[str, Cell]], csv_path: Path, workers: int = 2,
               progress: Callable[[dict[str, Any], int, int], None] | None = None
               ) -> list[dict[str, str]]:
    """Run the cells not yet in ``csv_path`` on ``workers`` processes (1: in this process),
    appending each finished row; returns the rows of the design (cached and new)."""
    cells = list(cells)
    csv_path = Path(csv_path)
    done = {_csv_key(r) for r in read_rows(csv_path)}
    todo = [c for c in cells if _row_key(*c) not in done]
    # seed 1 of every part first (an interrupted run covers the whole design), inside a seed
    # the longest cells first (better packing on the pool)
    todo.sort(key=lambda c: (c[1].seed, -c[1].duration))
    new = not csv_path.is_file()
    if not new:
        _upgrade(csv_path)
    csv_path.parent.mkdir(parents=True, exist_ok=True)
    with open(csv_path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        if new:
            w.writeheader()
        results: Iterable[dict[str, Any]]
        if workers <= 1:
            results = map(_job, todo)
            pool = None
        else:
            pool = mp.get_context("spawn").Pool(workers)
            results = pool.imap_unordered(_job, todo)
        try:
            for i, row in enumerate(results, 1):
                w.writerow(row)
                f.flush()
                if progress is not None:
                    progress(row, i, len(todo))
        finally:
            if pool is not None:
                pool.terminate()
                pool.join()
    wanted = {_row_key(*c) for c in cells}
    return [r for r in read_rows(csv_path) if _csv_key(r) in wanted]


__all__ = [
    "ANCHOR",
    "COLUMNS",
    "JUDGED",
    "METRICS",
    "blind_speed",
    "design",
    "judge",
    "plane_speeds",
    "read_rows",
    "required_snr_db",
    "run_design",
]
