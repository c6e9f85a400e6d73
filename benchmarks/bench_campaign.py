"""Monte Carlo campaign throughput: runs per second with 1 Dask worker vs 2 workers.

Run: ``python benchmarks/bench_campaign.py [--scenario closed-loop] [--duration 0.3]
[--runs 16] [--repeat 2] [--fmu-dir DIR]``.

The same campaign (``--runs`` runs of ``--scenario`` shortened to ``--duration`` s, seeds
BASE..BASE+runs−1) runs through :func:`axir.orchestrator.campaign.run_campaign` on a
LocalCluster of 1 worker process and on one of 2 (one thread each). Each cluster is started
and warmed up first (one run per worker: the FMUs are sent, extracted and instantiated
there), then the campaign is timed ``--repeat`` times (cached instances, fmi2Reset between
runs); the best pass is reported, and the end-to-end time including the cluster start and
warm-up is printed too. The two campaigns' aggregates are compared bit for bit. Nothing is
asserted: numbers only (the machine has 2 cores and may be shared with other jobs; the
target in issue 4 is a ratio ≥ 1.7). Also printed: the mean wall time of one run measured on
its worker, and the share of the workers' time spent inside runs: when a run itself gets
slower with 2 workers, the two processes compete for the CPU (other jobs, the client and
scheduler process), not for anything in the campaign machinery.

The FMUs are built into a temporary directory unless ``--fmu-dir`` is given.
"""

from __future__ import annotations

import argparse
import logging
import os
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from axir.orchestrator.campaign import LOCAL_CLUSTER_QUIET, run_campaign
from axir.orchestrator.scenario import load_scenario


def measure(n_workers: int, args: argparse.Namespace, fmu_dir: Path):
    """(best steady-state seconds, end-to-end seconds, campaign result) with ``n_workers``."""
    from distributed import Client, LocalCluster

    sc = replace(load_scenario(args.scenario), duration=args.duration)
    t0 = time.perf_counter()
    with LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                      silence_logs=logging.ERROR, **LOCAL_CLUSTER_QUIET) as cluster, \
            Client(cluster) as client:
        run_campaign(sc, fmu_dir, n_workers, client=client, seed=10_000, progress=False)
        warm = time.perf_counter() - t0
        best = float("inf")
        res = None
        for _ in range(args.repeat):
            t1 = time.perf_counter()
            r = run_campaign(sc, fmu_dir, args.runs, client=client, seed=args.seed,
                             progress=False)
            if time.perf_counter() - t1 < best:
                best, res = time.perf_counter() - t1, r
        assert res is not None
        if res.failed:
            print(f"  {len(res.failed)} runs failed: {res.failed[0]['error']}")
    return best, warm + best, res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="closed-loop")
    ap.add_argument("--duration", type=float, default=0.3, help="simulated s per run")
    ap.add_argument("--runs", type=int, default=16)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--fmu-dir", type=Path, default=None)
    args = ap.parse_args()
    fmu_dir = args.fmu_dir
    if fmu_dir is None:
        from axir.fmus.build import build_all

        fmu_dir = Path(tempfile.mkdtemp(prefix="axir_bench_campaign_"))
        build_all(fmu_dir)
    print(f"campaign: {args.scenario}, {args.runs} runs of {args.duration} s, "
          f"best of {args.repeat}; {os.cpu_count()} CPUs, load average "
          f"{os.getloadavg()[0]:.2f}")
    out = {}
    for n in (1, 2):
        best, e2e, res = measure(n, args, fmu_dir)
        out[n] = (best, res)
        steps = sum(r["steps"] for r in res.results)
        in_runs = sum(r["wall_s"] for r in res.results)
        print(f"  {n} worker(s): {args.runs / best:6.2f} runs/s steady "
              f"({best:.2f} s, {1e6 * best / max(steps, 1):.0f} µs per macro step overall); "
              f"end to end incl. cluster start and warm-up {e2e:.2f} s")
        cpu = sum(r["cpu_s"] for r in res.results)
        print(f"      one run on its worker: {in_runs / args.runs:.3f} s wall, "
              f"{cpu / args.runs:.3f} s CPU (CPU/wall {cpu / in_runs:.2f}: below 1 = the "
              f"process waited for a core); workers busy in runs {100 * in_runs / (n * best):.0f}"
              " % of the campaign (the rest: Dask scheduling, transfers, idle tail)")
    ratio = out[1][0] / out[2][0]
    a1, a2 = out[1][1].aggregates, out[2][1].aggregates
    same = all(np.array_equal(a1.rms[k], a2.rms[k], equal_nan=True) for k in a1.rms) and \
        a1.rms.keys() == a2.rms.keys()
    print(f"throughput ratio 2 workers / 1 worker: {ratio:.2f} (issue 4 target >= 1.7); "
          f"aggregates identical: {same}; load average now {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
