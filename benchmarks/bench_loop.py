"""FMU loop vs direct loop: µs per PRI of the closed tracking loop, with a per-unit breakdown.

Run: ``python benchmarks/bench_loop.py [--duration 2] [--repeat 3] [--fmu-dir DIR]``.

The built-in ``closed-loop`` scenario (its parameters, seeds derived as ``axir run`` does,
Gauss-Seidel, variable step = the PRI the RadarManager commands), shortened to ``--duration``
seconds, runs through

(a) the four FMUs (built into a temporary directory with :func:`axir.fmus.build.build_all`,
    unless ``--fmu-dir`` is given) and our master (:class:`axir.orchestrator.master.Master`,
    no observers), and
(b) :class:`axir.models.loop.DirectLoop` with the same parameters (no FMI).

Timed passes alternate (a) and (b) ``--repeat`` times; the best of each is reported (the
machine may be shared); the CPU time of this process is printed too. One more instrumented
pass of each gives the per-unit breakdown:
model.step in the direct loop, model.step inside the FMU (pythonfmu runs the slave in this
interpreter, so the slave objects are reachable), fmi2DoStep as seen by the master, and the
fmi2Get*/fmi2Set* calls per unit. The timers add ~0.1 µs per wrapped call, and with them the
master steps through its generic path (``Master._advance``: one Python frame per FMI call,
≈ 1.3 µs per PRI more than the inlined path of the timed passes, session 7). Nothing is
asserted: numbers only.

``--null-models``: only the cost of the FMI path — the master, the 16 FMI calls, the C shim
and the slaves' gather/scatter — per PRI, robust to the load of a shared machine: the FMU
loop runs 0.05 s normally, then every ``model.step`` inside the FMUs is replaced by a function
returning that model's last output mapping (no model work, same values every step) and
``--repeat`` passes of 0.3 s are timed (best and all printed).

``--master-only``: the master's own work per PRI (session 6): the FMUs are loaded and
initialized, then every bound FMI call of the master's loop is replaced by a no-op returning
fmi2OK (a C function when the master steps in C, orchestrator/stepper.py; else a Python one)
— except ``fmi2GetReal`` of the step-size source, which stays real (the step size is read from
it) — and ``--repeat`` passes of 2 s are timed (CPU, best printed).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import gc
import tempfile
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from dataclasses import replace
from pathlib import Path
from typing import Any

from axir.models.loop import DirectLoop
from axir.models.system import GAUSS_SEIDEL_ORDER, unit_seed
from axir.orchestrator import stepper
from axir.orchestrator.master import Master
from axir.orchestrator.run import seeded_parameters
from axir.orchestrator.scenario import load_scenario

Acc = dict[tuple[str, str], list[float]]  # (unit, what) -> [seconds, calls]


def _timed(fn: Callable[..., Any], acc: Acc, key: tuple[str, str]) -> Callable[..., Any]:
    pc = time.perf_counter
    cell = acc[key]

    def wrapper(*args: Any) -> Any:
        t0 = pc()
        try:
            return fn(*args)
        finally:
            cell[0] += pc() - t0
            cell[1] += 1

    return wrapper


def _scenario(duration: float):
    return replace(load_scenario("closed-loop"), duration=duration)


def direct_params(sc) -> dict[str, dict[str, Any]]:
    """The scenario's unit parameters for :meth:`DirectLoop.from_params`, with the per-unit
    seeds ``axir run`` gives the FMUs that have a ``seed`` parameter."""
    models = DirectLoop.from_params().units
    out = {}
    for name, spec in sc.units.items():
        p = dict(spec.get("parameters", {}))
        if "seed" not in p and any(q.name == "seed" for q in type(models[name]).PARAMS):
            p["seed"] = unit_seed(sc.seed, name)
        out[name] = p
    return out


def run_fmu(fmu_dir: Path, sc, acc: Acc | None = None) -> tuple[int, float, float]:
    """(steps, wall seconds, CPU seconds of this process) of the FMU loop; with ``acc``,
    instrumented."""
    system = sc.system(fmu_dir)
    with Master(system, algorithm=sc.algorithm, order=sc.order, step=sc.step,
                step_from=sc.step_from, initial_step=sc.initial_step) as master:
        master.initialize(0.0, sc.duration,  # seeds as in axir run
                          seeded_parameters(system, master.instances, sc.seed))
        if acc is not None:
            _instrument_master(master, acc)
        c0, t0 = time.process_time(), time.perf_counter()
        master.run(sc.duration)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        return master.steps, wall, cpu


def run_null_models(fmu_dir: Path, repeat: int) -> list[tuple[float, float]]:
    """(wall, CPU) µs per PRI of ``repeat`` passes of the FMU loop with null models (see the
    module doc), sorted by wall time."""
    sc = _scenario(1000.0)
    system = sc.system(fmu_dir)
    with Master(system, algorithm=sc.algorithm, order=sc.order, step=sc.step,
                step_from=sc.step_from, initial_step=sc.initial_step) as master:
        master.initialize(0.0, sc.duration)
        master.run(0.05)
        for obj in gc.get_objects():  # the pythonfmu slaves live in this interpreter
            if any(c.__name__ == "AxirSlave" for c in type(obj).__mro__[1:]) and getattr(
                    obj, "model", None) is not None and obj.instance_name in master.instances:
                out = obj.model.step(1e-4, obj._gather())
                obj.model.step = lambda h, inputs, out=out: out
        passes = []
        for _ in range(repeat):
            n0, c0, t0 = master.steps, time.process_time(), time.perf_counter()
            master.run(master.t_ns / 1e9 + 0.3)
            n = master.steps - n0
            passes.append((1e6 * (time.perf_counter() - t0) / n,
                           1e6 * (time.process_time() - c0) / n))
    return sorted(passes)


def run_master_only(fmu_dir: Path, repeat: int) -> float:
    """CPU µs per PRI of the master alone (see the module doc), best of ``repeat``."""
    from axir.orchestrator import fmi

    sc = _scenario(1000.0)
    source = sc.step_from.partition(".")[0] if sc.step_from else None
    orig = fmi.FmuInstance._raw

    def noop_raw(self: Any, function: str, args: Any) -> Any:
        raw = orig(self, function, args)
        if raw is None or (function == "fmi2GetReal" and self.name == source):
            return raw
        if stepper.available():  # C no-ops: the master keeps its C step
            noop = (stepper._stepper.NOOP_DO_STEP if function == "fmi2DoStep"
                    else stepper._stepper.NOOP_TRANSFER)
            return ctypes.PYFUNCTYPE(ctypes.c_int)(noop), raw[1]
        return (lambda *a: 0), raw[1]

    fmi.FmuInstance._raw = noop_raw
    try:
        with Master(sc.system(fmu_dir), algorithm=sc.algorithm, order=sc.order, step=sc.step,
                    step_from=sc.step_from, initial_step=sc.initial_step) as master:
            master.initialize(0.0, sc.duration)
            best = float("inf")
            for _ in range(repeat):
                n0, c0 = master.steps, time.process_time()
                master.run(master.t_ns / 1e9 + 2.0)
                best = min(best, 1e6 * (time.process_time() - c0) / (master.steps - n0))
            return best
    finally:
        fmi.FmuInstance._raw = orig


def _instrument_master(master: Master, acc: Acc) -> None:
    # the master's prepared calls (private: this benchmark belongs with the master)
    for name, writes in master._writes_into.items():
        for w in writes:
            w.write = _timed(w.write, acc, (name, "set"))
            for src, *_ in w.segments:
                if not getattr(src, "_bench_timed", False):
                    src.read = _timed(src.read, acc, (src.inst.name, "get"))
                    src._bench_timed = True
    if master._step_read is not None:
        src = master._step_read[0]
        if not getattr(src, "_bench_timed", False):
            src.read = _timed(src.read, acc, (src.inst.name, "get"))
    names = {id(inst): name for name, inst in master.instances.items()}
    master._steps = [(writes, _timed(step, acc, (names[id(inst)], "do_step")))
                     for (inst, _), (writes, step) in zip(master._sequence, master._steps,
                                                          strict=True)]
    # model.step inside each FMU: the pythonfmu slaves live in this interpreter
    for obj in gc.get_objects():
        if any(c.__name__ == "AxirSlave" for c in type(obj).__mro__[1:]) and getattr(
                obj, "model", None) is not None:
            unit = obj.instance_name
            if unit in master.instances:
                obj.model.step = _timed(obj.model.step, acc, (unit, "model.step (in FMU)"))


def run_direct(params: dict[str, dict[str, Any]], duration: float,
               acc: Acc | None = None) -> tuple[int, float, float]:
    """(steps, wall seconds, CPU seconds) of the direct loop; with ``acc``, instrumented."""
    loop = DirectLoop.from_params(params)
    if acc is not None:
        for name, model in ((n, loop.units[n]) for n in GAUSS_SEIDEL_ORDER):
            model.step = _timed(model.step, acc, (name, "model.step (direct)"))
    c0, t0 = time.process_time(), time.perf_counter()
    loop.run(duration)
    return loop.steps, time.perf_counter() - t0, time.process_time() - c0


@contextlib.contextmanager
def _fmus(fmu_dir: Path | None) -> Iterator[Path]:
    """``fmu_dir``, or the four FMUs built into a temporary directory removed afterwards."""
    if fmu_dir is not None:
        yield fmu_dir
        return
    from axir.fmus.build import build_all

    with tempfile.TemporaryDirectory(prefix="axir_bench_") as tmp:
        build_all(Path(tmp))
        yield Path(tmp)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=2.0, help="simulated seconds (2)")
    ap.add_argument("--repeat", type=int, default=3, help="timed passes of each loop (3)")
    ap.add_argument("--fmu-dir", type=Path, default=None,
                    help="use these FMUs instead of building them into a temporary directory")
    ap.add_argument("--null-models", action="store_true",
                    help="time only the FMI path: every model.step a constant (see the doc)")
    ap.add_argument("--master-only", action="store_true",
                    help="time only the master's own work: FMI calls no-ops (see the doc)")
    a = ap.parse_args(argv)
    if a.master_only:
        with _fmus(a.fmu_dir) as fmu_dir:
            us = run_master_only(fmu_dir, a.repeat)
        print(f"master alone (FMI calls no-ops), best of {a.repeat} passes of 2 s: "
              f"{us:.2f} CPU µs/PRI")
        return
    if a.null_models:
        with _fmus(a.fmu_dir) as fmu_dir:
            passes = run_null_models(fmu_dir, a.repeat)
        print(f"FMU loop with null models (FMI path only), best of {a.repeat} passes of 0.3 s: "
              f"{passes[0][0]:.1f} µs/PRI wall, {min(c for _, c in passes):.1f} CPU "
              f"(all, wall: {', '.join(f'{w:.1f}' for w, _ in passes)})")
        return
    sc = _scenario(a.duration)
    params = direct_params(sc)
    with _fmus(a.fmu_dir) as fmu_dir:
        run_fmu(fmu_dir, _scenario(0.05))  # warm-up: imports, first-call caches
        run_direct(params, 0.05)
        fmu, direct = [], []
        for _ in range(a.repeat):
            fmu.append(run_fmu(fmu_dir, sc))
            direct.append(run_direct(params, a.duration))
        f_steps, f_wall, _ = min(fmu, key=lambda x: x[1] / x[0])
        d_steps, d_wall, _ = min(direct, key=lambda x: x[1] / x[0])
        f_us, d_us = 1e6 * f_wall / f_steps, 1e6 * d_wall / d_steps
        f_cpu = min(1e6 * c / s for s, _, c in fmu)
        d_cpu = min(1e6 * c / s for s, _, c in direct)
        print(f"closed-loop, {a.duration:g} s simulated, best of {a.repeat}")
        print(f"  FMU loop   : {f_us:7.1f} µs/PRI  ({f_steps} steps, "
              f"all passes: {', '.join(f'{1e6 * w / s:.1f}' for s, w, _ in fmu)})")
        print(f"  direct loop: {d_us:7.1f} µs/PRI  ({d_steps} steps, "
              f"all passes: {', '.join(f'{1e6 * w / s:.1f}' for s, w, _ in direct)})")
        print(f"  ratio FMU/direct: {f_us / d_us:.2f}   (FMI + adapter cost: "
              f"{f_us - d_us:.1f} µs/PRI)")
        print(f"  CPU time of this process (robust to other processes' load), best: FMU "
              f"{f_cpu:.1f}, direct {d_cpu:.1f} µs/PRI, ratio {f_cpu / d_cpu:.2f}, "
              f"FMI cost {f_cpu - d_cpu:.1f} µs/PRI")

        acc: Acc = defaultdict(lambda: [0.0, 0])
        f_steps, f_wall, _ = run_fmu(fmu_dir, sc, acc)
        d_steps, d_wall, _ = run_direct(params, a.duration, acc)

    def per(unit: str, what: str, steps: int) -> tuple[float, float]:
        s, n = acc.get((unit, what), (0.0, 0))
        return 1e6 * s / steps, n / steps

    print(f"\nper unit, instrumented pass (µs per PRI; FMU loop {1e6 * f_wall / f_steps:.1f}, "
          f"direct {1e6 * d_wall / d_steps:.1f})")
    head = ("unit", "model.step direct", "model.step in FMU", "fmi2DoStep", "fmi2Get*",
            "fmi2Set*", "FMU calls/PRI", "FMU - direct")
    print("  " + " | ".join(f"{h:>17}" if i else f"{h:<15}" for i, h in enumerate(head)))
    tot = defaultdict(float)
    for unit in GAUSS_SEIDEL_ORDER:
        md, _ = per(unit, "model.step (direct)", d_steps)
        mf, _ = per(unit, "model.step (in FMU)", f_steps)
        ds, nd = per(unit, "do_step", f_steps)
        g, ng = per(unit, "get", f_steps)
        st, ns = per(unit, "set", f_steps)
        row = (md, mf, ds, g, st, nd + ng + ns, ds + g + st - md)
        for k, v in zip(head[1:], row, strict=True):
            tot[k] += v
        print(f"  {unit:<15} | " + " | ".join(f"{v:17.1f}" for v in row))
    print(f"  {'total':<15} | " + " | ".join(f"{tot[k]:17.1f}" for k in head[1:]))
    rest = 1e6 * f_wall / f_steps - (tot["fmi2DoStep"] + tot["fmi2Get*"] + tot["fmi2Set*"])
    print(f"  master (loop, gather memmove, step size, timers): {rest:.1f} µs/PRI; "
          f"adapter + pythonfmu bridge inside fmi2DoStep: "
          f"{tot['fmi2DoStep'] - tot['model.step in FMU']:.1f} µs/PRI")


if __name__ == "__main__":
    main()
