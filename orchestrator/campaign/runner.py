"""Run a campaign: every run submitted to Dask (a LocalCluster, an existing scheduler or
client) or serially in this process, results collected in run order, aggregated, summarised."""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import AxirError
from ..outdir import claim
from ..preflight import check_duration
from ..run import versions
from ..scenario_spec import Scenario
from .outputs import CAMPAIGN_FILES, write_outputs
from .spec import DEFAULT_COVARIANCE, DEFAULT_ERRORS, CampaignSpec, prepare
from .stats import Aggregates, CampaignResult, _nanmean, _scalar, aggregate
from .worker import SCRATCH_ENV, FmuCachePlugin, _close_all, simulate_run

#: no dashboard; the scheduler's HTTP endpoints on a free port (never a clash on :8787)
LOCAL_CLUSTER_QUIET: dict[str, Any] = {
    "dashboard_address": None,
    "scheduler_kwargs": {"dashboard": False, "dashboard_address": ":0"},
}


def run_campaign(
    scenario: Scenario | str | Path | None,
    fmu_dir: Path,
    runs: int,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    seed: int | None = None,
    duration: float | None = None,
    parameters: Mapping[str, Mapping[str, Any]] | None = None,
    per_run: Mapping[int, Mapping[str, Mapping[str, Any]]] | None = None,
    errors: Mapping[str, tuple[str, str]] = DEFAULT_ERRORS,
    covariance: Sequence[str] | None = DEFAULT_COVARIANCE,
    progress: bool | None = None,
    out_dir: Path | None = None,
    plot: bool = True,
    on_failure: Callable[[dict[str, Any]], None] | None = None,
    client: Any = None,
    long_ok: bool = False,
) -> CampaignResult:
    """Run a Monte Carlo campaign (see module docstring) and return its results.

    ``workers``: size of the LocalCluster (default: CPU count); 0 runs serially in this
    process without Dask. ``scheduler``: address of an existing Dask scheduler (exclusive
    with ``workers``). ``client``: an existing ``distributed.Client`` (API; not closed).
    ``parameters`` overrides unit parameters for every run. Failed runs are reported through
    ``on_failure`` (default: one line on stderr) and in the per-run table; they never stop
    the campaign. Writes the outputs into ``out_dir`` when given: the folder is checked
    and claimed before the first run (:mod:`..outdir`: writable, one campaign at a time, an
    earlier campaign's files removed, a folder holding other files refused). A campaign
    estimated to take more than a day needs ``long_ok``.
    """
    if workers is not None and scheduler is not None:
        raise AxirError("give either --workers or --scheduler, not both")
    if workers is not None and workers < 0:
        raise AxirError(f"--workers must be >= 0, got {workers}")
    spec, blobs = prepare(scenario, fmu_dir, runs, seed=seed, duration=duration,
                          parameters=parameters, per_run=per_run, errors=errors,
                          covariance=covariance)
    n_workers = (1 if workers == 0 else workers or os.cpu_count() or 1) \
        if client is None and scheduler is None else 1
    sc = spec.scenario
    check_duration(sc.duration, sc.step or sc.initial_step, long_ok, runs, n_workers)
    folder = claim(Path(out_dir), CAMPAIGN_FILES) if out_dir is not None else None
    try:
        result = _run(spec, blobs, runs, workers, scheduler, client, progress, on_failure,
                      errors, covariance, parameters)
        if folder is not None:
            result.files = write_outputs(result, folder.path, plot=plot)
    finally:
        if folder is not None:
            folder.release()
    return result


def _run(spec: CampaignSpec, blobs: Mapping[str, bytes], runs: int, workers: int | None,
         scheduler: str | None, client: Any, progress: bool | None,
         on_failure: Callable[[dict[str, Any]], None] | None,
         errors: Mapping[str, tuple[str, str]], covariance: Sequence[str] | None,
         parameters: Mapping[str, Mapping[str, Any]] | None) -> CampaignResult:
    report = on_failure or _report_failure
    wall0 = time.perf_counter()
    results: dict[int, dict[str, Any]] = {}
    from tqdm import tqdm

    disable = None if progress is None else not progress
    bar = tqdm(total=runs, unit="run", disable=disable, desc=spec.scenario.name,
               file=sys.stderr)
    try:
        if workers == 0 and client is None:
            where = "in-process"
            for i in range(runs):
                res = simulate_run(spec, blobs, i, in_dask=False)
                _collect(res, results, bar, report)
        else:
            where = _run_on_dask(spec, blobs, workers, scheduler, client, results, bar,
                                 report)
    finally:
        bar.close()
        if workers == 0 and client is None:
            _close_all()
    wall = time.perf_counter() - wall0
    ordered = [results[i] for i in range(runs)]
    agg = aggregate(ordered, spec.record, errors, covariance)
    summary = _summary(spec, ordered, agg, wall, where, parameters or {})
    return CampaignResult(spec, ordered, agg, summary)


def _collect(res: dict[str, Any], results: dict[int, dict[str, Any]], bar: Any,
             report: Callable[[dict[str, Any]], None]) -> None:
    results[res["run"]] = res
    bar.update(1)
    if res["status"] != "ok":
        report(res)


def _report_failure(res: dict[str, Any]) -> None:
    from tqdm import tqdm

    tqdm.write(f"run {res['run']} (seed {res['seed']}, worker {res['worker']}) failed: "
               f"{res['error']}", file=sys.stderr)


def _worker_losses(dask_scheduler: Any, key: str) -> int:
    """On the scheduler: how many workers died while running task ``key`` (each loss makes
    the scheduler run the task again elsewhere, up to ``distributed.scheduler.allowed-failures``
    times, then the task fails with KilledWorker)."""
    ts = dask_scheduler.tasks.get(key)
    return int(getattr(ts, "suspicious", 0)) if ts is not None else 0


def _quiet_logs(level: int = logging.CRITICAL) -> None:
    """Silence distributed's loggers (in this process or, through ``client.run``, a worker):
    called just before shutdown, when a heartbeat racing the closing scheduler would
    otherwise print a traceback of a connection closed on purpose."""
    for name in ("distributed", "distributed.worker", "distributed.nanny",
                 "distributed.core", "distributed.comm", "distributed.scheduler"):
        logging.getLogger(name).setLevel(level)


def _run_on_dask(spec: CampaignSpec, blobs: Mapping[str, bytes], workers: int | None,
                 scheduler: str | None, client: Any, results: dict[int, dict[str, Any]],
                 bar: Any, report: Callable[[dict[str, Any]], None]) -> str:
    """Submit every run to Dask and collect them as they complete; returns a description of
    where they ran. Each result gets ``worker_losses`` (workers that died running it) and
    ``retries`` (times the scheduler ran it again after such a loss)."""
    from distributed import Client, LocalCluster, as_completed

    own: list[Any] = []
    scratch: Path | None = None
    try:
        if client is not None:
            where = f"client {client.scheduler.address}"
        elif scheduler is not None:
            try:
                client = Client(scheduler, timeout="10s")
            except Exception as e:
                raise AxirError(f"cannot connect to the Dask scheduler {scheduler}: {e}"
                                ) from None
            own.append(client)
            where = f"scheduler {scheduler}"
        else:
            n = workers or os.cpu_count() or 1
            # everything the workers write (Dask's scratch space, their FMU copies and
            # extracted FMUs: FmuCachePlugin.setup) goes into a folder of our own, removed
            # after the cluster closed, even when a worker was killed (by default Dask leaves
            # dask-scratch-space in TMPDIR)
            import dask

            scratch = Path(tempfile.mkdtemp(prefix="axir_dask_"))
            with dask.config.set({"temporary-directory": str(scratch)}):
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                       silence_logs=logging.ERROR,
                                       local_directory=str(scratch),
                                       env={SCRATCH_ENV: str(scratch)},
                                       **LOCAL_CLUSTER_QUIET)
            own.append(cluster)
            client = Client(cluster)
            own.insert(0, client)
            where = f"LocalCluster of {n} worker process(es)"
        client.register_plugin(FmuCachePlugin(), name=FmuCachePlugin.name)
        blob_futures = client.scatter(dict(blobs), broadcast=True)
        token = f"{spec.key}-{os.getpid()}-{time.time_ns()}"
        futures = {client.submit(simulate_run, spec, blob_futures, i, key=f"axir-run-{token}-{i}",
                                 pure=False, retries=0): i for i in range(spec.runs)}
        for fut in as_completed(futures):
            i = futures[fut]
            try:
                res = fut.result()
            except Exception as e:  # the worker died (KilledWorker), cancelled, ...
                res = {"run": i, "seed": spec.base_seed + i, "worker": "?", "status": "failed",
                       "error": f"{type(e).__name__}: {e}", "steps": 0, "data": None,
                       "wall_s": 0.0, "cpu_s": 0.0}
            try:
                losses = client.run_on_scheduler(_worker_losses, key=fut.key)
            except Exception:  # pragma: no cover - scheduler gone: unknown
                losses = None
            res["worker_losses"] = losses
            res["retries"] = None if losses is None else (
                losses if res["status"] == "ok" else max(losses - 1, 0))
            fut.release()
            _collect(res, results, bar, report)
        return where
    finally:
        if own:  # this process's loggers; the workers' only if the cluster is ours
            _quiet_logs()
            if scratch is not None:
                with contextlib.suppress(Exception):
                    client.run(_quiet_logs)
        for obj in own:  # the client first, then the cluster it talks to
            try:
                obj.close()
            except Exception as e:  # pragma: no cover - shutdown noise
                print(f"axir campaign: closing Dask: {e}", file=sys.stderr)
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)


def _summary(spec: CampaignSpec, results: Sequence[Mapping[str, Any]], agg: Aggregates,
             wall: float, where: str, parameters: Mapping[str, Any]) -> dict[str, Any]:
    ok = [r for r in results if r["status"] == "ok"]
    out: dict[str, Any] = {
        "scenario": spec.scenario.name,
        "source": spec.scenario.source,
        "runs": spec.runs,
        "succeeded": len(ok),
        "failed": len(results) - len(ok),
        "failures": [{"run": r["run"], "seed": r["seed"], "error": r["error"]}
                     for r in results if r["status"] != "ok"],
        "worker_losses": sum(r.get("worker_losses") or 0 for r in results),
        "retried_runs": [{"run": r["run"], "worker_losses": r["worker_losses"],
                          "retries": r["retries"], "status": r["status"]}
                         for r in results if r.get("worker_losses")],
        "base_seed": spec.base_seed,
        "seeds": f"{spec.base_seed}..{spec.base_seed + spec.runs - 1}",
        "duration": spec.scenario.duration,
        "parameters": {u: dict(p) for u, p in parameters.items()},
        "executed_on": where,
        "wall_time_s": round(wall, 3),
        "runs_per_s": round(len(results) / wall, 3) if wall > 0 else None,
        "recorded": list(spec.record),
        "errors_available": sorted(agg.rms),
    }
    for k, r in agg.rms.items():
        out[f"rms_{k}_time_avg"] = _scalar(_nanmean(r)) if r.size else None
    if agg.nees is not None and agg.nees_band is not None:
        inside = np.isfinite(agg.nees) & (agg.nees >= agg.nees_band[0]) & (
            agg.nees <= agg.nees_band[1])
        usable = np.isfinite(agg.nees)
        out["nees_time_avg"] = _scalar(_nanmean(agg.nees))
        out["nees_fraction_in_95_band"] = _scalar(inside.sum() / max(usable.sum(), 1))
    out["versions"] = versions()
    return out
