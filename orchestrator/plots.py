"""PNG plots of a recorded run (matplotlib, Agg backend), drawn for a radar engineer:

- ``errors.png`` (time axis shared): the mode timeline; the range error against the filter's
  ±1σ (√P_rr); the angle errors (cross-elevation az·cos el, and el) against a ±1σ band; the
  antenna pointing error against the 3 dB beam edge (θ3/2); the Doppler-centre error (folded
  into ±PRF/2, as the filters see it) against half the filter spacing;
- ``ascope.png``: the range-Doppler picture at lock: SUM per range bin for the 3 Doppler
  filters (A-scope, dB) and the 16 × 3 map, with the target's true range;
- ``trajectory.png``: plan and elevation views of truth and confirmed track, zoomed on the
  target (the radar is off the frame; an arrow gives its direction);
- ``pedestal.png``: pedestal and target angles, and the rate commands.

Everything is drawn in engineering units (km, m, deg, Hz, dB); the data stay SI.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .metrics import MODE_NAMES, angle_between
from .record import Recorder

#: the PNGs :func:`plot_run` writes (an output folder may hold them from an earlier run)
PLOT_FILES = ("errors.png", "ascope.png", "trajectory.png", "pedestal.png")
MODE_COLOURS = ("#f4cccc", "#fff2cc", "#d9ead3")
#: [s] window of the moving RMS drawn as the ±1σ band of the angle errors
SIGMA_WINDOW_S = 0.5
#: range bin [m] (SYSTEM.md: 16 bins of 75 m) and the gate's centre bin (1-based)
BIN_M, GATE_CENTRE_BIN = 75.0, 7


def _mode_band(ax: Any, t: np.ndarray, mode: np.ndarray | None) -> None:
    if mode is None or not t.size:
        return
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or mode[i] != mode[start]:
            m = int(mode[start])
            if 0 <= m < 3:
                ax.axvspan(t[start], t[min(i, len(t) - 1)], color=MODE_COLOURS[m], lw=0,
                           zorder=0)
            start = i


def _wrap_deg(x: np.ndarray) -> np.ndarray:
    """Angles [deg] into (−180, 180]."""
    return -((-np.asarray(x) + 180.0) % 360.0 - 180.0)


def _moving_rms(t: np.ndarray, x: np.ndarray, window: float) -> np.ndarray:
    """RMS of the finite samples of ``x`` over the last ``window`` seconds (NaN-aware)."""
    ok = np.isfinite(x)
    c2 = np.concatenate([[0.0], np.cumsum(np.where(ok, x * x, 0.0))])
    cn = np.concatenate([[0], np.cumsum(ok)])
    lo = np.searchsorted(t, t - window, side="left")
    idx = np.arange(1, len(t) + 1)
    n = cn[idx] - cn[lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 1, np.sqrt((c2[idx] - c2[lo]) / np.maximum(n, 1)), np.nan)


def _robust_ylim(ax: Any, *series: np.ndarray, floor: float = 0.0, sym: bool = True) -> None:
    """Y limits covering 99.5 % of the finite samples (a transient at lock does not squash
    the steady state), at least ±``floor``."""
    vals = np.concatenate([np.abs(s[np.isfinite(s)]) if sym else s[np.isfinite(s)]
                           for s in series if s is not None] or [np.zeros(0)])
    if not vals.size:
        return
    hi = max(float(np.percentile(vals, 99.5)) * 1.15, floor)
    if hi > 0:
        ax.set_ylim(-hi if sym else 0.0, hi)


def plot_run(rec: Recorder, out_dir: Path, extra: Recorder | None = None,
             snapshot: Any = None, beamwidth: float | None = None) -> list[Path]:
    """Write the PNGs of :data:`PLOT_FILES` (those the recorded data allow); return their
    paths. ``extra``: the plot-only recording (:mod:`.plot_probe`), ``snapshot``: the SUM
    map at lock, ``beamwidth`` [rad]: the 3 dB beamwidth (pointing panel)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)

    def col(name: str) -> np.ndarray | None:
        c = rec.column(name)
        if c is None and extra is not None and extra.n == rec.n:
            c = extra.column(name)
        return c

    files = [_errors(plt, rec.data[:, 0], col, beamwidth, out_dir / "errors.png")]
    if snapshot is not None:
        files.append(_ascope(plt, snapshot, out_dir / "ascope.png"))
    files.append(_trajectory(plt, col, out_dir / "trajectory.png"))
    files.append(_pedestal(plt, rec.data[:, 0], col, out_dir / "pedestal.png"))
    return files


def _errors(plt: Any, t: np.ndarray, col: Any, beamwidth: float | None, path: Path) -> Path:
    from matplotlib.patches import Patch

    mode = col("RadarManager.mode")
    conf = (mode == 2) if mode is not None else np.ones_like(t, dtype=bool)
    fig, ax = plt.subplots(5, 1, figsize=(11, 11.5), sharex=True,
                           gridspec_kw={"height_ratios": [0.55, 1, 1, 1, 1]})
    # mode timeline
    if mode is not None:
        ax[0].step(t, mode, where="post", color="k", lw=1.2)
        _mode_band(ax[0], t, mode)
    title = "Radar mode"
    if mode is not None and (mode == 2).any():
        lock = float(t[np.argmax(mode == 2)])
        drops = int(np.sum((mode[:-1] == 2) & (mode[1:] != 2)))
        title += f" (first confirmed at {lock:.3f} s; {drops} track drop{'s' * (drops != 1)})"
    ax[0].set(yticks=[0, 1, 2], yticklabels=list(MODE_NAMES), ylim=(-0.4, 2.4), title=title)
    ax[0].legend(handles=[Patch(color=c, label=n) for c, n in
                          zip(MODE_COLOURS, MODE_NAMES, strict=True)],
                 loc="lower right", fontsize=8, ncol=3)
    # range error against the filter's 1σ
    tr, tt, prr = col("Tracker.track.range"), col("TargetGenerator.truth.range"), \
        col("Tracker.track.P_rr")
    if tr is not None and tt is not None:
        err = np.where(conf, tr - tt, np.nan)
        sig = np.where(conf, np.sqrt(np.abs(prr)), np.nan) if prr is not None else \
            _moving_rms(t, err, SIGMA_WINDOW_S)
        how = "filter √P_rr" if prr is not None else f"RMS over {SIGMA_WINDOW_S:g} s"
        ax[1].fill_between(t, -sig, sig, color="0.8", lw=0, label=f"±1σ ({how})")
        ax[1].plot(t, err, lw=0.8, color="C0", label="track − truth")
        _robust_ylim(ax[1], err, sig, floor=1.0)
        rms = math.sqrt(np.nanmean(err ** 2)) if np.isfinite(err).any() else float("nan")
        ax[1].set_title(f"Range error, confirmed (RMS {rms:.1f} m; range bin {BIN_M:g} m)")
    ax[1].set(ylabel="range error [m]")
    ax[1].legend(loc="upper right", fontsize=8)
    # angle errors against a ±1σ band
    names = ("Tracker.track.az", "Tracker.track.el", "TargetGenerator.truth.az",
             "TargetGenerator.truth.el")
    if all(col(n) is not None for n in names):
        kaz, kel, taz, tel = (col(n) for n in names)
        e_az = np.where(conf, _wrap_deg(np.degrees(kaz - taz)) * np.cos(tel), np.nan) * 1e3
        e_el = np.where(conf, np.degrees(kel - tel), np.nan) * 1e3
        s_az, s_el = _moving_rms(t, e_az, SIGMA_WINDOW_S), _moving_rms(t, e_el, SIGMA_WINDOW_S)
        ax[2].fill_between(t, -s_az, s_az, color="C0", alpha=0.18, lw=0,
                           label=f"±1σ az (RMS over {SIGMA_WINDOW_S:g} s)")
        ax[2].fill_between(t, -s_el, s_el, color="C1", alpha=0.18, lw=0,
                           label=f"±1σ el (RMS over {SIGMA_WINDOW_S:g} s)")
        ax[2].plot(t, e_az, lw=0.7, color="C0", label="az error × cos el")
        ax[2].plot(t, e_el, lw=0.7, color="C1", label="el error")
        _robust_ylim(ax[2], e_az, e_el, floor=1.0)
    ax[2].set(ylabel="track angle error [mdeg]", title="Track angle errors, confirmed")
    ax[2].legend(loc="upper right", fontsize=8, ncol=2)
    # pointing error against the beam
    names = ("Pedestal.az", "Pedestal.el", "TargetGenerator.truth.az", "TargetGenerator.truth.el")
    if all(col(n) is not None for n in names):
        point = np.degrees(angle_between(*(col(n) for n in names)))
        ax[3].plot(t, point, lw=0.8, color="C2", label="antenna boresight − target")
        top = float(np.nanmax(point))
        if beamwidth:
            edge = math.degrees(beamwidth) / 2
            ax[3].axhline(edge, color="C3", ls="--", lw=1.0,
                          label=f"3 dB beam edge θ3/2 = {edge:.2f}°")
            top = max(top, edge)
        pos = point[conf & (point > 0)] if conf.any() else point[point > 0]
        low = max(float(np.percentile(pos, 1)) / 2, 1e-4) if pos.size else 1e-3
        ax[3].set(yscale="log", ylim=(low, 2.0 * top))  # log: the error and the beam both show
    ax[3].set(ylabel="pointing error [deg]",
              title="Antenna pointing error against the beam (log scale)")
    ax[3].legend(loc="upper right", fontsize=8)
    # Doppler centre error, folded as the filters see it
    dc, td, pri = col("RadarManager.doppler.centre"), col("TargetGenerator.truth.doppler"), \
        col("RadarManager.pri")
    if dc is not None and td is not None and pri is not None:
        prf = 1.0 / pri
        e = (dc - td + prf / 2) % prf - prf / 2
        ax[4].plot(t, np.where(conf, e, np.nan), lw=0.8, color="C4",
                   label="centre − true Doppler (folded)")
        half = float(np.nanmedian(prf[conf] if conf.any() else prf)) / 6
        for s in (-1, 1):
            ax[4].axhline(s * half, color="C3", ls="--", lw=1.0,
                          label="± half filter spacing (PRF/6)" if s > 0 else None)
        _robust_ylim(ax[4], np.where(conf, e, np.nan), floor=1.2 * half)
    else:
        ax[4].text(0.5, 0.5, "Doppler centre not recorded", transform=ax[4].transAxes,
                   ha="center")
    ax[4].set(ylabel="Doppler error [Hz]", xlabel="time [s]",
              title="Doppler-centre error, confirmed")
    ax[4].legend(loc="upper right", fontsize=8)
    for a in ax[1:]:
        _mode_band(a, t, mode)
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _ascope(plt: Any, snap: Any, path: Path) -> Path:
    v = snap.values
    s = np.asarray(snap.sum, dtype=float)
    db = 20.0 * np.log10(np.maximum(s, 1e-12))
    gate = v.get("gate_start_m", 0.0) + v.get("range_offset_m", 0.0)
    rng = (gate + BIN_M * np.arange(s.shape[0])) / 1e3  # true range of each bin [km]
    centre = v.get("doppler_centre_hz", 0.0)
    prf = 1.0 / v["pri_s"] if v.get("pri_s") else None
    spacing = v.get("doppler_spacing_hz") or (prf / 3 if prf else 0.0)
    freqs = [centre + (f - 1) * spacing for f in range(s.shape[1])]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.8),
                                 gridspec_kw={"width_ratios": [1.6, 1]})
    for f in range(s.shape[1]):
        a1.plot(rng, db[:, f], marker="o", ms=3, lw=1.0,
                label=f"filter {f + 1} ({freqs[f] / 1e3:+.2f} kHz)")
    if "truth_range_m" in v:
        a1.axvline(v["truth_range_m"] / 1e3, color="k", ls="--", lw=1.0, label="true range")
    a1.axvspan(rng[GATE_CENTRE_BIN - 2], rng[GATE_CENTRE_BIN], color="0.9", zorder=0,
               label="gate (bins 6-8)")
    a1.set(xlabel="true range of the bin [km]", ylabel="SUM [dB]",
           title=f"A-scope at lock (t = {snap.t:.3f} s)")
    lo, hi = float(np.min(db)), float(np.max(db))
    a1.set_ylim(lo - 2.0, hi + 0.35 * (hi - lo) + 2.0)  # room for the legend above the data
    a1.legend(fontsize=8, loc="upper center", ncol=3)
    a1.grid(alpha=0.3)
    im = a2.imshow(db.T, origin="lower", aspect="auto", cmap="viridis",
                   extent=(rng[0] - BIN_M / 2e3, rng[-1] + BIN_M / 2e3, 0.5, s.shape[1] + 0.5))
    if "truth_range_m" in v:
        a2.axvline(v["truth_range_m"] / 1e3, color="w", ls="--", lw=1.0)
    a2.set(xlabel="true range [km]", ylabel="Doppler filter", yticks=[1, 2, 3],
           yticklabels=[f"{f + 1}\n{freqs[f] / 1e3:+.2f} kHz" for f in range(s.shape[1])],
           title="Range-Doppler map (SUM, dB)")
    fig.colorbar(im, ax=a2, label="dB")
    if "truth_doppler_hz" in v and prf:
        off = (v["truth_doppler_hz"] - centre + prf / 2) % prf - prf / 2
        fig.suptitle(f"true target Doppler {off / 1e3:+.2f} kHz from the centre filter "
                     f"(folded into ±PRF/2, PRF {prf / 1e3:.2f} kHz)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _trajectory(plt: Any, col: Any, path: Path) -> Path:
    mode = col("RadarManager.mode")
    tx, ty, tz = (col(f"TargetGenerator.truth.{a}") for a in "xyz")
    kx, ky, kz = (col(f"Tracker.track.{a}") for a in "xyz")
    n = len(tx) if tx is not None else (len(kx) if kx is not None else 0)
    conf = (mode == 2) if mode is not None else np.ones(n, dtype=bool)
    if kx is not None:
        conf = conf & ((kx != 0) | (ky != 0))  # no track yet: (0, 0, 0) is not a position
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5.2))
    if tx is not None:
        a1.plot(tx / 1e3, ty / 1e3, "k-", lw=1.5, label="truth")
        a1.plot(tx[:1] / 1e3, ty[:1] / 1e3, "ko", ms=5, label="start")
        a2.plot(np.hypot(tx, ty) / 1e3, tz, "k-", lw=1.5, label="truth")
        a2.plot(np.hypot(tx, ty)[:1] / 1e3, tz[:1], "ko", ms=5, label="start")
        # the radar's direction, as an arrow from the start of the track (the radar itself,
        # km away, would squash the path to a dot)
        r0 = math.hypot(tx[0], ty[0])
        if r0 > 0:
            span = max(np.ptp(tx), np.ptp(ty), 200.0) / 1e3
            ux, uy = -tx[0] / r0, -ty[0] / r0
            head = (tx[0] / 1e3 + 0.2 * span * ux, ty[0] / 1e3 + 0.2 * span * uy)
            a1.annotate("", xy=head, xytext=(tx[0] / 1e3, ty[0] / 1e3),
                        arrowprops={"arrowstyle": "->", "color": "C3", "lw": 1.5})
            a1.text(*head, f" to the radar\n ({r0 / 1e3:.1f} km)", fontsize=8, color="C3",
                    va="top")
    if kx is not None:
        a1.plot(kx[conf] / 1e3, ky[conf] / 1e3, ".", ms=2, color="C0",
                label="track (confirmed)")
        a2.plot(np.hypot(kx, ky)[conf] / 1e3, kz[conf], ".", ms=2, color="C0",
                label="track (confirmed)")
    a1.set(xlabel="East [km]", ylabel="North [km]", title="Plan view", aspect="equal")
    a1.set_aspect("equal", adjustable="datalim")
    a2.set(xlabel="ground range from the radar [km]", ylabel="altitude [m]",
           title="Elevation view")
    for a in (a1, a2):
        a.legend(fontsize=8, loc="best")
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _pedestal(plt: Any, t: np.ndarray, col: Any, path: Path) -> Path:
    mode = col("RadarManager.mode")
    fig, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
    for ax, axis in zip(axes[:2], ("az", "el"), strict=True):
        ped, tru = col(f"Pedestal.{axis}"), col(f"TargetGenerator.truth.{axis}")
        wrap = _wrap_deg if axis == "az" else (lambda x: x)
        if tru is not None:
            ax.plot(t, wrap(np.degrees(tru)), "k-", lw=1.2, label=f"target {axis}")
        if ped is not None:
            ax.plot(t, wrap(np.degrees(ped)), lw=0.9, color="C2", ls="--",
                    label=f"pedestal {axis}")
        ax.set(ylabel=f"{'azimuth' if axis == 'az' else 'elevation'} [deg]")
        ax.legend(loc="upper right", fontsize=8)
    for n in ("Tracker.cmd.az", "Tracker.cmd.el"):
        if col(n) is not None:
            axes[2].plot(t, col(n), lw=0.6, label=n.split(".", 1)[1])
    _robust_ylim(axes[2], *(col(n) for n in ("Tracker.cmd.az", "Tracker.cmd.el")), floor=0.1)
    axes[2].set(ylabel="rate command [V]", xlabel="time [s]",
                title="Rate commands (axis covers 99.5 % of the samples)")
    axes[2].legend(loc="upper right", fontsize=8)
    axes[0].set_title("Pedestal angles (azimuth in ±180°) and rate commands")
    for ax in axes:
        _mode_band(ax, t, mode)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
