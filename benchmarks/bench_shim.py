"""Per-call cost of the C shim (fmus/shim/axir_fmi2_shim.c): Pedestal.fmu with and without it.

Run: ``python benchmarks/bench_shim.py [--calls 200000] [--steps 5000] [--repeat 5]``.

Both FMUs are built into a temporary folder (``shim=True`` / ``shim=False``) and loaded in
this process through fmpy's ctypes functions (no fmpy wrapper in the timed loop):

- ``fmi2GetRealStatus(fmi2LastSuccessfulTime)``: answered by pythonfmu in C (no Python), so
  the difference is the shim's forwarding (one indirect call, a flag reset, a status check)
  plus nothing else; ctypes' own cost is in both columns (after the first pass's fast
  doSteps the shim answers it itself, also in C);
- the same call in a C loop (a helper compiled with gcc into a temporary library calls the
  function pointer ``--c-calls`` times, timed with ``clock_gettime``): no ctypes cost, so
  the difference is the shim alone;
- ``fmi2GetReal`` of the 15 Real outputs and ``fmi2SetReal`` of the 3 inputs alone, through
  the master's pre-bound calls (``FmuInstance.bind``): with the shim they are answered from
  the value block the slave shares (no Python), without it they cross pythonfmu's bridge
  into the slave's Python get/set;
- a Pedestal step as the master does it: ``fmi2SetReal`` (3 inputs), ``fmi2DoStep``,
  ``fmi2GetReal`` (15 outputs), dominated by the Python slave's doStep (with the shim: its
  fast step, without pythonfmu's doStep bridge).

Passes alternate plain/shim ``--repeat`` times; the best of each is printed. Numbers only.
"""

from __future__ import annotations

import argparse
import ctypes
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from axir.fmus.build import build_fmu
from axir.orchestrator.fmi import FmuInstance


def _open(fmu: Path, name: str) -> FmuInstance:
    inst = FmuInstance(fmu, name)
    inst.setup(0.0)
    inst.enter_init()
    inst.exit_init()
    return inst


def _status_loop(inst: FmuInstance, n: int) -> float:
    f = inst._fmu.dll.fmi2GetRealStatus
    comp = inst._component
    value = ctypes.c_double()
    ref = ctypes.byref(value)
    t0 = time.perf_counter()
    for _ in range(n):
        f(comp, 2, ref)
    return (time.perf_counter() - t0) / n


C_LOOP = r"""
#include <time.h>
typedef int (*status_fn)(void *, int, double *);
double loop_ns(status_fn f, void *c, long n) {
    struct timespec a, b;
    double v;
    long i;
    clock_gettime(CLOCK_MONOTONIC, &a);
    for (i = 0; i < n; i++) f(c, 2, &v);
    clock_gettime(CLOCK_MONOTONIC, &b);
    return ((b.tv_sec - a.tv_sec) * 1e9 + (b.tv_nsec - a.tv_nsec)) / n;
}
"""


def _c_loop(tmp: Path) -> Any:
    """``loop_ns(function pointer, component, n)`` → ns per call, or None without gcc."""
    cc = shutil.which("gcc")
    if cc is None:
        return None
    (tmp / "loop.c").write_text(C_LOOP)
    subprocess.run([cc, "-O2", "-fPIC", "-shared", "-o", str(tmp / "loop.so"),
                    str(tmp / "loop.c")], check=True)
    lib = ctypes.CDLL(str(tmp / "loop.so"))
    lib.loop_ns.restype = ctypes.c_double
    lib.loop_ns.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_long]
    return lib.loop_ns


def _value_loops(inst: FmuInstance, n: int) -> tuple[float, float]:
    """Seconds per bound fmi2GetReal of the 15 Real outputs and per fmi2SetReal of the 3
    inputs."""
    ins = inst.port(["cmd.az", "cmd.el", "bandwidth"])
    outs = inst.port([v.name for v in inst.md.modelVariables
                      if v.causality == "output" and v.type == "Real"])
    ins.buf[:] = [0.5, -0.2, 2.0]
    get = inst.bind("fmi2GetReal", outs.vr, len(outs.vr), outs.buf)
    set_ = inst.bind("fmi2SetReal", ins.vr, len(ins.vr), ins.buf)
    t0 = time.perf_counter()
    for _ in range(n):
        get()
    t1 = time.perf_counter()
    for _ in range(n):
        set_()
    return (t1 - t0) / n, (time.perf_counter() - t1) / n


def _step_loop(inst: FmuInstance, n: int, k0: int) -> float:
    ins = inst.port(["cmd.az", "cmd.el", "bandwidth"])
    outs = inst.port([v.name for v in inst.md.modelVariables
                      if v.causality == "output" and v.type == "Real"])
    h = 1e-3
    t0 = time.perf_counter()
    for k in range(k0, k0 + n):
        ins.write([0.5, -0.2, 2.0])
        inst.do_step(k * h, h)
        outs.read()
    return (time.perf_counter() - t0) / n


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=200_000, help="fmi2GetRealStatus calls")
    ap.add_argument("--c-calls", type=int, default=2_000_000,
                    help="fmi2GetRealStatus calls in the C loop")
    ap.add_argument("--steps", type=int, default=5000, help="Pedestal steps per pass")
    ap.add_argument("--repeat", type=int, default=5, help="alternating passes of each")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        fmus = {"plain": build_fmu("Pedestal", Path(tmp) / "plain", shim=False),
                "shim": build_fmu("Pedestal", Path(tmp) / "shim", shim=True)}
        insts = {k: _open(p, k) for k, p in fmus.items()}
        loop_ns = _c_loop(Path(tmp))
        try:
            best: dict[tuple[str, str], float] = {}
            for r in range(a.repeat):
                for k, inst in insts.items():
                    get_t, set_t = _value_loops(inst, a.calls // 4)
                    times = [("status", _status_loop(inst, a.calls)),
                             ("get15", get_t), ("set3", set_t),
                             ("step", _step_loop(inst, a.steps, r * a.steps))]
                    if loop_ns is not None:
                        fptr = ctypes.cast(inst._fmu.dll.fmi2GetRealStatus, ctypes.c_void_p)
                        times.append(("c", 1e-9 * loop_ns(fptr.value, inst._component,
                                                          a.c_calls)))
                    for what, t in times:
                        key = (k, what)
                        best[key] = min(best.get(key, float("inf")), t)
        finally:
            for inst in insts.values():
                inst.close()
    us: dict[Any, float] = {k: 1e6 * v for k, v in best.items()}
    print(f"Pedestal.fmu, best of {a.repeat} alternating passes (ctypes calls, no fmpy wrapper)")
    print(f"  fmi2GetRealStatus  plain {us['plain', 'status']:7.3f} µs   shim "
          f"{us['shim', 'status']:7.3f} µs   shim overhead "
          f"{1e3 * (us['shim', 'status'] - us['plain', 'status']):+6.0f} ns/call")
    if ("shim", "c") in us:
        print(f"  fmi2GetRealStatus, C loop  plain {1e3 * us['plain', 'c']:6.1f} ns   shim "
              f"{1e3 * us['shim', 'c']:6.1f} ns   shim overhead "
              f"{1e3 * (us['shim', 'c'] - us['plain', 'c']):+5.1f} ns/call")
    for what, label in (("get15", "fmi2GetReal 15 outputs"), ("set3", "fmi2SetReal 3 inputs")):
        print(f"  {label:24s} plain {us['plain', what]:6.2f} µs   shim {us['shim', what]:6.2f} µs"
              f"   ratio {us['plain', what] / us['shim', what]:5.1f}x (shim: shared values, "
              "no Python)")
    print(f"  set 3 + doStep + get 15  plain {us['plain', 'step']:6.1f} µs   shim "
          f"{us['shim', 'step']:6.1f} µs   difference "
          f"{us['shim', 'step'] - us['plain', 'step']:+5.2f} µs/step")


if __name__ == "__main__":
    main()
