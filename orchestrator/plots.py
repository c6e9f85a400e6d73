"""PNG plots of a recorded run (matplotlib, Agg backend)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .metrics import MODE_NAMES, angle_between
from .record import Recorder

#: the PNGs :func:`plot_run` writes (an output folder may hold them from an earlier run)
PLOT_FILES = ("trajectory.png", "errors.png", "pedestal.png")


def _mode_band(ax, t: np.ndarray, mode: np.ndarray | None) -> None:
    if mode is None:
        return
    colors = ("#f4cccc", "#fff2cc", "#d9ead3")
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or mode[i] != mode[start]:
            m = int(mode[start])
            if 0 <= m < 3:
                ax.axvspan(t[start], t[min(i, len(t) - 1)], color=colors[m], lw=0, zorder=0)
            start = i


def plot_run(rec: Recorder, out_dir: Path) -> list[Path]:
    """Write truth-vs-track, errors-vs-time and pedestal plots; return the file paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    out_dir = Path(out_dir)
    t = rec.data[:, 0]
    c = rec.column
    mode = c("RadarManager.mode")
    conf = (mode == 2) if mode is not None else np.ones_like(t, dtype=bool)
    files = []
    legend = [Patch(color=col, label=n) for col, n in
              zip(("#f4cccc", "#fff2cc", "#d9ead3"), MODE_NAMES, strict=True)]

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5))
    tx, ty, tz = c("TargetGenerator.truth.x"), c("TargetGenerator.truth.y"), c(
        "TargetGenerator.truth.z")
    kx, ky, kz = c("Tracker.track.x"), c("Tracker.track.y"), c("Tracker.track.z")
    if tx is not None:
        a1.plot(tx / 1e3, ty / 1e3, "k-", label="truth")
        a2.plot(np.hypot(tx, ty) / 1e3, tz / 1e3, "k-", label="truth")
    if kx is not None:
        a1.plot(kx[conf] / 1e3, ky[conf] / 1e3, ".", ms=2, label="track (confirmed)")
        a2.plot(np.hypot(kx, ky)[conf] / 1e3, kz[conf] / 1e3, ".", ms=2, label="track")
    a1.plot([0], [0], "r^", label="radar")
    a1.set(xlabel="East [km]", ylabel="North [km]", title="Plan view", aspect="equal")
    a2.set(xlabel="Ground range [km]", ylabel="Altitude [km]", title="Elevation view")
    a1.legend(), a2.legend()
    files.append(out_dir / "trajectory.png")
    fig.tight_layout(), fig.savefig(files[-1], dpi=110), plt.close(fig)

    fig, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
    tr, tt = c("Tracker.track.range"), c("TargetGenerator.truth.range")
    if tr is not None and tt is not None:
        err = np.where(conf, tr - tt, np.nan)
        axes[0].plot(t, err, lw=0.8)
    axes[0].set(ylabel="range error [m]")
    names = ("Tracker.track.az", "Tracker.track.el", "TargetGenerator.truth.az",
             "TargetGenerator.truth.el")
    if all(c(n) is not None for n in names):
        ang = np.degrees(angle_between(*(c(n) for n in names)))
        axes[1].plot(t, np.where(conf, ang, np.nan), lw=0.8, label="track LOS")
    names = ("Pedestal.az", "Pedestal.el", "TargetGenerator.truth.az", "TargetGenerator.truth.el")
    if all(c(n) is not None for n in names):
        ang = np.degrees(angle_between(*(c(n) for n in names)))
        axes[1].plot(t, ang, lw=0.8, label="antenna pointing")
    axes[1].set(ylabel="angle error [deg]", yscale="log")
    axes[1].legend(loc="upper right")
    for n, lab in (("Tracker.dev.az", "dev.az"), ("Tracker.dev.el", "dev.el")):
        if c(n) is not None:
            axes[2].plot(t, np.degrees(c(n)), lw=0.6, label=lab)
    axes[2].set(ylabel="deviation [deg]", xlabel="time [s]")
    axes[2].legend(loc="upper right")
    for ax in axes:
        _mode_band(ax, t, mode)
    axes[0].legend(handles=legend, loc="upper right", fontsize=8)
    files.append(out_dir / "errors.png")
    fig.tight_layout(), fig.savefig(files[-1], dpi=110), plt.close(fig)

    fig, axes = plt.subplots(2, 1, figsize=(11, 6), sharex=True)
    for n, lab in (("Pedestal.az", "pedestal az"), ("TargetGenerator.truth.az", "truth az"),
                   ("Pedestal.el", "pedestal el"), ("TargetGenerator.truth.el", "truth el")):
        if c(n) is not None:
            axes[0].plot(t, np.degrees(c(n)), lw=0.8, label=lab)
    axes[0].set(ylabel="angle [deg]")
    axes[0].legend(loc="upper right", fontsize=8)
    for n in ("Tracker.cmd.az", "Tracker.cmd.el"):
        if c(n) is not None:
            axes[1].plot(t, c(n), lw=0.6, label=n.split(".", 1)[1])
    axes[1].set(ylabel="rate command [V]", xlabel="time [s]")
    axes[1].legend(loc="upper right")
    for ax in axes:
        _mode_band(ax, t, mode)
    files.append(out_dir / "pedestal.png")
    fig.tight_layout(), fig.savefig(files[-1], dpi=110), plt.close(fig)
    return files
