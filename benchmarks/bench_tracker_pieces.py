"""Isolated CPU cost of the pieces of one confirmed-mode Tracker PRI [ns], beside the replayed step.

Run::

    python benchmarks/bench_tracker_pieces.py [--at 5000] [--number 20000]

The built-in ``closed-loop`` scenario runs through the direct loop to record the Tracker's
``(dt, inputs)`` (as ``bench_units.py``); a Tracker is stepped to step ``--at`` (confirmed mode,
α-β in the mixed phase there), then each piece of ``BeamTracker.step`` — the numpy SUM, the
gate-cell reads, the helpers, the α-β update of the three axes, the 3-D NIS chain, the
geometry, the 38-entry output mapping — is timed alone with realistic arguments (best of 7,
``time.process_time``), and the whole replayed step's mean (``bench_units.replay``) printed
for scale. Isolated figures are lower bounds: inside the step the same code runs colder
(docs/performance.md, "Issue 14 (session 7)"). Nothing is asserted: numbers only
(issue 14, Tracker round 4).
"""

from __future__ import annotations

import argparse
import copy
import math
import time
import timeit
from typing import Any

import numpy as np
from bench_loop import _scenario, direct_params
from bench_units import record, replay, units_of

from axir.models.filters.alphabeta import update_axes
from axir.models.filters.gains import innovation_factor
from axir.models.loop import DirectLoop
from axir.models.radar.geometry import cart_to_sph_and_diff, sph_to_cart_and_diff_cs
from axir.models.tracker.cells import (
    _cartesian_variances_cs,
    _early_late_corrected,
    background_sum,
)
from axir.models.tracker.maneuver import nis_cs
from axir.models.tracker.outputs import outputs_flat

#: (label, statement, setup) of each piece; names from the namespace built in main()
PIECES: tuple[tuple[str, str, str], ...] = (
    ("SUM = np.add.reduce(beams, 0)", "ar(beams, 0)", "pass"),
    ("gate cells: SUM column + strongest cell's 4 beams",
     "cl = sums[:, 1].tolist(); beams[:, 6, 1].tolist()", "pass"),
    ("background_sum (noise level)", "background_sum(cl)", "cl = sums[:, 1].tolist()"),
    ("_early_late_corrected", "_early_late_corrected(s6, s7, s8, 0.5)", "pass"),
    ("sph_to_cart_and_diff_cs + its 4 trig",
     "sph_to_cart_and_diff_cs(rho, cos(az), sin(az), cos(el), sin(el), 1.0, 1e-3, 1e-3)",
     "pass"),
    ("4 trig of the measured direction", "cos(az), sin(az), cos(el), sin(el)", "pass"),
    ("_cartesian_variances_cs", "_cartesian_variances_cs(rho, 0.5, 0.8, 0.99, 0.1, 7.5, 1e-3)",
     "pass"),
    ("update_axes (X, Y, Z α-β, manager's steady gains)",
     "update_axes(ax, (px, py, pz), T, (50.0, 900.0, 900.0), steady=(a_ss, b_ss))",
     "ax = copy.deepcopy(core.axes)"),
    ("3-D NIS: innovation_factor + nis_cs + detector innovation/decide",
     "det.innovation(nis_cs((1.0, 2.0, 3.0), 0.5, 0.8, 0.99, 0.1, rho, 7.5, 1e-3, "
     "innovation_factor(fx.alpha, fx.beta, fx.evolutive))); det.decide()",
     "det = copy.deepcopy(core.detector)"),
    ("_limit_range_rate", "c._limit_range_rate()", "c = copy.deepcopy(core)"),
    ("cart_to_sph_and_diff", "cart_to_sph_and_diff(px, py, pz, vx, vy, vz)", "pass"),
    ("outputs_flat (38 entries)",
     "outputs_flat(sums, *flt[:17], False, 1.0, 2.0, 3, True, False, 1.0, 2.0, 3.0, "
     "(0.0, 0.0, 0.0, False), *flt[:7])", "pass"),
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--at", type=int, default=5000, help="step of the recorded run (≥ 100)")
    ap.add_argument("--number", type=int, default=20000, help="calls per timed repeat")
    a = ap.parse_args()
    if a.at < 100 or a.number < 1:
        ap.error("--at must be ≥ 100 and --number ≥ 1")
    duration = (a.at + 200) * 1.2e-4  # PRIs are ≈ 110 µs: a margin past --at
    params = direct_params(_scenario(duration))
    rec = record(params, duration)
    seq = rec["Tracker"]
    if a.at >= len(seq):
        ap.error(f"--at {a.at}: the run has {len(seq)} steps")
    trk = units_of(DirectLoop, params)["Tracker"]
    for h, inputs in seq[:a.at]:
        trk.step(h, inputs)
    core = trk.core
    T, inputs = seq[a.at]
    beams = np.asarray(inputs["beam"], dtype=float)
    sums = np.add.reduce(beams, 0)
    s6, s7, s8 = sums[5:8, 1].tolist()
    fx, fy, fz = core.axes
    ns: dict[str, Any] = {
        "copy": copy, "update_axes": update_axes, "innovation_factor": innovation_factor,
        "cart_to_sph_and_diff": cart_to_sph_and_diff, "nis_cs": nis_cs,
        "sph_to_cart_and_diff_cs": sph_to_cart_and_diff_cs, "outputs_flat": outputs_flat,
        "_cartesian_variances_cs": _cartesian_variances_cs, "background_sum": background_sum,
        "_early_late_corrected": _early_late_corrected, "ar": np.add.reduce, "beams": beams,
        "sums": sums, "s6": s6, "s7": s7,
        "s8": s8, "core": core, "fx": fx, "T": T, "cos": math.cos, "sin": math.sin,
        "az": float(inputs["ped.az"]), "el": float(inputs["ped.el"]), "rho": 3.0e4,
        "px": fx.pos, "py": fy.pos, "pz": fz.pos, "vx": fx.vel, "vy": fy.vel, "vz": fz.vel,
        "a_ss": float(inputs.get("alpha", 0.0)), "b_ss": float(inputs.get("beta", 0.0)),
        "flt": tuple(float(i) for i in range(17)),
    }
    step_ns = replay({"now": DirectLoop}, params, {"Tracker": seq}, 3, 500,
                     ("Tracker",))[("Tracker", "now")] * 1e3
    print(f"Tracker step replayed ({len(seq)} steps, mean, best of 3): {step_ns:7.0f} ns CPU")
    print(f"pieces at step {a.at} (mode {inputs.get('mode')}, n = {fx.n}), best of 7 × "
          f"{a.number}, CPU ns per call, and as a fraction of the step:")
    total = 0.0
    for label, stmt, setup in PIECES:
        t = min(timeit.repeat(stmt, setup, globals=ns, number=a.number, repeat=7,
                              timer=time.process_time)) / a.number * 1e9
        total += t
        print(f"  {t:7.0f}  {t / step_ns:5.1%}  {label}")
    print(f"  {total:7.0f}  {total / step_ns:5.1%}  sum of the pieces (the rest: the step's "
          "own bytecode)")


if __name__ == "__main__":
    main()
