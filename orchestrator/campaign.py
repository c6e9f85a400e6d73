"""Monte Carlo campaigns: N seeded co-simulations of one scenario on Dask distributed.

``axir montecarlo SCENARIO --runs N [--workers K | --scheduler ADDRESS] [--out DIR]
[--seed BASE] [--duration S] [--set UNIT.PARAM=VALUE ...]`` (see docs/campaigns.md).

How a campaign runs
-------------------
- Run i is the scenario with base seed ``BASE + i`` (default BASE: the scenario's seed): every
  unit with a ``seed`` parameter gets ``unit_seed(BASE + i, unit)`` exactly as
  ``axir run SCENARIO --seed BASE+i`` would (:func:`.run.seeded_parameters`), so run i of a
  campaign is bit-identical to that single run, whichever worker ran it and whatever it ran
  before (tested).
- Each run is a full co-simulation through the FMUs (:class:`.master.Master`). The FMU files
  are read once by the client and sent once to each worker (``Client.scatter``, broadcast);
  a worker writes them to its own temporary directory, extracts and instantiates them once
  per scenario and keeps the loaded :class:`~.master.Master` in a per-process cache
  (:data:`_CACHE`), never pickled. Every later run on that worker re-initialises the same
  instances: ``fmi2Reset`` (pythonfmu 0.7.0 rebuilds the Python slave object inside the loaded
  library; bit-identical to a fresh instantiation, tested), then parameters incl. the run's
  seeds, initialization mode, run. A run that fails drops its cached master (the instances
  are freed; the next run on that worker loads afresh).
- Scheduling: a ``LocalCluster`` of K worker processes, one thread each (pythonfmu slaves
  share one interpreter per process: threads would only contend for the GIL), or an existing
  cluster by scheduler address (its workers need the same ``axir`` installed). ``workers=0``
  (API only) runs serially in this process without Dask, for debugging.
- The worker processes hold pythonfmu libraries: :class:`FmuCachePlugin` frees every instance
  and library at worker teardown and then ends the process with ``os._exit`` at interpreter
  exit (the pythonfmu finalization heap-corruption trap, see cli.main).

Results (:func:`aggregate`, pure numpy; written by :func:`write_outputs`)
------------------------------------------------------------------------
Per time sample t (the recorded grid of the lowest-numbered successful run; other runs are
linearly interpolated onto it if their grid differs, e.g. variable-step scenarios), over the
N(t) successful runs whose track is valid at t:

- RMS errors ``sqrt(mean_i e_i(t)²)`` and mean errors of range, velocity and acceleration,
  e = estimate − truth (``Tracker.track.range/range_rate/range_acc`` vs
  ``TargetGenerator.truth.range/range_rate/range_acc``);
- NEES of the range axis (2 dof), ε_i = eᵀ P⁻¹ e with e = (e_r, e_v) and
  P = [[P_rr, P_rv], [P_rv, P_vv]] (``Tracker.track.P_*``), averaged over the runs, with its
  95 % band [χ²_{0.025}(2N)/N, χ²_{0.975}(2N)/N] (N ε̄ ~ χ²(2N) for a consistent filter,
  Bar-Shalom, Li & Kirubarajan 2001 §5.4);
- per run: RMS over time of each error, mean NEES, fraction of samples with the maneuver flag.

The first recorded sample (t = 0, before any step: the FMUs' start values) is not used.
Variables a scenario does not have (e.g. no ``track.range_acc`` in a Tracker without it) give
no column; :func:`aggregate` works on whatever :data:`DEFAULT_ERRORS` pairs are present.
"""

from __future__ import annotations

import atexit
import csv
import hashlib
import json
import math
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import click
import numpy as np

from .errors import AxirError
from .fmi import load_model_description
from .scenario import Scenario, load_scenario

#: error name → (estimate, truth) variables; units of the error: m, m/s, m/s²
DEFAULT_ERRORS: dict[str, tuple[str, str]] = {
    "range": ("Tracker.track.range", "TargetGenerator.truth.range"),
    "velocity": ("Tracker.track.range_rate", "TargetGenerator.truth.range_rate"),
    "acceleration": ("Tracker.track.range_acc", "TargetGenerator.truth.range_acc"),
}
ERROR_UNITS = {"range": "m", "velocity": "m/s", "acceleration": "m/s2"}
#: range-axis covariance of the track (P_rr [m²], P_rv [m²/s], P_vv [m²/s²])
DEFAULT_COVARIANCE: tuple[str, str, str] = (
    "Tracker.track.P_rr", "Tracker.track.P_rv", "Tracker.track.P_vv")
#: samples where this is recorded and 0 are excluded (no track yet)
DEFAULT_VALID = "Tracker.track.valid"
DEFAULT_MANEUVER = "Tracker.maneuver"
#: also recorded when present (per-run data for reports)
DEFAULT_EXTRA = ("Tracker.maneuver.statistic", "TargetGenerator.meas.range")


#: no dashboard; the scheduler's HTTP endpoints on a free port (never a clash on :8787)
LOCAL_CLUSTER_QUIET: dict[str, Any] = {
    "dashboard_address": None,
    "scheduler_kwargs": {"dashboard": False, "dashboard_address": ":0"},
}


# ============================================================================ specification
@dataclass(frozen=True)
class CampaignSpec:
    """Everything a worker needs to run any run of the campaign (small and picklable).

    ``units_fmu`` maps unit → (FMU file name, sha256 of its bytes); the bytes travel
    separately (scattered once per worker). ``record`` lists the variables recorded per run.
    ``per_run`` (run index → unit → {parameter: value}) overrides parameters of single runs
    (API only; e.g. a deliberately broken run in tests).
    """

    scenario: Scenario
    units_fmu: tuple[tuple[str, str, str], ...]
    runs: int
    base_seed: int
    record: tuple[str, ...]
    per_run: Mapping[int, Mapping[str, Mapping[str, Any]]] = field(default_factory=dict)

    @property
    def key(self) -> str:
        """Identity of the loaded system a worker may reuse: FMUs, units, order, connections,
        step settings (parameters and seeds change per run and are not part of it)."""
        sc = self.scenario
        ident = (self.units_fmu, tuple(sc.order), tuple(map(str, sc.connections)),
                 sc.algorithm, sc.step, sc.step_from, sc.initial_step)
        return hashlib.sha256(repr(ident).encode()).hexdigest()[:20]


def parse_assignment(text: str) -> tuple[str, str, Any]:
    """``"Unit.param=value"`` → (unit, param, value); the value is read as a boolean
    (``true``/``false``), an integer, a float, or else kept as a string."""
    ref, eq, raw = text.partition("=")
    unit, dot, name = ref.strip().partition(".")
    if not eq or not dot or not unit or not name:
        raise AxirError(f"--set {text!r}: expected UNIT.PARAMETER=VALUE")
    raw = raw.strip()
    value: Any
    if raw.lower() in ("true", "false"):
        value = raw.lower() == "true"
    else:
        try:
            value = int(raw)
        except ValueError:
            try:
                value = float(raw)
            except ValueError:
                value = raw
    return unit, name, value


def with_parameters(scenario: Scenario, assignments: Mapping[str, Mapping[str, Any]]
                    ) -> Scenario:
    """A copy of ``scenario`` with unit parameters overridden (unit → {name: value});
    unknown units raise :class:`AxirError` (unknown parameters are reported by the FMU)."""
    units = {n: {**s, "parameters": dict(s.get("parameters", {}))}
             for n, s in scenario.units.items()}
    for unit, params in assignments.items():
        if unit not in units:
            raise AxirError(f"parameter override for unknown unit {unit!r} "
                            f"(scenario {scenario.name} has {', '.join(units)})")
        units[unit]["parameters"].update(params)
    return replace(scenario, units=units)


def _fmu_files(scenario: Scenario, fmu_dir: Path) -> dict[str, Path]:
    out = {}
    for name, spec in scenario.units.items():
        path = Path(fmu_dir) / spec.get("fmu", f"{name}.fmu")
        if not path.is_file():
            raise AxirError(f"FMU file not found: {path} (unit {name}); run `axir build` "
                            "first or pass --fmu-dir")
        out[name] = path
    return out


def _available(paths: Mapping[str, Path]) -> set[str]:
    """``Unit.variable`` names of every unit's FMU (read from the modelDescription only)."""
    names = set()
    for unit, path in paths.items():
        md = load_model_description(path)
        names |= {f"{unit}.{v.name}" for v in md.modelVariables}
    return names


def record_list(available: set[str], errors: Mapping[str, tuple[str, str]],
                covariance: Sequence[str] | None) -> tuple[str, ...]:
    """The variables a campaign records: the error pairs, covariance, validity, maneuver and
    extras that exist in the FMUs (in a fixed order)."""
    want: list[str] = []
    for est, truth in errors.values():
        want += [est, truth]
    want += list(covariance or ())
    want += [DEFAULT_VALID, DEFAULT_MANEUVER, *DEFAULT_EXTRA]
    out: list[str] = []
    for v in want:
        if v in available and v not in out:
            out.append(v)
    return tuple(out)


# ============================================================================ worker side
#: per-process cache: spec key → [Master, used] ; FMU digest → file on this worker
_CACHE: dict[str, list[Any]] = {}
_FILES: dict[str, Path] = {}
_TMP: list[Path] = []
_MAX_MASTERS = 4
_EXIT_HOOK: list[bool] = []


def _close_all() -> None:
    """Free every cached instance and library, remove this process's FMU copies."""
    while _CACHE:
        _key, (master, _used) = _CACHE.popitem()
        try:
            master.close()
        except Exception as e:  # keep closing the others
            print(f"axir campaign: closing a cached system failed: {e}", file=sys.stderr)
    _FILES.clear()
    while _TMP:
        shutil.rmtree(_TMP.pop(), ignore_errors=True)


def _exit_without_finalization() -> None:  # pragma: no cover - runs at worker exit
    """atexit hook of worker processes that loaded FMUs: free them, then end the process
    before the interpreter's finalization (pythonfmu 0.7.0 can corrupt the heap there)."""
    _close_all()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


def _worker_file(unit: str, fname: str, digest: str, blob: bytes) -> Path:
    """This process's copy of an FMU (written once per content)."""
    path = _FILES.get(digest)
    if path is not None and path.is_file():
        return path
    if hashlib.sha256(blob).hexdigest() != digest:
        raise AxirError(f"FMU bytes of unit {unit} do not match their digest")
    if not _TMP:
        _TMP.append(Path(tempfile.mkdtemp(prefix="axir_campaign_")))
    d = _TMP[0] / digest[:16]
    d.mkdir(exist_ok=True)
    path = d / fname
    path.write_bytes(blob)
    _FILES[digest] = path
    return path


def _master(spec: CampaignSpec, blobs: Mapping[str, bytes], in_dask: bool) -> Any:
    """The cached, loaded master of this spec (reset if it ran before), or a new one."""
    from .master import Master
    from .system import SystemDescription, UnitSpec

    entry = _CACHE.get(spec.key)
    if entry is not None:
        master, used = entry
        if used:
            master.reset()
        entry[1] = True
        return master
    while len(_CACHE) >= _MAX_MASTERS:  # bound memory on long-lived shared clusters
        _key, (old, _used) = next(iter(_CACHE.items()))
        del _CACHE[_key]
        old.close()
    files = {unit: _worker_file(unit, Path(fname).name, digest, blobs[unit])
             for unit, fname, digest in spec.units_fmu}
    sc = spec.scenario
    system = SystemDescription(
        {n: UnitSpec(n, files[n], dict(s.get("parameters", {}))) for n, s in sc.units.items()},
        list(sc.connections))
    master = Master(system, algorithm=sc.algorithm, order=sc.order, step=sc.step,
                    step_from=sc.step_from, initial_step=sc.initial_step, logging_on=True)
    master.__enter__()
    _CACHE[spec.key] = [master, True]
    if in_dask and not _EXIT_HOOK:
        atexit.register(_exit_without_finalization)
        _EXIT_HOOK.append(True)
    return master


def _drop(spec: CampaignSpec) -> None:
    entry = _CACHE.pop(spec.key, None)
    if entry is not None:
        try:
            entry[0].close()
        except Exception as e:
            print(f"axir campaign: freeing a failed system: {e}", file=sys.stderr)


def simulate_run(spec: CampaignSpec, blobs: Mapping[str, bytes], index: int,
                 in_dask: bool = True) -> dict[str, Any]:
    """Run ``index`` of the campaign (on a worker). Never raises: a failure is returned as
    ``status = "failed"`` with the error message (and frees the cached system)."""
    from .errors import AxirError as _AxirError
    from .record import Recorder
    from .run import seeded_parameters

    seed = spec.base_seed + index
    t0, c0 = time.perf_counter(), time.process_time()
    worker = _worker_name()
    result: dict[str, Any] = {"run": index, "seed": seed, "worker": worker, "status": "ok",
                              "error": "", "steps": 0, "data": None, "wall_s": 0.0,
                              "cpu_s": 0.0}
    try:
        master = _master(spec, blobs, in_dask)
        params = seeded_parameters(master.system, master.instances, seed)
        for unit, extra in spec.per_run.get(index, {}).items():
            params[unit] = {**params[unit], **extra}
        duration = spec.scenario.duration
        master.initialize(0.0, duration, params)
        rec = Recorder(spec.record, spec.scenario.decimation)
        complete = master.run(duration, [rec])
        result["steps"] = master.steps
        if not complete:
            raise _AxirError("run interrupted")
        result["data"] = rec.data.copy()
    except Exception as e:
        _drop(spec)
        msg = str(e) if isinstance(e, _AxirError) else f"{type(e).__name__}: {e}"
        result.update(status="failed", error=msg)
    result["wall_s"] = time.perf_counter() - t0
    result["cpu_s"] = time.process_time() - c0  # CPU of this worker process during the run
    return result


def _worker_name() -> str:
    try:
        from distributed import get_worker

        return str(get_worker().name)
    except Exception:
        return "local"


try:  # the plugin base class is optional at import time (API use without distributed)
    from distributed.diagnostics.plugin import WorkerPlugin as _WorkerPluginBase
except Exception:  # pragma: no cover
    _WorkerPluginBase = object  # type: ignore[assignment,misc]


class FmuCachePlugin(_WorkerPluginBase):  # type: ignore[misc,valid-type]
    """Dask worker plugin: at worker teardown, free every cached FMU instance and library
    (fmi2FreeInstance then freeLibrary) and remove the worker's FMU copies."""

    name = "axir-fmu-cache"

    def teardown(self, worker: Any) -> None:
        _close_all()


# ============================================================================ aggregation
@dataclass
class Aggregates:
    """Campaign statistics vs time (arrays over the time grid ``t`` [s])."""

    t: np.ndarray
    n: np.ndarray  # runs with a valid track per sample
    rms: dict[str, np.ndarray]  # error name → RMS over runs
    mean: dict[str, np.ndarray]  # error name → mean over runs (bias)
    nees: np.ndarray | None = None  # mean NEES over runs (2 dof)
    nees_n: np.ndarray | None = None  # runs with a usable covariance per sample
    nees_band: tuple[np.ndarray, np.ndarray] | None = None  # 95 % χ² band of the mean
    per_run: list[dict[str, Any]] = field(default_factory=list)
    errors: dict[str, np.ndarray] = field(default_factory=dict)  # name → (runs, time)


def nees_band(n: np.ndarray | int, dof: int = 2, prob: float = 0.95
              ) -> tuple[np.ndarray, np.ndarray]:
    """Two-sided ``prob`` band of the mean of n NEES values of ``dof`` dimensions:
    [χ²_{(1−p)/2}(dof·n)/n, χ²_{(1+p)/2}(dof·n)/n] (NaN where n = 0)."""
    from scipy.stats import chi2

    n = np.asarray(n, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        lo = np.where(n > 0, chi2.ppf(0.5 - prob / 2, dof * n) / n, np.nan)
        hi = np.where(n > 0, chi2.ppf(0.5 + prob / 2, dof * n) / n, np.nan)
    return lo, hi


def nees2(e_r: np.ndarray, e_v: np.ndarray, p_rr: np.ndarray, p_rv: np.ndarray,
          p_vv: np.ndarray) -> np.ndarray:
    """eᵀ P⁻¹ e for e = (e_r, e_v), P = [[p_rr, p_rv], [p_rv, p_vv]] (elementwise; NaN where
    P is not positive definite or not finite):
    ε = (p_vv e_r² − 2 p_rv e_r e_v + p_rr e_v²) / (p_rr p_vv − p_rv²)."""
    e_r, e_v, p_rr, p_rv, p_vv = (np.asarray(x, dtype=float)
                                  for x in (e_r, e_v, p_rr, p_rv, p_vv))
    det = p_rr * p_vv - p_rv * p_rv
    ok = np.isfinite(det) & (det > 0.0) & (p_rr > 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        eps = (p_vv * e_r * e_r - 2.0 * p_rv * e_r * e_v + p_rr * e_v * e_v) / det
    return np.where(ok, eps, np.nan)


def _on_grid(t: np.ndarray, data: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """``data`` (samples × columns, time ``t``) on ``grid`` (linear interpolation; NaN outside
    the recorded span)."""
    if t.shape == grid.shape and np.array_equal(t, grid):
        return data
    out = np.empty((grid.size, data.shape[1]))
    for j in range(data.shape[1]):
        out[:, j] = np.interp(grid, t, data[:, j], left=np.nan, right=np.nan)
    return out


def aggregate(results: Sequence[Mapping[str, Any]], record: Sequence[str],
              errors: Mapping[str, tuple[str, str]] = DEFAULT_ERRORS,
              covariance: Sequence[str] | None = DEFAULT_COVARIANCE,
              valid: str | None = DEFAULT_VALID, maneuver: str | None = DEFAULT_MANEUVER
              ) -> Aggregates:
    """Statistics of the successful runs of ``results`` (see module docstring), in run order
    (so the result does not depend on completion order or on the number of workers)."""
    ok = sorted((r for r in results if r["status"] == "ok" and r["data"] is not None),
                key=lambda r: r["run"])
    col = {v: i + 1 for i, v in enumerate(record)}
    if not ok:
        empty = np.zeros(0)
        return Aggregates(empty, empty.astype(int), {}, {}, per_run=[])
    grid = ok[0]["data"][1:, 0]  # drop t = 0 (start values before the first step)
    stacks = np.stack([_on_grid(r["data"][1:, 0], r["data"][1:, 1:], grid) for r in ok])
    mask = np.ones(stacks.shape[:2], dtype=bool)
    if valid in col:
        mask &= stacks[:, :, col[valid] - 1] > 0.5
    err: dict[str, np.ndarray] = {}
    for name, (est, truth) in errors.items():
        if est in col and truth in col:
            e = stacks[:, :, col[est] - 1] - stacks[:, :, col[truth] - 1]
            err[name] = np.where(mask, e, np.nan)
    n = np.sum(mask & np.all(np.isfinite(np.stack(list(err.values()))), axis=0), axis=0) \
        if err else np.zeros(grid.size, dtype=int)
    with np.errstate(invalid="ignore"):
        rms = {k: np.sqrt(_nanmean(e * e, axis=0)) for k, e in err.items()}
        mean = {k: _nanmean(e, axis=0) for k, e in err.items()}
    agg = Aggregates(grid, n, rms, mean, errors=err)
    eps = None
    if covariance and all(c in col for c in covariance) and "range" in err \
            and "velocity" in err:
        p = [stacks[:, :, col[c] - 1] for c in covariance]
        eps = nees2(err["range"], err["velocity"], *p)
        agg.nees_n = np.sum(np.isfinite(eps), axis=0)
        agg.nees = _nanmean(eps, axis=0)
        agg.nees_band = nees_band(agg.nees_n)
    man = stacks[:, :, col[maneuver] - 1] if maneuver in col else None
    for i, r in enumerate(ok):
        row: dict[str, Any] = {"run": r["run"]}
        for k, e in err.items():
            row[f"rms_{k}"] = _scalar(np.sqrt(_nanmean(e[i] * e[i])))
        if eps is not None:
            row["nees_mean"] = _scalar(_nanmean(eps[i]))
        if man is not None:
            row["maneuver_fraction"] = _scalar(np.mean(man[i] > 0.5))
        agg.per_run.append(row)
    return agg


def _nanmean(x: np.ndarray, axis: int | None = None) -> np.ndarray:
    """Mean ignoring NaN, NaN (no warning) where every value is NaN."""
    finite = np.isfinite(x)
    cnt = finite.sum(axis=axis)
    tot = np.where(finite, x, 0.0).sum(axis=axis)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(cnt > 0, tot / np.maximum(cnt, 1), np.nan)


def _scalar(x: Any) -> float | None:
    v = float(x)
    return v if math.isfinite(v) else None


# ============================================================================ the campaign
@dataclass
class CampaignResult:
    """What :func:`run_campaign` returns: the spec, every run's result (in run order), the
    aggregates of the successful ones and the campaign summary."""

    spec: CampaignSpec
    results: list[dict[str, Any]]
    aggregates: Aggregates
    summary: dict[str, Any]

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [r for r in self.results if r["status"] != "ok"]


def prepare(scenario: Scenario | str | Path | None, fmu_dir: Path, runs: int, *,
            seed: int | None = None, duration: float | None = None,
            parameters: Mapping[str, Mapping[str, Any]] | None = None,
            per_run: Mapping[int, Mapping[str, Mapping[str, Any]]] | None = None,
            errors: Mapping[str, tuple[str, str]] = DEFAULT_ERRORS,
            covariance: Sequence[str] | None = DEFAULT_COVARIANCE,
            ) -> tuple[CampaignSpec, dict[str, bytes]]:
    """Validate the inputs and build the :class:`CampaignSpec` and the FMU bytes per unit."""
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    if not (isinstance(runs, int) and runs >= 1):
        raise AxirError(f"--runs must be a positive integer, got {runs!r}")
    sc = sc.with_overrides(duration=duration)
    if parameters:
        sc = with_parameters(sc, parameters)
    base = sc.seed if seed is None else int(seed)
    if base < 0:
        raise AxirError(f"--seed must be >= 0, got {base}")
    paths = _fmu_files(sc, fmu_dir)
    blobs = {u: p.read_bytes() for u, p in paths.items()}
    units_fmu = tuple((u, p.name, hashlib.sha256(blobs[u]).hexdigest())
                      for u, p in sorted(paths.items()))
    record = record_list(_available(paths), errors, covariance)
    spec = CampaignSpec(sc, units_fmu, runs, base, record, dict(per_run or {}))
    return spec, blobs


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
) -> CampaignResult:
    """Run a Monte Carlo campaign (see module docstring) and return its results.

    ``workers``: size of the LocalCluster (default: CPU count); 0 runs serially in this
    process without Dask. ``scheduler``: address of an existing Dask scheduler (exclusive
    with ``workers``). ``client``: an existing ``distributed.Client`` (API; not closed).
    ``parameters`` overrides unit parameters for every run. Failed runs are reported through
    ``on_failure`` (default: one line on stderr) and in the per-run table; they never stop
    the campaign. Writes the outputs into ``out_dir`` when given.
    """
    if workers is not None and scheduler is not None:
        raise AxirError("give either --workers or --scheduler, not both")
    if workers is not None and workers < 0:
        raise AxirError(f"--workers must be >= 0, got {workers}")
    spec, blobs = prepare(scenario, fmu_dir, runs, seed=seed, duration=duration,
                          parameters=parameters, per_run=per_run, errors=errors,
                          covariance=covariance)
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
    result = CampaignResult(spec, ordered, agg, summary)
    if out_dir is not None:
        write_outputs(result, Path(out_dir), plot=plot)
    return result


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


def _run_on_dask(spec: CampaignSpec, blobs: Mapping[str, bytes], workers: int | None,
                 scheduler: str | None, client: Any, results: dict[int, dict[str, Any]],
                 bar: Any, report: Callable[[dict[str, Any]], None]) -> str:
    """Submit every run to Dask and collect them as they complete; returns a description of
    where they ran."""
    import logging

    from distributed import Client, LocalCluster, as_completed

    own: list[Any] = []
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
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                   silence_logs=logging.ERROR, **LOCAL_CLUSTER_QUIET)
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
            fut.release()
            _collect(res, results, bar, report)
        return where
    finally:
        for obj in own:
            try:
                obj.close()
            except Exception as e:  # pragma: no cover - shutdown noise
                print(f"axir campaign: closing Dask: {e}", file=sys.stderr)


def _summary(spec: CampaignSpec, results: Sequence[Mapping[str, Any]], agg: Aggregates,
             wall: float, where: str, parameters: Mapping[str, Any]) -> dict[str, Any]:
    from .run import versions

    ok = [r for r in results if r["status"] == "ok"]
    out: dict[str, Any] = {
        "scenario": spec.scenario.name,
        "source": spec.scenario.source,
        "runs": spec.runs,
        "succeeded": len(ok),
        "failed": len(results) - len(ok),
        "failures": [{"run": r["run"], "seed": r["seed"], "error": r["error"]}
                     for r in results if r["status"] != "ok"],
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


# ============================================================================ outputs
def write_outputs(result: CampaignResult, out_dir: Path, plot: bool = True) -> list[Path]:
    """``aggregates.csv`` (statistics vs time), ``runs.csv`` (one row per run),
    ``campaign.json`` (summary) and, with ``plot``, ``campaign.png``; returns the paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    agg = result.aggregates
    files = [out_dir / "aggregates.csv", out_dir / "runs.csv", out_dir / "campaign.json"]
    cols: list[tuple[str, np.ndarray]] = [("time_s", agg.t), ("runs_valid", agg.n)]
    for k in agg.rms:
        u = ERROR_UNITS.get(k, "")
        cols.append((f"rms_{k}_{u}".replace("/", "_"), agg.rms[k]))
        cols.append((f"mean_{k}_{u}".replace("/", "_"), agg.mean[k]))
    if agg.nees is not None and agg.nees_band is not None:
        cols += [("nees_runs", agg.nees_n), ("nees_mean", agg.nees),
                 ("nees_lo95", agg.nees_band[0]), ("nees_hi95", agg.nees_band[1])]
    with open(files[0], "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow([c for c, _ in cols])
        for i in range(agg.t.size):
            w.writerow([_cell(v[i]) for _, v in cols])
    per = {r["run"]: r for r in agg.per_run}
    metric_keys = sorted({k for r in agg.per_run for k in r if k != "run"})
    with open(files[1], "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["run", "seed", "status", "worker", "steps", "wall_s", "cpu_s",
                    *metric_keys, "error"])
        for r in result.results:
            m = per.get(r["run"], {})
            w.writerow([r["run"], r["seed"], r["status"], r["worker"], r["steps"],
                        f"{r['wall_s']:.4f}", f"{r.get('cpu_s', 0.0):.4f}",
                        *(_cell(m.get(k)) for k in metric_keys), r["error"]])
    files[2].write_text(json.dumps(result.summary, indent=2) + "\n", encoding="utf-8")
    if plot and agg.t.size and (agg.rms or agg.nees is not None):
        files.append(plot_campaign(result, out_dir / "campaign.png"))
    return files


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, (float, np.floating)):
        return repr(float(v)) if math.isfinite(v) else ""
    return str(int(v)) if isinstance(v, (np.integer, bool)) else str(v)


def plot_campaign(result: CampaignResult, path: Path) -> Path:
    """RMS errors vs time (one panel per error) and the mean NEES with its 95 % band."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    agg = result.aggregates
    panels = list(agg.rms) + (["nees"] if agg.nees is not None else [])
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 2.6 * len(panels)), sharex=True,
                             squeeze=False)
    for ax, k in zip(axes[:, 0], panels, strict=True):
        if k == "nees":
            lo, hi = agg.nees_band
            ax.plot(agg.t, agg.nees, lw=1.0, label="mean NEES (range axis, 2 dof)")
            ax.fill_between(agg.t, lo, hi, color="0.85", label="95 % χ² band")
            ax.set(ylabel="NEES", yscale="log")
        else:
            ax.plot(agg.t, agg.rms[k], lw=1.0, label=f"RMS {k} error")
            ax.set(ylabel=f"{k} [{ERROR_UNITS.get(k, '')}]")
        ax.legend(loc="upper right", fontsize=8)
        ax.grid(alpha=0.3)
    axes[-1, 0].set(xlabel="time [s]")
    s = result.summary
    fig.suptitle(f"{s['scenario']}: {s['succeeded']}/{s['runs']} runs, seeds {s['seeds']}")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


# ============================================================================ CLI
@click.command()
@click.argument("scenario", required=False)
@click.option("--runs", "-n", type=click.IntRange(min=1), required=True,
              help="Number of Monte Carlo runs (run i uses seed BASE + i).")
@click.option("--workers", "-w", type=click.IntRange(min=1), default=None,
              help="Worker processes of a local Dask cluster (default: CPU count).")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Use an existing Dask cluster (e.g. tcp://host:8786) instead.")
@click.option("--out", "out_dir", default="out/montecarlo", show_default=True,
              type=click.Path(file_okay=False, path_type=Path), help="Results directory.")
@click.option("--seed", type=click.IntRange(min=0), default=None,
              help="Base seed BASE (default: the scenario's seed).")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True),
              help="Simulated duration of each run [s] (overrides the scenario).")
@click.option("--set", "assignments", multiple=True, metavar="UNIT.PARAM=VALUE",
              help="Override a unit parameter for every run (repeatable).")
@click.option("--fmu-dir", default=None, type=click.Path(file_okay=False, path_type=Path),
              help="Where the FMUs are (default: $AXIR_FMU_DIR or dist).")
@click.option("--plot/--no-plot", default=True, show_default=True,
              help="Write campaign.png.")
@click.option("--progress/--no-progress", default=None, help="Progress bar (default: on a tty).")
def montecarlo(scenario: str | None, runs: int, workers: int | None, scheduler: str | None,
               out_dir: Path, seed: int | None, duration: float | None,
               assignments: tuple[str, ...], fmu_dir: Path | None, plot: bool,
               progress: bool | None) -> None:
    """Run SCENARIO (a .toml file or a built-in name; default: the closed loop) --runs times
    on Dask and write aggregates.csv, runs.csv, campaign.json and campaign.png.

    Exit status: 0 when every run succeeded, 1 when some failed (reported on stderr and in
    runs.csv; the others are aggregated), 2 on a usage or scenario error or when every run
    failed.
    """
    from .cli import DEFAULT_FMU_DIR

    if workers is not None and scheduler is not None:
        raise click.UsageError("--workers and --scheduler are mutually exclusive")
    params: dict[str, dict[str, Any]] = {}
    for a in assignments:
        unit, name, value = parse_assignment(a)
        params.setdefault(unit, {})[name] = value
    res = run_campaign(scenario, fmu_dir or Path(DEFAULT_FMU_DIR), runs, workers=workers,
                       scheduler=scheduler, seed=seed, duration=duration, parameters=params,
                       progress=progress, out_dir=None)
    files = write_outputs(res, out_dir, plot=plot)
    s = res.summary
    click.echo("wrote " + ", ".join(str(f) for f in files))
    keys = ("scenario", "runs", "succeeded", "failed", "seeds", "executed_on", "wall_time_s",
            "runs_per_s", *(k for k in s if k.startswith(("rms_", "nees_"))))
    click.echo(json.dumps({k: s.get(k) for k in keys}, indent=1))
    if s["succeeded"] == 0:
        raise AxirError(f"every run failed; first error: {s['failures'][0]['error']}")
    if s["failed"]:
        click.echo(f"{s['failed']} of {s['runs']} runs failed (see runs.csv)", err=True)
        sys.exit(1)


__all__ = [
    "DEFAULT_COVARIANCE", "DEFAULT_ERRORS", "Aggregates", "CampaignResult", "CampaignSpec",
    "FmuCachePlugin", "aggregate", "montecarlo", "nees2", "nees_band", "parse_assignment",
    "run_campaign", "simulate_run", "write_outputs",
]
