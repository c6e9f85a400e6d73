"""Start-up of the FMU loop: loading, initializing and freeing the four FMUs [s] (issue 14).

Run::

    python benchmarks/bench_startup.py [--repeat 3] [--fmu-dir DIR]
        [--before-path DIR --before-fmu-dir DIR]

Each pass is a fresh Python process (imports are per process) that loads the built-in
``closed-loop`` scenario's four FMUs with our master (``Master.__enter__``: fmpy extraction,
``fmi2Instantiate``, i.e. the import of each FMU's bundled sources), initializes them
(``Master.initialize``: the units' ``reset``, e.g. the RadarManager's threshold tables) and
frees them, timing each phase (wall and CPU time of the process; the CPU time is robust to
other processes' load). Nothing is stepped. ``--before-path`` (a directory holding an older
``axir`` package: ``axir/models``, ``axir/fmus``, ``axir/orchestrator``, put first on
``PYTHONPATH``) with ``--before-fmu-dir`` (its FMUs) alternates the two versions and prints
the ratio after/before of the total CPU time. Numbers only; nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

#: the child: times the three phases and prints them as one JSON line (no user input executed)
_CHILD = r"""
import json, sys, time
from dataclasses import replace
c0, t0 = time.process_time(), time.perf_counter()
from axir.orchestrator.master import Master
from axir.orchestrator.scenario import load_scenario
c1, t1 = time.process_time(), time.perf_counter()
sc = load_scenario("closed-loop")
system = sc.system(sys.argv[1])
m = Master(system, algorithm=sc.algorithm, order=sc.order, step=sc.step,
           step_from=sc.step_from, initial_step=sc.initial_step)
m.__enter__()
c2, t2 = time.process_time(), time.perf_counter()
m.initialize(0.0, 1.0)
c3, t3 = time.process_time(), time.perf_counter()
m.__exit__(None, None, None)
c4, t4 = time.process_time(), time.perf_counter()
print(json.dumps({"import master": [t1 - t0, c1 - c0], "load": [t2 - t1, c2 - c1],
                  "initialize": [t3 - t2, c3 - c2], "free": [t4 - t3, c4 - c3]}))
"""
PHASES = ("import master", "load", "initialize", "free")


def one_pass(fmu_dir: Path, pythonpath: str | None) -> dict[str, list[float]]:
    """The phases' (wall, CPU) seconds of one fresh process."""
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    out = subprocess.run([sys.executable, "-c", _CHILD, str(fmu_dir)], env=env, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="passes per version (best printed)")
    ap.add_argument("--fmu-dir", type=Path, default=Path("dist"), help="the FMUs (this tree)")
    ap.add_argument("--before-path", default=None, help="PYTHONPATH of the older axir package")
    ap.add_argument("--before-fmu-dir", type=Path, default=None, help="the older FMUs")
    a = ap.parse_args(argv)
    if a.repeat < 1:
        ap.error("--repeat must be >= 1")
    for d in [a.fmu_dir] + ([a.before_fmu_dir] if a.before_fmu_dir else []):
        if not d.is_dir():
            ap.error(f"no FMU directory {d}")
    versions: dict[str, tuple[Path, str | None]] = {}
    if a.before_path:
        if a.before_fmu_dir is None:
            ap.error("--before-path needs --before-fmu-dir")
        versions["before"] = (a.before_fmu_dir, a.before_path)
    versions["after" if a.before_path else "now"] = (a.fmu_dir, None)
    runs: dict[str, list[dict[str, list[float]]]] = {v: [] for v in versions}
    for _ in range(a.repeat):  # alternate the versions (shared machine)
        for v, (d, pp) in versions.items():
            runs[v].append(one_pass(d, pp))
    print(f"start-up of the four FMUs, s (fresh process per pass, best of {a.repeat}; "
          "wall / CPU)")
    totals: dict[str, float] = {}
    for v, rs in runs.items():
        cells = []
        for ph in PHASES:
            wall = min(r[ph][0] for r in rs)
            cpu = min(r[ph][1] for r in rs)
            cells.append(f"{ph} {wall:.3f} / {cpu:.3f}")
        totals[v] = min(sum(r[ph][1] for ph in PHASES[1:]) for r in rs)
        all_cpu = ", ".join(f"{sum(r[ph][1] for ph in PHASES[1:]):.3f}" for r in rs)
        print(f"  {v:6s} " + "; ".join(cells))
        print(f"         load + initialize + free, CPU: best {totals[v]:.3f} (all: {all_cpu})")
    if a.before_path:
        print(f"  ratio after/before (CPU, load + initialize + free): "
              f"{totals['after'] / totals['before']:.3f}")


if __name__ == "__main__":
    main()
