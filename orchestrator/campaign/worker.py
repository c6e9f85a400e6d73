"""Worker side of a campaign: one run (:func:`simulate_run`) on a per-process cache of loaded
masters (FMUs scattered once, instantiated once, ``fmi2Reset`` between runs), and the Dask
plugin that frees them at worker teardown."""

from __future__ import annotations

import atexit
import hashlib
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..archive import remove_extracted
from ..errors import AxirError
from ..master import Master
from ..record import Recorder
from ..run import seeded_parameters
from ..system import SystemDescription, UnitSpec
from .spec import CampaignSpec

#: per-process cache: spec key → [Master, used] ; FMU digest → file on this worker
_CACHE: dict[str, list[Any]] = {}
_FILES: dict[str, Path] = {}
_TMP: list[Path] = []
_MAX_MASTERS = 4
_EXIT_HOOK: list[bool] = []
#: environment variable naming the scratch folder of a campaign's own LocalCluster
SCRATCH_ENV = "AXIR_SCRATCH"


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
    remove_extracted()  # the FMUs' extracted directories (orchestrator/archive.py cache)


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
    seed = spec.base_seed + index
    t0, c0 = time.perf_counter(), time.process_time()
    worker = _worker_name()
    result: dict[str, Any] = {"run": index, "seed": seed, "worker": worker, "status": "ok",
                              "error": "", "steps": 0, "data": None, "wall_s": 0.0,
                              "cpu_s": 0.0, "worker_losses": 0, "retries": 0}
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
            raise AxirError("run interrupted")
        result["data"] = rec.data.copy()
    except Exception as e:
        _drop(spec)
        msg = str(e) if isinstance(e, AxirError) else f"{type(e).__name__}: {e}"
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

    def setup(self, worker: Any) -> None:
        """On a worker of our own LocalCluster (``AXIR_SCRATCH`` set by the runner): every
        temp file of this worker process (FMU copies, extracted FMUs) goes into that
        folder, which the campaign removes even if this worker is killed."""
        scratch = os.environ.get(SCRATCH_ENV)
        if scratch and os.path.isdir(scratch):
            tempfile.tempdir = scratch

    def teardown(self, worker: Any) -> None:
        _close_all()
