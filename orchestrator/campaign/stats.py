"""Campaign statistics (pure numpy): RMS and mean errors vs time, the range-axis NEES with its
χ² band, per-run figures (see the package docstring)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .spec import (
    DEFAULT_COVARIANCE,
    DEFAULT_ERRORS,
    DEFAULT_MANEUVER,
    DEFAULT_VALID,
    CampaignSpec,
)


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


@dataclass
class CampaignResult:
    """What :func:`run_campaign` returns: the spec, every run's result (in run order), the
    aggregates of the successful ones and the campaign summary."""

    spec: CampaignSpec
    results: list[dict[str, Any]]
    aggregates: Aggregates
    summary: dict[str, Any]
    #: the output files written (when :func:`run_campaign` was given ``out_dir``)
    files: list[Path] = field(default_factory=list)

    @property
    def failed(self) -> list[dict[str, Any]]:
        return [r for r in self.results if r["status"] != "ok"]
