"""Per-call cost of the C shim (fmus/shim/axir_fmi2_shim.c): Pedestal.fmu with and without it.

Run: ``python benchmarks/bench_shim.py [--calls 200000] [--steps 5000] [--repeat 5]``.

Both FMUs are built into a temporary folder (``shim=True`` / ``shim=False``) and loaded in
this process through fmpy's ctypes functions (no fmpy wrapper in the timed loop):

- ``fmi2GetRealStatus(fmi2LastSuccessfulTime)``: answered by pythonfmu in C (no Python), so
  the difference is the shim's forwarding (one indirect call, a flag reset, a status check)
  plus nothing else; ctypes' own cost is in both columns;
- a Pedestal step as the master does it: ``fmi2SetReal`` (3 inputs), ``fmi2DoStep``,
  ``fmi2GetReal`` (15 outputs): 3 forwarded calls, dominated by the Python slave.

Passes alternate plain/shim ``--repeat`` times; the best of each is printed. Numbers only.
"""

from __future__ import annotations

import argparse
import ctypes
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
    ap.add_argument("--steps", type=int, default=5000, help="Pedestal steps per pass")
    ap.add_argument("--repeat", type=int, default=5, help="alternating passes of each")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        fmus = {"plain": build_fmu("Pedestal", Path(tmp) / "plain", shim=False),
                "shim": build_fmu("Pedestal", Path(tmp) / "shim", shim=True)}
        insts = {k: _open(p, k) for k, p in fmus.items()}
        try:
            best: dict[tuple[str, str], float] = {}
            for r in range(a.repeat):
                for k, inst in insts.items():
                    for what, t in (("status", _status_loop(inst, a.calls)),
                                    ("step", _step_loop(inst, a.steps, r * a.steps))):
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
    print(f"  set 3 + doStep + get 15  plain {us['plain', 'step']:6.1f} µs   shim "
          f"{us['shim', 'step']:6.1f} µs   difference "
          f"{us['shim', 'step'] - us['plain', 'step']:+5.2f} µs/step (3 forwarded calls)")


if __name__ == "__main__":
    main()
