"""Campaign outputs: ``aggregates.csv``, ``runs.csv``, ``campaign.json``, ``campaign.png``."""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..outdir import write_json_atomic
from .spec import ERROR_UNITS
from .stats import CampaignResult

#: the files a campaign writes into its output folder (cleared before the next campaign there)
CAMPAIGN_FILES = ("aggregates.csv", "runs.csv", "campaign.json", "campaign.png")


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
                    "worker_losses", "retries", *metric_keys, "error"])
        for r in result.results:
            m = per.get(r["run"], {})
            w.writerow([r["run"], r["seed"], r["status"], r["worker"], r["steps"],
                        f"{r['wall_s']:.4f}", f"{r.get('cpu_s', 0.0):.4f}",
                        _cell(r.get("worker_losses", 0)), _cell(r.get("retries", 0)),
                        *(_cell(m.get(k)) for k in metric_keys), r["error"]])
    write_json_atomic(files[2], result.summary)
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
