"""Seed 000 reproduction: α-β evolutive gains from acquisition to the manager's steady gains.

Runs the default ``closed-loop`` scenario (shortened to ``--duration``, 6.5 s by default)
through the four FMUs with orchestrator.run.run_scenario, recording every PRI step
(decimation 1). The FMUs are built from the working tree into a temporary directory unless
``--fmu-dir`` is given.

The gains the Tracker actually applied are *measured* from its outputs, not read from its
code: at an update n (``track.n`` grew by one) the α-β filter of seed 000 is
P = x(k−1) + T·v(k−1), x(k) = P + α·ν, v(k) = v(k−1) + (β/T)·ν with ν = ``innovation``, so

    α = Σ_axes (x(k) − P)·ν / Σ ν²,     β = T·Σ_axes (v(k) − v(k−1))·ν / Σ ν².

They are compared with the seed's evolutive law α(n) = 2(2n − 1)/(n(n + 1)),
β(n) = 6/(n(n + 1)) (seed 000 "Evolutive coefficients", SYSTEM.md) and with the steady gains
the RadarManager sends in confirmed mode (Kalata's tracking index; each gain hands over when
α(n) or β(n) falls below it). The track errors (range, 3-D position) are shown converging
next to the least-squares law σ_R·√α(n) (the variance of the end point of a least-squares
line through n equally spaced points with white noise σ_R is σ_R²·α(n)); σ_R is the standard
deviation of the reconstructed range measurements z = P + ν about the truth in confirmed mode
once the manager's Doppler centre follows the track (lock + 0.5 s). The measurement errors are
also tabulated per phase: they are biased and correlated, so the track error does not follow
the white-noise law (see seed000.md).

Outputs under ``reports/out/``: ``seed000_gains.png`` (α, β vs n, log-log),
``seed000_convergence.png`` (mode, gains and errors vs time), ``seed000.md`` and
``seed000.json``.

Usage: ``.venv/bin/python reports/seed000.py [--fmu-dir DIR] [--duration S] [--out DIR]``.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from common import (
    OUT,
    Recorded,
    fmt,
    fmu_directory,
    provenance,
    rms,
    run_recorded,
)

from axir.models.tracker import Tracker
from axir.orchestrator.campaign.spec import with_parameters
from axir.orchestrator.scenario import load_scenario

SCENARIO = "closed-loop"
DURATION = 6.5  # [s]: the default gains hand over ≈ 4.2 s (β) and ≈ 4.9 s (α) after lock
AXES = ("x", "y", "z")
RECORD = (
    *(f"TargetGenerator.truth.{a}" for a in AXES),
    *(f"TargetGenerator.truth.v{a}" for a in AXES),
    "TargetGenerator.truth.range", "TargetGenerator.truth.az", "TargetGenerator.truth.el",
    *(f"Tracker.track.{a}" for a in AXES),
    *(f"Tracker.track.v{a}" for a in AXES),
    *(f"Tracker.innovation.{a}" for a in AXES),
    "Tracker.track.n", "Tracker.track.range", "Tracker.track.az", "Tracker.track.el",
    "Tracker.coasting", "Tracker.track.valid", "Tracker.maneuver",
    "RadarManager.mode", "RadarManager.alpha", "RadarManager.beta", "RadarManager.pri",
    "RadarManager.tracking.index", "RadarManager.doppler.centre",
    "TargetGenerator.truth.doppler",
    "Pedestal.az", "Pedestal.el",
)
REL_TOL = 1e-6  # measured gain = law within this relative error (float64 reconstruction)


def evolutive(n: np.ndarray | int) -> tuple[np.ndarray, np.ndarray]:
    """Seed 000 evolutive gains: α(n) = 2(2n − 1)/(n(n + 1)), β(n) = 6/(n(n + 1))."""
    n = np.asarray(n, dtype=float)
    return 2.0 * (2.0 * n - 1.0) / (n * (n + 1.0)), 6.0 / (n * (n + 1.0))


@dataclass
class Gains:
    """Per α-β update (track.n grew by one): sample index, time, n and measured gains."""

    k: np.ndarray  # row index of the update
    t: np.ndarray  # [s]
    n: np.ndarray  # index n of the update (track.n after it)
    alpha: np.ndarray  # measured α
    beta: np.ndarray  # measured β
    alpha_ss: np.ndarray  # manager's steady α the Tracker received (previous step's output)
    beta_ss: np.ndarray
    z: np.ndarray  # (m, 3) reconstructed measurement z = P + ν [m]


def measured_gains(rec: Recorded) -> Gains:
    """The gains applied at each update, reconstructed from the recorded outputs (every step
    must be recorded: decimation 1)."""
    t = rec.t
    n = rec["Tracker.track.n"]
    x = np.stack([rec[f"Tracker.track.{a}"] for a in AXES], axis=1)
    v = np.stack([rec[f"Tracker.track.v{a}"] for a in AXES], axis=1)
    nu = np.stack([rec[f"Tracker.innovation.{a}"] for a in AXES], axis=1)
    step = np.diff(n)
    k = np.flatnonzero((step == 1) & (n[:-1] >= 1)) + 1  # an update at row k (not the init)
    T = t[k] - t[k - 1]
    P = x[k - 1] + v[k - 1] * T[:, None]  # seed 000: P = V3 + V5·T
    nn = np.sum(nu[k] ** 2, axis=1)
    ok = nn > 0.0
    k, T, P, nn = k[ok], T[ok], P[ok], nn[ok]
    alpha = np.sum((x[k] - P) * nu[k], axis=1) / nn  # OutP = P + α·V1
    beta = T * np.sum((v[k] - v[k - 1]) * nu[k], axis=1) / nn  # OutV = V5 + (β/T)·V1
    return Gains(k, t[k], n[k].astype(int), alpha, beta, rec["RadarManager.alpha"][k - 1],
                 rec["RadarManager.beta"][k - 1], P + nu[k])


def run(fmu_dir: Path, duration: float = DURATION) -> Recorded:
    """The closed-loop scenario, shortened, every step recorded, with seed 000's Tracker
    (``Tracker.SEED000``: its evolutive gains exactly; the defaults depart from them for a
    young track since session 19)."""
    sc = with_parameters(load_scenario(SCENARIO), {"Tracker": Tracker.SEED000})
    return run_recorded(sc, fmu_dir, duration=duration, record=RECORD, decimation=1)


def expected_gains(g: Gains) -> tuple[np.ndarray, np.ndarray]:
    """Gains the seed + SYSTEM.md schedule prescribe: the evolutive law until the manager's
    steady gain (when it sends one, > 0) is larger, per gain."""
    a_n, b_n = evolutive(g.n)
    a = np.where(g.alpha_ss > 0.0, np.maximum(a_n, g.alpha_ss), a_n)
    b = np.where(g.beta_ss > 0.0, np.maximum(b_n, g.beta_ss), b_n)
    return a, b


def _first(mask: np.ndarray) -> int | None:
    return int(np.argmax(mask)) if mask.any() else None


def _final(mask: np.ndarray) -> int | None:
    """Start of the run of True that ends the array (None if the array ends False)."""
    if not mask.size or not mask[-1]:
        return None
    off = np.flatnonzero(~mask)
    return int(off[-1]) + 1 if off.size else 0


def metrics(rec: Recorded, g: Gains) -> dict[str, Any]:
    """Measured numbers (see the module docstring)."""
    a_n, b_n = evolutive(g.n)
    a_exp, b_exp = expected_gains(g)
    ev_a = a_exp == a_n  # updates in the evolutive phase of each gain
    ev_b = b_exp == b_n
    rel_a = np.abs(g.alpha - a_exp) / a_exp
    rel_b = np.abs(g.beta - b_exp) / b_exp
    t = rec.t
    mode = rec["RadarManager.mode"]
    conf = mode == 2
    out: dict[str, Any] = {
        "scenario": SCENARIO, "duration_s": float(t[-1]), "steps": rec.summary.get("steps"),
        "wall_time_s": rec.summary.get("wall_time_s"),
        "us_per_step": rec.summary.get("us_per_step"),
        "lock_time_s": rec.summary.get("lock_time"),
        "updates": int(g.n.size),
        "n_max": int(g.n.max()) if g.n.size else 0,
    }
    if not g.n.size:
        return out
    k_init = int(np.argmax(rec["Tracker.track.n"] >= 1))
    t0 = float(t[k_init])  # first tentative measurement (n = 1)
    out["track_start_s"] = t0
    out["max_rel_err_alpha_evolutive"] = float(rel_a[ev_a].max()) if ev_a.any() else None
    out["max_rel_err_beta_evolutive"] = float(rel_b[ev_b].max()) if ev_b.any() else None
    out["max_rel_err_alpha_all"] = float(rel_a.max())
    out["max_rel_err_beta_all"] = float(rel_b.max())
    out["updates_matching_law"] = int(np.sum((rel_a < REL_TOL) & (rel_b < REL_TOL)))
    # the manager's steady gains in confirmed mode (last values) and the tracking index
    a_ss = rec["RadarManager.alpha"][conf]
    b_ss = rec["RadarManager.beta"][conf]
    out["alpha_ss"] = float(a_ss[-1]) if a_ss.size else None
    out["beta_ss"] = float(b_ss[-1]) if b_ss.size else None
    lam = rec["RadarManager.tracking.index"][conf]
    out["tracking_index"] = float(lam[-1]) if lam.size else None
    pri = rec["RadarManager.pri"][conf]
    out["pri_confirmed_s"] = float(pri[-1]) if pri.size else None
    for name, law, ss, meas in (("alpha", a_n, g.alpha_ss, g.alpha), ("beta", b_n, g.beta_ss,
                                                                        g.beta)):
        steady = (ss > 0.0) & (law < ss)  # the schedule prescribes the steady gain
        departs = np.abs(meas - law) / law > REL_TOL  # the measured gain is not the law
        # first handover: the first update where the steady gain is larger than the law
        i, j = _first(steady), _first(departs)
        out[f"handover_{name}_n_predicted"] = int(g.n[i]) if i is not None else None
        out[f"handover_{name}_n_measured"] = int(g.n[j]) if j is not None else None
        out[f"handover_{name}_t_measured_s"] = float(g.t[j]) if j is not None else None
        out[f"handover_{name}_after_track_start_s"] = (float(g.t[j]) - t0
                                                       if j is not None else None)
        # final handover: from the last update on the law to steady gains for good
        i, j = _final(steady), _final(departs)
        out[f"final_handover_{name}_n_predicted"] = int(g.n[i]) if i is not None else None
        out[f"final_handover_{name}_n_measured"] = int(g.n[j]) if j is not None else None
        out[f"final_handover_{name}_after_track_start_s"] = (float(g.t[j]) - t0
                                                             if j is not None else None)
    man = rec["Tracker.maneuver"] > 0.5
    out["maneuver_flag_s"] = float(np.sum(np.diff(t, prepend=t[0])[man]))
    out["last_maneuver_flag_s"] = float(t[np.flatnonzero(man)[-1]]) if man.any() else None
    # errors: range and 3-D position, in windows since the track start
    rng_err = rec["Tracker.track.range"] - rec["TargetGenerator.truth.range"]
    pos_err = np.linalg.norm(
        np.stack([rec[f"Tracker.track.{a}"] - rec[f"TargetGenerator.truth.{a}"] for a in AXES],
                 axis=1), axis=1)
    valid = rec["Tracker.track.valid"] > 0.5
    edges = [0.0, 0.01, 0.1, 0.5, 1.0, 2.0, 4.0, 6.0, math.inf]
    rows = []
    for lo, hi in itertools.pairwise(edges):
        sel = valid & (t - t0 >= lo) & (t - t0 < hi)
        if sel.any():
            rows.append({"from_s": lo, "to_s": hi if math.isfinite(hi) else float(t[-1] - t0),
                         "rms_range_m": rms(rng_err[sel]), "rms_position_m": rms(pos_err[sel])})
    out["error_windows"] = rows
    # range measurement errors, from the reconstructed measurements z = P + ν, per phase:
    # tentative; confirmed before / after the Doppler centre follows the track
    e = np.linalg.norm(g.z, axis=1) - rec["TargetGenerator.truth.range"][g.k]
    m_k = mode[g.k]
    f_off = np.abs(_fold(rec["TargetGenerator.truth.doppler"] - rec["RadarManager.doppler.centre"],
                         rec["RadarManager.pri"]))[g.k]
    t_conf = out["lock_time_s"] if out["lock_time_s"] is not None else math.inf
    phases = {"tentative": m_k == 1,
              "confirmed, t < lock + 0.5 s": (m_k == 2) & (g.t < t_conf + 0.5),
              "confirmed, t >= lock + 0.5 s": (m_k == 2) & (g.t >= t_conf + 0.5)}
    out["measurement_error"] = [
        {"phase": name, "updates": int(sel.sum()), "mean_m": float(np.mean(e[sel])),
         "std_m": float(np.std(e[sel])), "doppler_offset_hz": float(np.median(f_off[sel]))}
        for name, sel in phases.items() if sel.any()]
    late = phases["confirmed, t >= lock + 0.5 s"]
    out["sigma_range_meas_m"] = float(np.std(e[late])) if late.any() else float(np.std(e))
    return out


def _fold(f: np.ndarray, pri: np.ndarray) -> np.ndarray:
    """Frequency folded into [−PRF/2, PRF/2) [Hz] (models/radar/conventions.py convention)."""
    prf = 1.0 / pri
    return (f + 0.5 * prf) % prf - 0.5 * prf


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _log_subsample(n: np.ndarray, per_decade: int = 60) -> np.ndarray:
    """Indices of a sorted index array ``n`` thinned to ~per_decade points per decade."""
    if not n.size:
        return np.zeros(0, int)
    grid = np.unique(np.round(np.logspace(0, math.log10(n.max()),
                                          per_decade * max(1, int(math.log10(n.max())) + 1))))
    return np.unique(np.clip(np.searchsorted(n, grid), 0, n.size - 1))


def plot_gains(g: Gains, m: dict[str, Any], path: Path) -> None:
    """α(n), β(n): analytic law, measured, manager's steady gains (log-log)."""
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.5))
    nn = np.unique(np.round(np.logspace(0, math.log10(max(2, g.n.max())), 400)))
    nn = nn[nn >= 2]
    a_law, b_law = evolutive(nn)
    idx = _log_subsample(g.n)
    for ax, law, meas, ss, name in ((axs[0], a_law, g.alpha, g.alpha_ss, "α"),
                                    (axs[1], b_law, g.beta, g.beta_ss, "β")):
        ax.loglog(nn, law, "k-", lw=1.0, label=f"{name}(n), seed 000 law")
        ax.loglog(g.n[idx], meas[idx], "o", ms=3, mfc="none", color="tab:red",
                  label=f"{name} applied by Tracker.fmu (measured)")
        pos = ss[idx] > 0.0
        ax.loglog(g.n[idx][pos], ss[idx][pos], "--", color="tab:blue",
                  label=f"steady {name} from RadarManager.fmu")
        key = "alpha" if name == "α" else "beta"
        for pre, what, ls in (("", "first handover", ":"), ("final_", "final handover", "-.")):
            nh = m.get(f"{pre}handover_{key}_n_measured")
            if nh:
                th = fmt(m.get(f"{pre}handover_{key}_after_track_start_s"))
                ax.axvline(nh, color="0.5", ls=ls, lw=1.0, label=f"{what} n = {nh} ({th} s)")
        ax.set_xlabel("n (measurements in the track)")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle("seed 000: evolutive α-β gains in the closed loop (through the FMUs)",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_convergence(rec: Recorded, g: Gains, m: dict[str, Any], path: Path) -> None:
    """Mode, applied gains and track errors vs time."""
    plt = _plt()
    t = rec.t
    fig, axs = plt.subplots(4, 1, figsize=(9, 12), sharex=True,
                            gridspec_kw={"height_ratios": [1, 2, 2, 3]})
    axs[0].step(t, rec["RadarManager.mode"], where="post", color="k", label="mode")
    axs[0].fill_between(t, 0, 2 * rec["Tracker.maneuver"], step="post", color="tab:orange",
                        alpha=0.3, lw=0, label="Tracker maneuver flag")
    axs[0].set_yticks([0, 1, 2], ["acq.", "tent.", "conf."])
    axs[0].legend(fontsize=8, loc="center right")
    axs[0].set_title("seed 000: acquisition → tentative → confirmed, gains and track errors "
                     "(closed-loop scenario through the FMUs)", fontsize=10)
    ax = axs[1]
    idx = np.unique(np.concatenate((_log_subsample(g.n), np.arange(0, g.n.size, 50))))
    ax.semilogy(g.t[idx], g.alpha[idx], ".", ms=2, color="tab:red", label="α applied")
    ax.semilogy(g.t[idx], g.beta[idx], ".", ms=2, color="tab:purple", label="β applied")
    a_n, b_n = evolutive(g.n)
    ax.semilogy(g.t, a_n, "k-", lw=0.6, label="α(n), β(n) law")
    ax.semilogy(g.t, b_n, "k-", lw=0.6)
    for ss, c in ((g.alpha_ss, "tab:red"), (g.beta_ss, "tab:purple")):
        ax.semilogy(g.t, np.where(ss > 0, ss, np.nan), "--", color=c, lw=1.0)
    ax.set_ylabel("gain")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3, which="both")
    valid = rec["Tracker.track.valid"] > 0.5
    rng_err = np.where(valid, rec["Tracker.track.range"] - rec["TargetGenerator.truth.range"],
                       np.nan)
    ax = axs[2]
    z_err = np.linalg.norm(g.z, axis=1) - rec["TargetGenerator.truth.range"][g.k]
    ax.plot(g.t[idx], z_err[idx], ".", ms=2, color="0.6", label="range measurement z − truth")
    ax.plot(t, rng_err, color="tab:green", lw=0.8, label="track range − truth")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_ylim(-60, 60)
    ax.set_ylabel("range error [m]")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    ax = axs[3]
    pos_err = np.where(valid, np.linalg.norm(
        np.stack([rec[f"Tracker.track.{a}"] - rec[f"TargetGenerator.truth.{a}"] for a in AXES],
                 axis=1), axis=1), np.nan)
    ax.semilogy(t, pos_err, color="0.6", lw=0.5, label="|position error| (3-D)")
    ax.semilogy(t, np.abs(rng_err), color="tab:green", lw=0.5, label="|range error|")
    sig = m.get("sigma_range_meas_m")
    if sig:
        ax.semilogy(g.t, sig * np.sqrt(a_n), "k--", lw=1.0,
                    label=f"σ_R·√α(n), least-squares law for white noise (σ_R = {sig:.1f} m)")
    ax.set_ylabel("error [m]")
    ax.set_xlabel("time [s]")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def markdown(m: dict[str, Any], fmu_note: str) -> str:
    """seed000.md."""
    def g(key: str, d: int = 3) -> str:
        v = m.get(key)
        return "—" if v is None else (str(v) if isinstance(v, int) else fmt(v, d))

    def e(key: str) -> str:
        v = m.get(key)
        return "—" if v is None else f"{v:.3e}"

    lines = [
        "# Seed 000 (AXIR tracker) — α-β evolutive convergence in the closed loop",
        "",
        f"Generated by `reports/seed000.py`: the `closed-loop` scenario shortened to "
        f"{g('duration_s', 1)} s, every PRI recorded, through the four FMUs ({fmu_note}). "
        "Gains are measured from the Tracker's outputs (state, velocity, innovation), not read "
        "from its code. See docs/reproductions.md.",
        "",
        "| quantity | value |",
        "|---|---|",
        f"| lock (first confirmed) | {g('lock_time_s')} s |",
        f"| first tentative measurement (n = 1) | {g('track_start_s')} s |",
        f"| α-β updates recorded | {m.get('updates')} (n up to {m.get('n_max')}) |",
        f"| max relative error, measured vs α(n) = 2(2n−1)/(n(n+1)), evolutive phase | "
        f"{e('max_rel_err_alpha_evolutive')} |",
        f"| max relative error, measured vs β(n) = 6/(n(n+1)), evolutive phase | "
        f"{e('max_rel_err_beta_evolutive')} |",
        f"| max relative error vs max(law, steady), whole run (α / β) | "
        f"{e('max_rel_err_alpha_all')} / {e('max_rel_err_beta_all')} |",
        f"| manager's steady gains at the end (α_ss, β_ss) | "
        f"{e('alpha_ss')}, {e('beta_ss')} |",
        f"| tracking index Λ = σ_m T²/σ_n, confirmed PRI | {e('tracking_index')}, "
        f"{1e6 * (m.get('pri_confirmed_s') or math.nan):.2f} µs |",
        f"| first β handover: n measured / predicted (first β(n) < β_ss) | "
        f"{g('handover_beta_n_measured')} / {g('handover_beta_n_predicted')}, at "
        f"{g('handover_beta_after_track_start_s')} s after n = 1 |",
        f"| first α handover: n measured / predicted (first α(n) < α_ss) | "
        f"{g('handover_alpha_n_measured')} / {g('handover_alpha_n_predicted')}, at "
        f"{g('handover_alpha_after_track_start_s')} s after n = 1 |",
        f"| final β handover (steady for good): n measured / predicted | "
        f"{g('final_handover_beta_n_measured')} / {g('final_handover_beta_n_predicted')}, at "
        f"{g('final_handover_beta_after_track_start_s')} s after n = 1 |",
        f"| final α handover (steady for good): n measured / predicted | "
        f"{g('final_handover_alpha_n_measured')} / {g('final_handover_alpha_n_predicted')}, at "
        f"{g('final_handover_alpha_after_track_start_s')} s after n = 1 |",
        f"| Tracker maneuver flag raised (total time; last at) | {g('maneuver_flag_s')} s; "
        f"{g('last_maneuver_flag_s')} s |",
        f"| range measurement noise σ_R (std of z − truth, confirmed after lock + 0.5 s) | "
        f"{g('sigma_range_meas_m', 2)} m |",
        f"| wall time | {g('wall_time_s', 1)} s ({g('us_per_step', 0)} µs per PRI step) |",
        "",
        "Track errors after the first measurement (valid samples):",
        "",
        "| window after n = 1 [s] | RMS range error [m] | RMS 3-D position error [m] |",
        "|---|---|---|",
    ]
    for w in m.get("error_windows", []):
        lines.append(f"| {w['from_s']:g} – {w['to_s']:.2f} | {fmt(w['rms_range_m'])} | "
                     f"{fmt(w['rms_position_m'])} |")
    lines += [
        "",
        "Range measurements z = P + ν reconstructed from the outputs, error against truth "
        "(|Doppler offset|: folded truth Doppler minus the manager's Doppler centre):",
        "",
        "| phase | updates | mean [m] | std [m] | median Doppler offset [Hz] |",
        "|---|---|---|---|---|",
    ]
    for w in m.get("measurement_error", []):
        lines.append(f"| {w['phase']} | {w['updates']} | {fmt(w['mean_m'])} | "
                     f"{fmt(w['std_m'])} | {fmt(w['doppler_offset_hz'], 0)} |")
    lines += ["", "Figures: `seed000_gains.png`, `seed000_convergence.png`.", ""]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu-dir", type=Path, default=None,
                    help="directory with the four FMUs (default: build them into a temp dir)")
    ap.add_argument("--duration", type=float, default=DURATION,
                    help=f"simulated time [s] (default {DURATION})")
    ap.add_argument("--out", type=Path, default=OUT, help="output directory (reports/out)")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    with fmu_directory(args.fmu_dir) as fmu_dir:
        print(f"seed000: running {SCENARIO} for {args.duration} s through the FMUs ...",
              flush=True)
        rec = run(fmu_dir, args.duration)
    g = measured_gains(rec)
    m = metrics(rec, g)
    plot_gains(g, m, args.out / "seed000_gains.png")
    plot_convergence(rec, g, m, args.out / "seed000_convergence.png")
    note = ("FMUs from --fmu-dir" if args.fmu_dir else
            "FMUs built from the working tree into a temporary directory")
    note += "; " + provenance(rec.summary)
    (args.out / "seed000.md").write_text(markdown(m, note), encoding="utf-8")
    (args.out / "seed000.json").write_text(json.dumps(m, indent=2) + "\n", encoding="utf-8")
    print(json.dumps({k: v for k, v in m.items() if k != "error_windows"}, indent=1),
          flush=True)
    print(f"seed000: wrote {args.out}/seed000.md and the figures", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
