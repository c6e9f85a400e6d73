"""Seed 001 reproduction: DDRE range tracking of an aircraft and of the ship Absalon.

Two paths, both with the DDRE of models/ddre.py (seed 001 eqs. 1-11):

1. **Through the FMUs** (the shipped scenarios): the built-in scenarios ``aircraft`` (Fig. 1, no
   background subtraction), ``aircraft-bgs`` (Fig. 2, local background subtraction) and
   ``ship`` (Fig. 3) run through the four FMUs with orchestrator.run.run_scenario (the FMUs are
   built from the working tree into a temporary directory unless ``--fmu-dir`` is given). The
   DDRE runs inside the Tracker FMU on AXIR's SUM range profile: 16 bins of 75 m around the
   tracking gate (central Doppler filter in confirmed mode), so the paper's 24 m and 100 m
   windows become 1 and 2 bins (the smallest whole number of 75 m bins covering them).
2. **At the paper's resolution, models only** (``paper-*`` figures): the paper's MRS radar
   recorded a fine range profile over a wide window; AXIR cannot (75 m bins), so a documented
   synthetic profile model (:func:`paper_profiles`, assumptions below) feeds
   models.tracker.ddre.DDRE directly with the paper's exact windows (24 m = 6 bins and
   100 m = 25 bins of 4 m), an extended target (scatterers along its length) and a fixed
   recording window, so the raw range-time image looks like the paper's. Same trajectories,
   RCS and DDRE settings as the scenarios.

Outputs under ``reports/out/``: ``seed001_<name>.png`` (FMU path) and
``seed001_paper_<name>.png`` (paper resolution), each like the paper's figures — top, the raw
data |SUM|² or |A|² [dB] vs time and true range; middle, the detected range R(t) (eq. 7, red),
the damped track RS(t) (eq. 8), the "prediction" RT(t) (eq. 11, blue) and the truth; bottom,
the errors against truth with the analytic steady lags — plus
``seed001_aircraft_background.png`` (with / without local background subtraction, both paths),
``seed001.md`` and ``seed001.json`` (measured numbers).

Usage: ``.venv/bin/python reports/seed001.py [--fmu-dir DIR] [--duration S] [--out DIR]``.

Metrics (all against the truth range; the centre of the target in the paper-resolution path):

- ``rms_measured``: RMS of R(t) − truth (confirmed samples once the DDRE has a track);
- after convergence (t ≥ first DDRE detection + 5τ): mean and RMS of RS − truth and of
  RT − truth, and their analytic means. For a target at constant range rate ṙ, eq. (8)
  updated every Δt lags its input by L = Δt·a/(1 − a) ≈ τ − Δt/2 (a = e^(−Δt/τ), eq. 10), so
  in steady state RS − truth = −ṙ·L; the forward shift of models/ddre.py ("extrapolate",
  RT = RS + t_pred·V_S with V_S → ṙ) gives RT − truth = −ṙ·(L − t_pred). ``rms_noise``: RMS of
  RS minus eq. (8) applied to the truth range itself (the lag taken out: what the
  measurement noise leaves).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from common import OUT, fmt, fmu_directory, provenance, rms, run_recorded

from axir.models.radar.trajectory import trajectory_from_spec
from axir.models.tracker.ddre import DDRE

SCENARIOS = ("aircraft", "aircraft-bgs", "ship")
FIGURE_OF = {"aircraft": "Fig. 1", "aircraft-bgs": "Fig. 2", "ship": "Fig. 3",
             "ship-nocut": "Fig. 3 without the velocity cut"}
BIN_M = 75.0  # AXIR range bin [m] (models/radar/conventions.py)
SUM_BINS = [f"Tracker.sum[{r},2]" for r in range(1, 17)]
CONVERGED_MEMORIES = 5.0  # t ≥ t_first + 5τ: the initial transient is e^−5 ≈ 0.7 %


@dataclass
class Tracks:
    """DDRE outputs of one run against truth, plus the raw range-time image.

    Arrays are per recorded sample; ``meas``/``smooth``/``pred`` are NaN before the DDRE has a
    track. The image is ``img_db`` (n, m) with cell edges ``img_t`` and ``img_r`` (1-D, or 2-D
    of shape (n + 1, m + 1) when the window moves).
    """

    name: str
    path: str  # "fmu" or "paper"
    t: np.ndarray
    truth: np.ndarray
    rdot: np.ndarray
    meas: np.ndarray
    smooth: np.ndarray
    pred: np.ndarray
    valid: np.ndarray
    conf: np.ndarray  # samples where the radar holds a confirmed track (FMU) / all (paper)
    track: np.ndarray | None  # α-β track range (FMU path)
    img_t: np.ndarray
    img_r: np.ndarray
    img_db: np.ndarray
    window_m: float
    window_bins: int
    bin_m: float
    background: str
    threshold: float
    memory: float
    velocity_cut: float
    t_pred: float
    update_dt: float  # [s] interval between DDRE updates (PRI, or profile interval)
    info: dict[str, Any] = field(default_factory=dict)


# ------------------------------------------------------------------------------ FMU path
def _edges(t: np.ndarray) -> np.ndarray:
    """Cell edges around sample times (midpoints, half a step outside the ends)."""
    mid = 0.5 * (t[1:] + t[:-1])
    first = t[0] - (mid[0] - t[0]) if t.size > 1 else t[0] - 0.5
    last = t[-1] + (t[-1] - mid[-1]) if t.size > 1 else t[-1] + 0.5
    return np.concatenate(([first], mid, [last]))


def run_fmu(name: str, fmu_dir: Path, duration: float | None = None) -> Tracks:
    """Run the built-in scenario ``name`` through the FMUs (optionally shortened [s])."""
    rec = run_recorded(name, fmu_dir, duration=duration)
    p = rec.scenario.units["Tracker"]["parameters"]
    k = rec.t > 0.0  # the sample at t = 0 holds the outputs before the first step
    col = {ref: v[k] for ref, v in rec.columns.items()}
    t = col["time"]
    has = col["Tracker.ddre.smoothed"] != 0.0  # the Tracker outputs 0.0 until a DDRE track
    mode = col["RadarManager.mode"]

    def tracked(ref: str) -> np.ndarray:
        return np.where(has, col[ref], np.nan)

    # raw data: |SUM|² of the 16 bins (central filter), bin r at its true range
    s = np.stack([col[v] for v in SUM_BINS], axis=1)
    img = 10.0 * np.log10(np.maximum(s * s, 1e-12))
    img[mode < 1] = np.nan  # acquisition search windows jump around: not shown
    start = col["Tracker.gate.start"] + col["RadarManager.range.offset"]
    te = _edges(t)
    start_e = np.interp(te, t, start)
    img_r = start_e[:, None] + BIN_M * (np.arange(17)[None, :] - 0.5)
    img_t = np.repeat(te[:, None], 17, axis=1)
    window = int(p["ddre_window"])
    return Tracks(
        name=name, path="fmu", t=t, truth=col["TargetGenerator.truth.range"],
        rdot=col["TargetGenerator.truth.range_rate"], meas=tracked("Tracker.ddre.range"),
        smooth=tracked("Tracker.ddre.smoothed"), pred=tracked("Tracker.ddre.predicted"),
        valid=col["Tracker.ddre.valid"] > 0.5, conf=mode == 2,
        track=np.where(mode == 2, col["Tracker.track.range"], np.nan),
        img_t=img_t, img_r=img_r, img_db=np.ma.masked_invalid(img),
        window_m=window * BIN_M, window_bins=window, bin_m=BIN_M,
        background=str(p.get("ddre_background", "none")),
        threshold=float(p.get("ddre_threshold", 0.0)), memory=float(p.get("ddre_memory", 0.5)),
        velocity_cut=float(p.get("ddre_velocity_cut", 200.0)),
        t_pred=float(p.get("ddre_t_pred", 0.1)),
        update_dt=float(np.median(col["RadarManager.pri"][mode == 2])) if (mode == 2).any()
        else float(np.median(col["RadarManager.pri"])),
        info={"steps": rec.summary.get("steps"), "wall_time_s": rec.summary.get("wall_time_s"),
              "us_per_step": rec.summary.get("us_per_step"),
              "lock_time_s": rec.summary.get("lock_time"),
              "time_confirmed_s": rec.summary.get("time_in_mode", {}).get("confirmed"),
              "trajectory": rec.scenario.units["TargetGenerator"]["parameters"]["trajectory"],
              "provenance": provenance(rec.summary)},
    )


# ------------------------------------------------------------------- paper-resolution path
@dataclass(frozen=True)
class PaperCase:
    """One paper-resolution case (all values assumptions except the DDRE settings, which are
    the paper's; trajectories and RCS are those of the FMU scenarios)."""

    trajectory: str  # JSON spec (models/radar/trajectory.py), the scenario's
    rcs: float  # [m²] mean, shared by the scatterers
    length: float  # [m] target extent along the line of sight
    scatterers: int
    cnr_db: float | None  # clutter-to-noise ratio per 4 m cell [dB] (None: no clutter)
    duration: float  # [s]
    window_m: float  # seed 001
    background: str  # seed 001
    rcs_threshold: float  # [m²] seed 001
    memory: float  # [s] seed 001
    velocity_cut: float  # [m/s] seed 001
    t_pred: float = 0.1  # [s] seed 001


PAPER_BIN_M = 4.0  # assumption: 4 m bins, so 24 m = 6 bins and 100 m = 25 bins exactly
PAPER_DT = 0.01  # [s] assumption: one range profile every 10 ms
PAPER_SNR_REF = 100.0  # SNR of 1 m² at 10 km per bin and profile (TargetGenerator default, 20 dB)
PAPER_SNR_REF_RANGE = 10_000.0  # [m]
IMAGE_COLUMNS = 400  # raw-image columns (mean power over groups of profiles)
_AIR_TRAJ = '{"type": "cv", "position": [0.0, 6000.0, 500.0], "velocity": [0.0, -150.0, 0.0]}'
_SHIP_TRAJ = ('{"type": "cv", "position": [3000.0, 7000.0, -10.0], '
              '"velocity": [-0.98480, -2.29786, 0.0]}')
_SHIP_CNR = 25.0 - 10.0 * math.log10(75.0 / PAPER_BIN_M)  # 25 dB per 75 m cell → 4 m cells
PAPER_CASES = {
    # aircraft: 20 m long (assumption: a business jet seen nose-on, 5 scatterers)
    "aircraft": PaperCase(_AIR_TRAJ, 5.0, 20.0, 5, None, 8.0, 24.0, "none", 0.1, 0.5, 200.0),
    "aircraft-bgs": PaperCase(_AIR_TRAJ, 5.0, 20.0, 5, None, 8.0, 24.0, "local", 0.1, 0.5,
                              200.0),
    # Absalon: 137 m bow-on, 15 scatterers; sea clutter as ship.toml, scaled to the cell
    "ship": PaperCase(_SHIP_TRAJ, 8.0e4, 137.0, 15, _SHIP_CNR, 60.0, 100.0, "none", 300.0, 3.0,
                      3.0),
    # the same without the velocity cut: shows what the 3 m/s cut does to a noisy centroid
    "ship-nocut": PaperCase(_SHIP_TRAJ, 8.0e4, 137.0, 15, _SHIP_CNR, 60.0, 100.0, "none", 300.0,
                            3.0, 0.0),
}


def paper_profiles(case: PaperCase, seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                            np.ndarray, np.ndarray]:
    """Synthetic fine range profiles (assumptions, the seed gives none of this).

    Every ``PAPER_DT`` a profile of complex samples on a fixed grid of ``PAPER_BIN_M`` bins
    covering the whole trajectory: ``scatterers`` points equally spaced over ``length`` along
    the line of sight around the trajectory range (radial motion: the target is seen nose- or
    bow-on), each with mean RCS rcs/N and an independent CN(0, 1) amplitude per profile
    (Swerling-2-like), radar-equation amplitude a² = SNR_ref·σ·(R_ref/R)⁴, triangular
    matched-filter response of half-width one bin, thermal noise CN(0, 1) per bin and, for the
    ship, white sea clutter CN(0, CNR) per bin.

    Returns (t [s], truth range [m] (target centre), range rate [m/s], grid [m] (bin centres),
    profiles (n, m) complex).
    """
    rng = np.random.default_rng(seed)
    traj = trajectory_from_spec(case.trajectory)
    t = np.arange(1, round(case.duration / PAPER_DT) + 1) * PAPER_DT
    p, v, _ = traj.state(t)
    rc = np.linalg.norm(p, axis=1)
    rdot = np.sum(p * v, axis=1) / rc
    lo = float(rc.min()) - case.length - 150.0
    hi = float(rc.max()) + case.length + 150.0
    grid = np.arange(math.floor(lo / PAPER_BIN_M), math.ceil(hi / PAPER_BIN_M) + 1) * PAPER_BIN_M
    offs = np.linspace(-0.5 * case.length, 0.5 * case.length, case.scatterers)
    rs = rc[:, None] + offs[None, :]  # (n, N) scatterer ranges
    amp = np.sqrt(PAPER_SNR_REF * case.rcs / case.scatterers) * (PAPER_SNR_REF_RANGE / rs) ** 2
    fl = (rng.standard_normal(rs.shape) + 1j * rng.standard_normal(rs.shape)) * math.sqrt(0.5)
    n, m = t.size, grid.size
    prof = (rng.standard_normal((n, m)) + 1j * rng.standard_normal((n, m))) * math.sqrt(0.5)
    if case.cnr_db is not None:
        cnr = 10.0 ** (case.cnr_db / 10.0)
        prof += (rng.standard_normal((n, m)) + 1j * rng.standard_normal((n, m))) * math.sqrt(
            0.5 * cnr)
    for j in range(case.scatterers):  # triangular response: only the two nearest bins
        q = (rs[:, j] - grid[0]) / PAPER_BIN_M
        k0 = np.floor(q).astype(int)
        w1 = q - k0
        rows = np.arange(n)
        c = amp[:, j] * fl[:, j]
        ok0 = (k0 >= 0) & (k0 < m)
        ok1 = (k0 + 1 >= 0) & (k0 + 1 < m)
        prof[rows[ok0], k0[ok0]] += (c * (1.0 - w1))[ok0]
        prof[rows[ok1], k0[ok1] + 1] += (c * w1)[ok1]
    return t, rc, rdot, grid, prof


def run_paper(name: str, duration: float | None = None, seed: int = 1) -> Tracks:
    """The paper-resolution case ``name`` through models.tracker.ddre.DDRE directly."""
    case = PAPER_CASES[name]
    if duration is not None:
        case = PaperCase(**{**case.__dict__, "duration": float(duration)})
    t, truth, rdot, grid, prof = paper_profiles(case, seed)
    r0 = float(np.linalg.norm(trajectory_from_spec(case.trajectory).position(0.0)))
    # cross-section threshold → S0: a point scatterer of σ_th centred on a bin at the start
    # range R0 has |A|² = SNR_ref·σ_th·(R_ref/R0)⁴ (same convention as the FMU scenarios)
    thr = PAPER_SNR_REF * case.rcs_threshold * (PAPER_SNR_REF_RANGE / r0) ** 4
    window = round(case.window_m / PAPER_BIN_M)
    ddre = DDRE(window=window, bin_size=PAPER_BIN_M, range_start=float(grid[0]),
                background=case.background, threshold=thr, memory=case.memory,
                velocity_cut=case.velocity_cut, t_pred=case.t_pred)
    out = np.array([tuple(ddre.update(prof[k], float(t[k]))[:5]) for k in range(t.size)])
    meas, smooth, pred = out[:, 0], out[:, 1], out[:, 2]
    # image: mean power over groups of profiles (at most IMAGE_COLUMNS columns, small PNGs)
    g = max(1, -(-t.size // IMAGE_COLUMNS))
    n_img = t.size // g
    pw = (np.abs(prof[: n_img * g]) ** 2).reshape(n_img, g, -1).mean(axis=1)
    img = 10.0 * np.log10(np.maximum(pw, 1e-12))
    img_t = np.concatenate(([t[0] - PAPER_DT], t[g - 1 : n_img * g : g]))
    return Tracks(
        name=name, path="paper", t=t, truth=truth, rdot=rdot, meas=meas, smooth=smooth,
        pred=pred, valid=out[:, 4] > 0.5, conf=np.ones(t.size, bool), track=None,
        img_t=img_t, img_r=np.concatenate((grid - 0.5 * PAPER_BIN_M,
                                               [grid[-1] + 0.5 * PAPER_BIN_M])),
        img_db=img, window_m=window * PAPER_BIN_M, window_bins=window, bin_m=PAPER_BIN_M,
        background=case.background, threshold=thr, memory=case.memory,
        velocity_cut=case.velocity_cut, t_pred=case.t_pred, update_dt=PAPER_DT,
        info={"length_m": case.length, "scatterers": case.scatterers, "rcs_m2": case.rcs,
              "cnr_db_per_bin": case.cnr_db, "profile_interval_s": PAPER_DT,
              "bins": int(grid.size)},
    )


# ---------------------------------------------------------------------------- metrics
def damped(t: np.ndarray, x: np.ndarray, tau: float) -> np.ndarray:
    """Seed 001 eqs. (8), (10) applied to samples x(t): RS_k = a_k RS_(k−1) + (1 − a_k) x_k,
    a_k = exp(−(t_k − t_(k−1))/τ), started at x_0 (reference filter of the noise metric)."""
    out = np.empty(x.shape, dtype=float)
    out[0] = x[0]
    a = np.exp(-np.diff(t) / tau)
    for k in range(1, x.size):
        out[k] = a[k - 1] * out[k - 1] + (1.0 - a[k - 1]) * x[k]
    return out


def ema_lag_time(tau: float, dt: float) -> float:
    """Time lag [s] of eq. (8) on a ramp sampled every dt [s]: dt·a/(1 − a), a = e^(−dt/τ)
    (eq. 10) — τ − dt/2 + O(dt²/τ). A ramp x_k = v·k·dt in, RS_k → x_k − v·lag out."""
    a = math.exp(-dt / tau)
    return dt * a / (1.0 - a)


def _mean(x: np.ndarray) -> float:
    x = x[np.isfinite(x)]
    return float(np.mean(x)) if x.size else math.nan


def metrics(tr: Tracks) -> dict[str, Any]:
    """Measured numbers of one run (see the module docstring)."""
    t = tr.t
    has = np.isfinite(tr.smooth)
    out: dict[str, Any] = {
        "scenario": tr.name, "path": tr.path, "duration_s": float(t[-1]),
        "window_bins": tr.window_bins, "bin_m": tr.bin_m, "window_m": tr.window_m,
        "background": tr.background, "threshold_s0": tr.threshold, "memory_s": tr.memory,
        "velocity_cut_m_s": tr.velocity_cut, "t_pred_s": tr.t_pred, **tr.info,
    }
    if not has.any():
        out["ddre_track"] = False
        return out
    k0 = int(np.argmax(has))
    t_first = float(t[k0])
    sel = tr.conf & has
    conv = sel & (t >= t_first + CONVERGED_MEMORIES * tr.memory)
    ref = np.full(t.shape, np.nan)
    ref[k0:] = damped(t[k0:], tr.truth[k0:], tr.memory)
    rd = _mean(tr.rdot[conv])
    lag = ema_lag_time(tr.memory, tr.update_dt)
    out.update({
        "ddre_track": True,
        "first_ddre_track_s": t_first,
        "detection_rate": float(np.mean(tr.valid[sel])) if sel.any() else math.nan,
        "rms_measured_m": rms((tr.meas - tr.truth)[sel]),
        "mean_measured_m": _mean((tr.meas - tr.truth)[sel]),
        "rms_track_m": rms((tr.track - tr.truth)[tr.conf]) if tr.track is not None else None,
        "converged_from_s": t_first + CONVERGED_MEMORIES * tr.memory,
        "mean_range_rate_m_s": rd,
        "mean_smoothed_m": _mean((tr.smooth - tr.truth)[conv]),
        "rms_smoothed_m": rms((tr.smooth - tr.truth)[conv]),
        "lag_smoothed_theory_m": -rd * lag,
        "mean_predicted_m": _mean((tr.pred - tr.truth)[conv]),
        "rms_predicted_m": rms((tr.pred - tr.truth)[conv]),
        "lag_predicted_theory_m": -rd * (lag - tr.t_pred),
        "rms_noise_m": rms((tr.smooth - ref)[conv]),
    })
    return out


# ---------------------------------------------------------------------------- figures
def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_tracks(tr: Tracks, path: Path) -> None:
    """The paper-like figure of one run (raw data, tracks, errors)."""
    plt = _plt()
    t = tr.t
    fig, axs = plt.subplots(3, 1, figsize=(9, 10), sharex=True,
                            gridspec_kw={"height_ratios": [3, 3, 2]})
    ax = axs[0]
    finite = np.ma.compressed(np.ma.masked_invalid(tr.img_db))
    vmax = float(np.percentile(finite, 99.8)) if finite.size else 0.0
    # colour floor at the median (the noise floor): smooth background, small PNG files
    vmin = max(vmax - 50.0, float(np.median(finite))) if finite.size else vmax - 50.0
    c = tr.img_db.T if tr.img_t.ndim == 1 else tr.img_db  # 1-D edges: C is (range, time)
    mesh = ax.pcolormesh(tr.img_t, tr.img_r, c, shading="flat", cmap="viridis",
                         vmin=vmin, vmax=vmax, rasterized=True)
    fig.colorbar(mesh, ax=ax, label="power [dB]", pad=0.01)
    ax.plot(t, tr.truth, "w--", lw=0.7, label="truth (target centre)")
    lo, hi = float(np.min(tr.truth)), float(np.max(tr.truth))
    margin = max(6 * BIN_M, 0.2 * (hi - lo))
    ax.set_ylim(lo - margin, hi + margin)
    ax.set_ylabel("range [m]")
    what = ("|SUM|² of AXIR's 16 range bins (75 m), central Doppler filter, through the FMUs"
            if tr.path == "fmu" else
            f"|A|² of {tr.bin_m:g} m bins, synthetic extended target, models only")
    ax.set_title(f"{tr.name} (seed 001 {FIGURE_OF.get(tr.name, '')}), raw data:\n{what}",
                 fontsize=10)
    ax.legend(loc="upper right", fontsize=8)
    ax = axs[1]
    ax.plot(t, tr.truth, "k-", lw=1.0, label="truth")
    ax.plot(t, tr.meas, "r-", lw=0.6, label=f"R(t) detected, {tr.window_m:g} m window "
            f"({tr.background} background)")
    ax.plot(t, tr.smooth, "c-", lw=0.8, label="RS(t) damped (eq. 8)")
    ax.plot(t, tr.pred, "b-", lw=1.2, label=f"RT(t) prediction: τ = {tr.memory:g} s, "
            f"{tr.velocity_cut:g} m/s cut, shift {tr.t_pred:g} s")
    ax.set_ylabel("range [m]")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    ax = axs[2]
    ax.plot(t, tr.meas - tr.truth, "r-", lw=0.4, label="R − truth")
    ax.plot(t, tr.smooth - tr.truth, "c-", lw=0.8, label="RS − truth")
    ax.plot(t, tr.pred - tr.truth, "b-", lw=1.0, label="RT − truth")
    if tr.track is not None:
        ax.plot(t, tr.track - tr.truth, color="0.5", lw=0.5, label="α-β track − truth")
    ax.plot(t, -tr.rdot * tr.memory, "c:", lw=1.0, label="−ṙτ (theory)")
    ax.plot(t, -tr.rdot * (tr.memory - tr.t_pred), "b:", lw=1.0,
            label="−ṙ(τ − t_pred) (theory)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("error [m]")
    ax.legend(loc="best", fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_background(pairs: list[tuple[Tracks, Tracks]], path: Path) -> None:
    """Detected-range error without / with local background subtraction, one panel per path."""
    plt = _plt()
    fig, axs = plt.subplots(len(pairs), 1, figsize=(9, 3.5 * len(pairs)), squeeze=False)
    for ax, (a, b) in zip(axs[:, 0], pairs, strict=True):
        for tr, color in ((a, "r"), (b, "m")):
            m = metrics(tr)
            ax.plot(tr.t, tr.meas - tr.truth, color=color, lw=0.5,
                    label=f"{tr.name}: {tr.background} background "
                          f"(RMS {fmt(m.get('rms_measured_m'))} m)")
        if a.t.shape == b.t.shape and np.array_equal(a.t, b.t):
            ax.plot(a.t, b.meas - a.meas, "k-", lw=0.5, label="difference local − none")
        ax.set_ylabel("R(t) − truth [m]")
        ax.set_title(("through the FMUs (AXIR, 1 bin of 75 m)" if a.path == "fmu" else
                      f"paper resolution ({a.window_bins} bins of {a.bin_m:g} m)"), fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axs[-1, 0].set_xlabel("time [s]")
    fig.suptitle("seed 001 Figs. 1-2: detected range without / with local background "
                 "subtraction", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# ---------------------------------------------------------------------------- summary
def markdown(results: dict[str, dict[str, Any]], fmu_note: str) -> str:
    """seed001.md: one table row per run."""
    lines = [
        "# Seed 001 (DDRE range tracker) — reproduction",
        "",
        "Generated by `reports/seed001.py`: rows `fmu` run the shipped scenarios through the "
        f"four FMUs ({fmu_note}); rows `paper` run models.tracker.ddre.DDRE directly on synthetic "
        "fine range profiles of an extended target at the paper's windows. Choices and "
        "differences from the paper: docs/reproductions.md.",
        "",
        "| run | path | window | background | τ [s] | cut [m/s] | t_pred [s] | detections | "
        "RMS R−truth [m] | mean RS−truth [m] (theory −ṙL) | mean RT−truth [m] "
        "(theory −ṙ(L−t_pred)) | "
        "RMS RT−truth [m] | RMS noise [m] | RMS α-β track [m] | wall [s] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for key, m in results.items():
        if not m.get("ddre_track"):
            lines.append(f"| {key} | {m['path']} | no DDRE track |" + " |" * 12)
            continue
        lines.append(
            f"| {m['scenario']} | {m['path']} | {m['window_bins']} × {m['bin_m']:g} m | "
            f"{m['background']} | {m['memory_s']:g} | {m['velocity_cut_m_s']:g} | "
            f"{m['t_pred_s']:g} | {100 * m['detection_rate']:.1f} % | "
            f"{fmt(m['rms_measured_m'])} | {fmt(m['mean_smoothed_m'])} "
            f"({fmt(m['lag_smoothed_theory_m'])}) | {fmt(m['mean_predicted_m'])} "
            f"({fmt(m['lag_predicted_theory_m'])}) | {fmt(m['rms_predicted_m'])} | "
            f"{fmt(m['rms_noise_m'])} | {fmt(m.get('rms_track_m'))} | "
            f"{fmt(m.get('wall_time_s'), 0)} |"
        )
    lines += [
        "",
        "Steady-state columns: t ≥ first DDRE detection + 5τ. 'detections': fraction of "
        "confirmed-mode samples whose S0(r_max) passed the threshold (else the previous range "
        "is reused). 'RMS noise': RS minus eq. (8) applied to the truth range (the lag "
        "removed). L = Δt·a/(1 − a) ≈ τ − Δt/2 is the lag of eq. (8) updated every Δt (PRI "
        "for the FMU runs, 10 ms for the paper-resolution runs). FMU runs: lock (first "
        "confirmed) at "
        + ", ".join(f"{m['scenario']} {fmt(m.get('lock_time_s'), 3)} s"
                    for m in results.values() if m["path"] == "fmu") + ".",
        "",
        "Figures: " + ", ".join(
            f"`seed001_{'paper_' if m['path'] == 'paper' else ''}{m['scenario']}.png`"
            for m in results.values()) + ", `seed001_aircraft_background.png`.",
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu-dir", type=Path, default=None,
                    help="directory with the four FMUs (default: build them into a temp dir)")
    ap.add_argument("--duration", type=float, default=None,
                    help="shorten every run to this many seconds (default: as shipped)")
    ap.add_argument("--out", type=Path, default=OUT, help="output directory (reports/out)")
    ap.add_argument("--paper-only", action="store_true",
                    help="only the paper-resolution runs (no FMUs)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    fmu: dict[str, Tracks] = {}
    paper: dict[str, Tracks] = {}
    results: dict[str, dict[str, Any]] = {}
    for name in PAPER_CASES:
        paper[name] = tr = run_paper(name, args.duration)
        results[f"paper:{name}"] = metrics(tr)
        plot_tracks(tr, args.out / f"seed001_paper_{name}.png")
    if not args.paper_only:
        with fmu_directory(args.fmu_dir) as fmu_dir:
            for name in SCENARIOS:
                print(f"seed001: running {name} through the FMUs ...", flush=True)
                fmu[name] = tr = run_fmu(name, fmu_dir, args.duration)
                results[f"fmu:{name}"] = metrics(tr)
                plot_tracks(tr, args.out / f"seed001_{name}.png")
    pairs = [(d["aircraft"], d["aircraft-bgs"]) for d in (fmu, paper) if d]
    plot_background(pairs, args.out / "seed001_aircraft_background.png")
    note = ("FMUs from --fmu-dir" if args.fmu_dir else
            "FMUs built from the working tree into a temporary directory")
    note += "; " + (fmu["aircraft"].info["provenance"] if "aircraft" in fmu else provenance())
    (args.out / "seed001.md").write_text(markdown(results, note), encoding="utf-8")
    (args.out / "seed001.json").write_text(json.dumps(results, indent=2) + "\n",
                                           encoding="utf-8")
    for key, m in results.items():
        print(f"  {key}: RMS R-truth {fmt(m.get('rms_measured_m'))} m, mean RT-truth "
              f"{fmt(m.get('mean_predicted_m'))} m (theory {fmt(m.get('lag_predicted_theory_m'))}"
              f"), RMS noise {fmt(m.get('rms_noise_m'))} m", flush=True)
    print(f"seed001: wrote {args.out}/seed001.md and the figures", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
