"""Monte Carlo campaigns: N seeded co-simulations of one scenario on Dask distributed.

Modules: :mod:`.spec` (what a campaign is), :mod:`.worker` (one run on a worker),
:mod:`.stats` (statistics), :mod:`.runner` (Dask scheduling), :mod:`.outputs` (files),
:mod:`.cli` (``axir montecarlo``).

``axir montecarlo SCENARIO --runs N [--workers K | --scheduler ADDRESS] [--out DIR]
[--seed BASE] [--duration S] [--set UNIT.PARAM=VALUE ...]`` (see docs/campaigns.md).

How a campaign runs
-------------------
- Run i is the scenario with base seed ``BASE + i`` (default BASE: the scenario's seed): every
  unit with a ``seed`` parameter gets ``unit_seed(BASE + i, unit)`` exactly as ``axir run
  SCENARIO --seed BASE+i`` would (:func:`axir.orchestrator.run.seeded_parameters`), so run i of
  a campaign is bit-identical to that single run, whichever worker ran it and whatever it ran
  before (tested).
- Each run is a full co-simulation through the FMUs (:class:`axir.orchestrator.master.Master`).
  The FMU files are read once by the client and sent once to each worker (``Client.scatter``,
  broadcast); a worker writes them to its own temporary directory, extracts and instantiates
  them once per scenario and keeps the loaded :class:`~axir.orchestrator.master.Master` in a
  per-process cache (:data:`.worker._CACHE`), never pickled. Every later run on that worker
  re-initialises the same instances: ``fmi2Reset`` (pythonfmu 0.7.0 rebuilds the Python slave
  object inside the loaded library; bit-identical to a fresh instantiation, tested), then
  parameters incl. the run's seeds, initialization mode, run. A run that fails drops its cached
  master (the instances are freed; the next run on that worker loads afresh).
- Scheduling: a ``LocalCluster`` of K worker processes, one thread each (pythonfmu slaves
  share one interpreter per process: threads would only contend for the GIL), or an existing
  cluster by scheduler address (its workers need the same ``axir`` installed). ``workers=0``
  (API only) runs serially in this process without Dask, for debugging.
- The worker processes hold pythonfmu libraries: :class:`FmuCachePlugin` frees every instance
  and library at worker teardown and then ends the process with ``os._exit`` at interpreter
  exit (the pythonfmu finalization heap-corruption trap, see axir.orchestrator.cli.main).

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

from .outputs import plot_campaign, write_outputs
from .runner import LOCAL_CLUSTER_QUIET, run_campaign
from .spec import (
    DEFAULT_COVARIANCE,
    DEFAULT_ERRORS,
    CampaignSpec,
    parse_assignment,
    prepare,
    record_list,
    with_parameters,
)
from .stats import Aggregates, CampaignResult, aggregate, nees2, nees_band
from .worker import FmuCachePlugin, simulate_run

__all__ = [
    "DEFAULT_COVARIANCE", "DEFAULT_ERRORS", "LOCAL_CLUSTER_QUIET", "Aggregates",
    "CampaignResult", "CampaignSpec", "FmuCachePlugin", "aggregate", "nees2", "nees_band",
    "parse_assignment", "plot_campaign", "prepare", "record_list", "run_campaign",
    "simulate_run", "with_parameters", "write_outputs",
]
