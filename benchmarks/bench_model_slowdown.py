"""Why the same models run slower inside the FMU loop than in the direct loop (issue 14).

Run: ``python benchmarks/bench_model_slowdown.py [--duration 1] [--repeat 2] [--fmu-dir DIR]``.

``bench_loop.py``'s instrumented pass shows ``model.step`` ≈ 15 % slower inside the four FMUs
than in :class:`axir.models.loop.DirectLoop` (same models, same parameters). Each experiment
below changes ONE thing of the direct loop towards the FMU loop and prints the CPU time of
``model.step`` (summed over the four units, µs per PRI; best of ``--repeat``), the two
variants alternating in one process, plus their ratio:

``copies``     the units' classes from the four FMUs' bundled copies of ``models/`` (one
               copy per unit, as inside the FMU loop) vs the installed package;
``instances``  the FMU slaves' own model instances (built inside the FMUs at initialization)
               vs fresh ones;
``inputs``     inputs made as the FMU adapter makes them (fresh Python floats from ``struct``,
               fresh array copies) vs the previous unit's output objects;
``reentry``    ``model.step`` called Python → ctypes → C → Python (a ctypes callback called
               through its function pointer, as the shim calls the fast step) vs directly;
``pollute``    before each unit's step, ``ndarray.sum`` over N KiB (data the model does not
               use: what the code between two model steps does to the caches) vs nothing.

A ratio near 1 rules the difference out. Nothing is asserted: numbers only. The FMUs are
built into a temporary directory unless ``--fmu-dir`` is given.
"""

from __future__ import annotations

import argparse
import ctypes
import gc
import struct
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from bench_loop import _fmus, _scenario, direct_params

from axir.models.loop import DirectLoop
from axir.models.system import GAUSS_SEIDEL_ORDER
from axir.orchestrator.master import Master
from axir.orchestrator.run import seeded_parameters

Wrap = Callable[[Callable[..., Any], str], Callable[..., Any]]
_F = ctypes.PYFUNCTYPE(ctypes.c_int)


def _models_in_fmus(fmu_dir: Path) -> tuple[Master, dict[str, Any]]:
    """An initialized :class:`Master` of the closed loop (caller closes it) and its slaves'
    model instances by unit (pythonfmu runs the slaves in this interpreter)."""
    sc = _scenario(1000.0)
    system = sc.system(fmu_dir)
    master = Master(system, algorithm=sc.algorithm, order=sc.order, step=sc.step,
                    step_from=sc.step_from, initial_step=sc.initial_step)
    master.load()
    master.initialize(0.0, sc.duration,  # seeds as in axir run
                      seeded_parameters(system, master.instances, sc.seed))
    models = {obj.instance_name: obj.model for obj in gc.get_objects()
              if any(c.__name__ == "AxirSlave" for c in type(obj).__mro__[1:])
              and getattr(obj, "model", None) is not None
              and obj.instance_name in master.instances}
    return master, models


def _timed_run(loop: DirectLoop, duration: float, wrap: Wrap | None = None) -> float:
    """CPU µs per PRI of the four ``model.step`` calls of ``loop`` over ``duration`` [s];
    ``wrap(step, unit)`` may put something around each step (outside the timer)."""
    pc = time.process_time_ns
    acc = [0]
    for name in GAUSS_SEIDEL_ORDER:
        unit = loop.units[name]
        orig = unit.step

        def timed(h: float, inputs: Any, orig: Callable[..., Any] = orig) -> Any:
            t0 = pc()
            out = orig(h, inputs)
            acc[0] += pc() - t0
            return out

        unit.step = wrap(timed, name) if wrap is not None else timed
    loop.run(duration)
    return acc[0] / 1e3 / loop.steps


def _fresh_inputs(step: Callable[..., Any], _: str) -> Callable[..., Any]:
    rt = struct.Struct("<d")

    def fresh(h: float, inputs: Any) -> Any:
        inputs = {k: (v.copy() if isinstance(v, np.ndarray)
                      else rt.unpack(rt.pack(v))[0] if type(v) is float else v)
                  for k, v in inputs.items()}
        return step(h, inputs)
    return fresh


def _through_c(step: Callable[..., Any], _: str) -> Callable[..., Any]:
    box: dict[str, Any] = {}

    def inner() -> int:
        box["out"] = step(*box["args"])
        return 0

    cb = _F(inner)
    call = _F(ctypes.cast(cb, ctypes.c_void_p).value)

    def via_c(h: float, inputs: Any, cb: Any = cb) -> Any:
        box["args"] = (h, inputs)
        call()
        return box["out"]
    return via_c


def _polluting(kib: int) -> Wrap:
    junk = np.ones(kib * 128)  # 8 bytes per float64

    def wrap(step: Callable[..., Any], _: str) -> Callable[..., Any]:
        touch = junk.sum

        def polluted(h: float, inputs: Any) -> Any:
            touch()
            return step(h, inputs)
        return polluted
    return wrap


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=1.0, help="simulated seconds (1)")
    ap.add_argument("--repeat", type=int, default=2, help="alternating passes (2)")
    ap.add_argument("--fmu-dir", type=Path, default=None, help="use these FMUs")
    ap.add_argument("--kib", type=int, nargs="+", default=[256, 1024, 4096],
                    help="pollute: KiB touched before each step (256 1024 4096)")
    a = ap.parse_args(argv)
    sc = _scenario(a.duration)
    params = direct_params(sc)
    with _fmus(a.fmu_dir) as fmu_dir:
        master, fmu_models = _models_in_fmus(fmu_dir)
        masters = [master]
        try:
            classes = {n: type(m) for n, m in fmu_models.items()}

            def bundled() -> DirectLoop:
                return DirectLoop(
                    gen=classes["TargetGenerator"](**params["TargetGenerator"]),
                    trk=classes["Tracker"](**params["Tracker"]),
                    ped=classes["Pedestal"](**params["Pedestal"]),
                    mgr=classes["RadarManager"](**params["RadarManager"]))

            def fresh() -> DirectLoop:
                return DirectLoop.from_params(params)

            def fmu_instances() -> DirectLoop:  # used once per pass: the next pass' are new
                m, models = _models_in_fmus(fmu_dir)
                masters.append(m)
                return DirectLoop(gen=models["TargetGenerator"], trk=models["Tracker"],
                                  ped=models["Pedestal"], mgr=models["RadarManager"])

            experiments: list[tuple[str, Callable[[], float], Callable[[], float]]] = [
                ("copies", lambda: _timed_run(fresh(), a.duration),
                 lambda: _timed_run(bundled(), a.duration)),
                ("instances", lambda: _timed_run(fresh(), a.duration),
                 lambda: _timed_run(fmu_instances(), a.duration)),
                ("inputs", lambda: _timed_run(fresh(), a.duration),
                 lambda: _timed_run(fresh(), a.duration, _fresh_inputs)),
                ("reentry", lambda: _timed_run(fresh(), a.duration),
                 lambda: _timed_run(fresh(), a.duration, _through_c)),
            ]
            experiments += [
                (f"pollute {k} KiB", lambda: _timed_run(fresh(), a.duration),
                 lambda k=k: _timed_run(fresh(), a.duration, _polluting(k)))
                for k in a.kib]
            print(f"model.step of the four units in the direct loop, CPU µs per PRI, "
                  f"{a.duration:g} s simulated, best of {a.repeat} alternating passes")
            for name, base, variant in experiments:
                b, v = [], []
                for _ in range(a.repeat):
                    b.append(base())
                    v.append(variant())
                print(f"  {name:<17} as in the direct loop {min(b):6.1f}   changed {min(v):6.1f}"
                      f"   ratio {min(v) / min(b):.3f}")
        finally:
            for m in masters:
                m.close()


if __name__ == "__main__":
    main()
