"""Tables and heat maps of the envelope benchmark (benchmarks/bench_envelope.py): reads the
per-cell CSV, judges every cell against the issue-11 goals, draws docs/img/envelope_*.png and
rewrites the generated part of docs/envelope.md; and the direct-loop vs FMU check of one cell.
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from axir.models.radar.conventions import BIN_S
from axir.models.target_generator import TargetGenerator
from axir.orchestrator.envelope import Cell, clutter_loss_db, required_snr_db
from axir.orchestrator.envelope_run import ACQ_PRI_BINS, read_rows

LOCK_GOAL = 1.0  # [s]
HELD_GOAL = 0.99
RMS_GOAL = 10.0  # [m]
BEGIN, END = "<!-- envelope:begin -->", "<!-- envelope:end -->"
#: the one-factor sweeps about the anchor (orchestrator/envelope_run.py): design label, the
#: swept column, its figure label, its table header, and the anchor as the table describes it
SWEEPS = (("elevation", "el_deg", "elevation [deg]", "el [deg]", "−53.15 m/s, el 5°, 10 m²"),
          ("rcs", "rcs", "RCS [m²] at 30 km", "RCS [m²]", "−53.15 m/s, el 5°, 10 m², range 30 km"),
          ("maneuver", "g", "maneuver [g]", "g",
           "−53.15 m/s, el 5°, 10 m², 250 m/s across, turn from 1 s"),
          ("slow", "speed", "radial speed [m/s]", "speed [m/s]",
           "radial speed beside the clutter notch, el 5°, 10 m²"))
PRI_BINS = (200, 211, 223)  # the manager's default PRI set (models/manager/ambiguity.py)


def _f(x: str) -> float | None:
    return None if x in ("", None) else float(x)


def filter_loss_db(speed: float, pri_bins: int = ACQ_PRI_BINS) -> float:
    """Loss [dB] of the best of the 3 search Doppler filters (centres 0, ±PRF/3) for a radial
    speed, relative to a filter-centred target (first-order resonator, pole ρ:
    |H(Δf)|² = (1 − ρ)²/|1 − ρ·e^{j2πΔfT}|², models/target_generator.py)."""
    d = TargetGenerator.defaults()
    t = pri_bins * BIN_S
    prf = 1.0 / t
    fd = -2.0 * speed / d["wavelength"]
    rho = d["pole"]
    best = 0.0
    for fc in (0.0, prf / 3.0, -prf / 3.0):
        df = (fd - fc + prf / 2.0) % prf - prf / 2.0
        h2 = (1.0 - rho) ** 2 / abs(1.0 - rho * complex(math.cos(2 * math.pi * df * t),
                                                       math.sin(2 * math.pi * df * t))) ** 2
        best = max(best, h2)
    return -10.0 * math.log10(best)


def clutter_offset_hz(speed: float, pri_bins: int = ACQ_PRI_BINS) -> float:
    """|folded Doppler| [Hz] from the clutter line (0 Hz) on a PRI."""
    prf = 1.0 / (pri_bins * BIN_S)
    fd = -2.0 * speed / TargetGenerator.defaults()["wavelength"]
    return abs((fd + prf / 2.0) % prf - prf / 2.0)


def verdict(r: dict[str, str]) -> str:
    """'ok' or the first goal a row misses ('no lock', 'late lock', 'dropped', 'held < 99 %',
    'RMS > 10 m', 'false conf.'); non-detectable rows: 'n/d' or 'false conf.'."""
    if int(r["false_confirmations"]) > 0:
        return "false conf."
    if r["detectable"] != "True":
        return "n/d"
    lock = _f(r["lock_time"])
    if lock is None:
        return "no lock"
    if lock > LOCK_GOAL:
        return "late lock"
    if int(r["drops"]) > 0:
        return "dropped"
    if (_f(r["held_fraction"]) or 0.0) < HELD_GOAL:
        return "held < 99 %"
    if (_f(r["rms_range_error_m"]) or math.inf) > RMS_GOAL:
        return "RMS > 10 m"
    return "ok"


def run_verdict(row: Mapping[str, Any]) -> str:
    """:func:`verdict` of one run's figures under the short keys the designation and
    low-elevation benchmarks keep (``false``, ``detectable``, ``lock``, ``drops``, ``held``,
    ``rms_m``; None: not measured)."""
    keys = {"false_confirmations": "false", "detectable": "detectable", "lock_time": "lock",
            "drops": "drops", "held_fraction": "held", "rms_range_error_m": "rms_m"}
    return verdict({k: "" if row[s] is None else str(row[s]) for k, s in keys.items()})


CATS = ("ok", "late lock", "no lock", "dropped", "held < 99 %", "RMS > 10 m", "false conf.",
        "n/d")
COLOURS = ("#2e7d32", "#f9a825", "#c62828", "#ef6c00", "#ffb74d", "#8e24aa", "#000000",
           "#bdbdbd")


def _worst(verdicts: Sequence[str]) -> str:
    """The worst verdict over seeds (order: false conf. > no lock > dropped > ... > ok)."""
    rank = ("false conf.", "no lock", "dropped", "late lock", "held < 99 %", "RMS > 10 m",
            "ok", "n/d")
    return min(verdicts, key=rank.index)


def _group(rows: list[dict[str, str]], keys: Sequence[str]) -> dict[tuple, list[dict]]:
    g: dict[tuple, list[dict]] = defaultdict(list)
    for r in rows:
        g[tuple(float(r[k]) for k in keys)].append(r)
    return dict(sorted(g.items()))


def plane_figures(rows: list[dict[str, str]], img: Path, name: str = "plane") -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    g = _group(rows, ("range_m", "speed"))
    ranges = sorted({k[0] for k in g})
    speeds = sorted({k[1] for k in g})
    cat = np.full((len(ranges), len(speeds)), np.nan)
    lock = np.full((len(ranges), len(speeds)), np.nan)
    for (r, v), rs in g.items():
        i, j = ranges.index(r), speeds.index(v)
        cat[i, j] = CATS.index(_worst([verdict(x) for x in rs]))
        locks = [_f(x["lock_time"]) for x in rs]
        lock[i, j] = max(x if x is not None else np.inf for x in locks)
    out = []
    el = float(rows[0]["el_deg"])
    loss = np.array([min(clutter_loss_db(Cell(float(ranges[0]), v, el, 10.0)), 40.0)
                     for v in speeds])
    fig, (ax0, ax) = plt.subplots(2, 1, figsize=(13, 6.5), sharex=True,
                                  gridspec_kw={"height_ratios": [1, 3]})
    xs = np.arange(len(speeds))
    ax0.bar(xs, loss, color="#546e7a")
    ax0.set_ylabel("clutter + notch\nloss [dB]")
    ax0.set_title(f"Range × radial speed (el {el:g}°, 10 m², clutter on): worst verdict over "
                  "seeds; bars: clutter loss of the criterion (2nd-best PRI, ≤ 40 dB)")
    cmap = ListedColormap(COLOURS)
    cmap.set_bad("white")  # cells left out of the design (they would pass the radar)
    ax.imshow(cat, cmap=cmap, vmin=-0.5, vmax=len(CATS) - 0.5, aspect="auto",
              origin="lower", interpolation="nearest")
    for i in range(len(ranges)):
        for j in range(len(speeds)):
            if not np.isnan(lock[i, j]) and np.isfinite(lock[i, j]):
                ax.text(j, i, f"{lock[i, j]:.2f}", ha="center", va="center", fontsize=6,
                        rotation=90, color="white")
    ax.set_yticks(range(len(ranges)), [f"{r / 1000:g}" for r in ranges])
    ax.set_xticks(xs, [f"{v:g}" for v in speeds], rotation=90, fontsize=7)
    ax.set_xlabel("radial speed [m/s] (< 0 closing); numbers: worst-seed on-target lock "
                  "time [s]; white: not run (would pass the radar)")
    ax.set_ylabel("range [km]")
    from matplotlib.patches import Patch

    used = sorted({int(c) for c in cat[~np.isnan(cat)]})
    ax.legend(handles=[Patch(color=COLOURS[c], label=CATS[c]) for c in used],
              loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    fig.tight_layout()
    p = img / f"envelope_{name}.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    out.append(p)
    return out


def sweep_figure(rows: list[dict[str, str]], img: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    present = {r["design"] for r in rows}
    parts = [(name, key, label) for name, key, label, _, _ in SWEEPS if name in present]
    fig, axes = plt.subplots(2, len(parts), figsize=(4.3 * len(parts), 6), sharex="col",
                             squeeze=False)
    for c, (name, key, label) in enumerate(parts):
        rs = [r for r in rows if r["design"] == name]
        for seed in sorted({r["seed"] for r in rs}):
            ss = sorted((r for r in rs if r["seed"] == seed), key=lambda r: float(r[key]))
            x = [float(r[key]) for r in ss]
            lk = [_f(r["lock_time"]) if _f(r["lock_time"]) is not None else np.nan for r in ss]
            hd = [_f(r["held_fraction"]) if _f(r["held_fraction"]) is not None else np.nan
                  for r in ss]
            line, = axes[0, c].plot(x, lk, "o-", label=f"seed {seed}")
            axes[1, c].plot(x, hd, "o-", color=line.get_color())
            miss = [xi for xi, v in zip(x, lk, strict=True) if np.isnan(v)]
            axes[0, c].plot(miss, [0.0] * len(miss), "x", ms=9, color=line.get_color())
            for xi, r in zip(x, ss, strict=True):
                if int(r["drops"]) or int(r["false_confirmations"]):
                    axes[1, c].annotate(f"s{seed}: d{r['drops']} f{r['false_confirmations']}",
                                        (xi, 0.02 + 0.2 * (int(seed) - 1)), fontsize=7,
                                        color=line.get_color())
        axes[0, c].axhline(LOCK_GOAL, color="k", ls=":", lw=0.8)
        axes[1, c].axhline(HELD_GOAL, color="k", ls=":", lw=0.8)
        axes[0, c].set_title(f"{name} sweep")
        axes[1, c].set_xlabel(label)
        if key in ("rcs", "el_deg"):
            axes[1, c].set_xscale("log")
        axes[1, c].set_ylim(-0.05, 1.05)
        axes[0, c].set_ylim(-0.1, max(3.0, axes[0, c].get_ylim()[1]))
    axes[0, 0].set_ylabel("on-target lock time [s] (× at 0: none)")
    axes[1, 0].set_ylabel("held fraction (d drops, f false)")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    p = img / "envelope_sweeps.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    return p


def _fmt(x: str, nd: int = 2) -> str:
    v = _f(x)
    return "–" if v is None else f"{v:.{nd}f}"


def _plane_table(pl: list[dict[str, str]], name: str) -> list[str]:
    """The per-range table of a range × speed plane and its verdicts by filter loss."""
    out: list[str] = []
    if not pl:
        return out
    out.append(f"Range × radial-speed plane `{name}` (el {float(pl[0]['el_deg']):g}°), per "
               "range (all speeds and seeds):\n")
    out.append("| range [km] | runs | detectable | ok | late lock | no lock | dropped | "
               "false conf. | median lock [s] | median RMS range [m] |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    for (r,), rs in _group(pl, ("range_m",)).items():
        v = [verdict(x) for x in rs]
        locks = [_f(x["lock_time"]) for x in rs if _f(x["lock_time"]) is not None]
        rms = [_f(x["rms_range_error_m"]) for x in rs
               if _f(x["rms_range_error_m"]) is not None]
        out.append(
            f"| {r / 1000:g} | {len(rs)} | {sum(x['detectable'] == 'True' for x in rs)} | "
            f"{v.count('ok')} | {v.count('late lock')} | {v.count('no lock')} | "
            f"{v.count('dropped')} | {v.count('false conf.')} | "
            f"{np.median(locks):.2f} | {np.median(rms):.1f} |" if locks and rms else
            f"| {r / 1000:g} | {len(rs)} | {sum(x['detectable'] == 'True' for x in rs)} | "
            f"{v.count('ok')} | {v.count('late lock')} | {v.count('no lock')} | "
            f"{v.count('dropped')} | {v.count('false conf.')} | – | – |")
    out.append("")
    # verdict by acquisition-filter loss
    out.append("Detectable plane runs by the acquisition PRI's Doppler-filter loss of the "
               "speed (best of the 3 search filters; see the bar chart above the map):\n")
    out.append("| filter loss [dB] | runs | ok | no lock | late lock | other misses |")
    out.append("|---|---|---|---|---|---|")
    bins = ((0, 3), (3, 6), (6, 10), (10, 15), (15, 40))
    for lo, hi in bins:
        rs = [x for x in pl if x["detectable"] == "True"
              and lo <= filter_loss_db(float(x["speed"])) < hi]
        v = [verdict(x) for x in rs]
        other = len(v) - v.count("ok") - v.count("no lock") - v.count("late lock")
        out.append(f"| {lo}-{hi} | {len(rs)} | {v.count('ok')} | {v.count('no lock')} | "
                   f"{v.count('late lock')} | {other} |")
    out.append("")
    return out


def tables(rows: list[dict[str, str]]) -> str:
    out: list[str] = []
    det = [r for r in rows if r["detectable"] == "True"]
    cnt = defaultdict(int)
    for r in det:
        cnt[verdict(r)] += 1
    nfalse = sum(int(r["false_confirmations"]) for r in rows)
    seeds = sorted({int(r["seed"]) for r in rows})
    cpu = sum(float(r["cpu_s"]) for r in rows)
    sim = sum(float(r["duration"]) for r in rows)
    out.append(f"Runs: {len(rows)} ({len(det)} detectable, "
               f"{len(rows) - len(det)} not detectable or target-free), seeds "
               f"{', '.join(map(str, seeds))}; {sim:.0f} simulated s for {cpu:.0f} CPU-s "
               f"({cpu / max(sim, 1e-9):.2f} CPU-s per simulated s, as measured on the "
               f"machine of the run); required filtered SNR {required_snr_db():.2f} dB.\n")
    out.append("| verdict (detectable runs) | runs |\n|---|---|")
    out += [f"| {c} | {cnt[c]} |" for c in CATS if c != "n/d" and cnt[c]]
    out.append(f"\nFalse confirmations in all runs: **{nfalse}** in "
               f"{sum(1 for r in rows if int(r['false_confirmations']))} runs "
               "(detectable or not, target-free included).\n")
    # plane per range
    for name in ("plane", "lowplane"):
        out += _plane_table([r for r in rows if r["design"] == name], name)
    for name, key, _, label, anchor in SWEEPS:
        rs = sorted((r for r in rows if r["design"] == name),
                    key=lambda r: (float(r[key]), int(r["seed"])))
        if not rs:
            continue
        out.append(f"Sweep `{name}` (anchor 10 km, {anchor}):\n")
        out.append(f"| {label} | seed | filt. SNR [dB] | lock [s] | held | drops | false | "
                   "RMS range [m] | RMS angle [mrad] | tentatives | verdict |")
        out.append("|---|---|---|---|---|---|---|---|---|---|---|")
        for r in rs:
            ang = _f(r["rms_angle_error_rad"])
            out.append(
                f"| {float(r[key]):g} | {r['seed']} | {_fmt(r['snr_filtered_db'], 1)} | "
                f"{_fmt(r['lock_time'], 3)} | {_fmt(r['held_fraction'], 3)} | {r['drops']} | "
                f"{r['false_confirmations']} | {_fmt(r['rms_range_error_m'], 1)} | "
                f"{'–' if ang is None else f'{1e3 * ang:.2f}'} | {r['tentatives']} | "
                f"{verdict(r)} |")
        out.append("")
    rs = sorted((r for r in rows if r["design"] == "clutter"),
                key=lambda r: (float(r["el_deg"]), -float(r["duration"]), int(r["seed"])))
    if rs:
        out.append("Target-free clutter (designation 20 km, every confirmation is false):\n")
        out.append("| el [deg] | seed | duration [s] | tentative attempts | per second | "
                   "false confirmations | time falsely confirmed [s] |")
        out.append("|---|---|---|---|---|---|---|")
        for r in rs:
            d = float(r["duration"])
            out.append(f"| {float(r['el_deg']):g} | {r['seed']} | {d:g} | {r['tentatives']} | "
                       f"{int(r['tentatives']) / d:.2f} | {r['false_confirmations']} | "
                       f"{_fmt(r['time_false_confirmed_s'], 2)} |")
        out.append("")
    return "\n".join(out)


def report(csv_path: Path, doc: Path, cells: list[tuple[str, Cell]] | None = None) -> None:
    """Figures into ``doc``'s img/ folder and the tables between its marks."""
    rows = read_rows(csv_path)
    img = doc.parent / "img"
    img.mkdir(parents=True, exist_ok=True)
    paths = []
    for name in ("plane", "lowplane"):
        if any(r["design"] == name for r in rows):
            paths += plane_figures([r for r in rows if r["design"] == name], img, name)
    if any(r["design"] in {name for name, *_ in SWEEPS} for r in rows):
        paths.append(sweep_figure(rows, img))
    text = tables(rows)
    body = doc.read_text() if doc.is_file() else f"# Envelope\n\n{BEGIN}\n{END}\n"
    if BEGIN not in body:
        body += f"\n{BEGIN}\n{END}\n"
    body = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END),
                  lambda _: f"{BEGIN}\n{text}\n{END}", body, flags=re.S)
    doc.write_text(body)
    for p in paths:
        print(f"wrote {p}")
    print(f"wrote {doc}")
    if cells is not None:
        print(f"{len(rows)} rows in the CSV; the design has {len(cells)} cells")


def fmu_check(duration: float = 1.5) -> None:
    """The anchor cell through the four FMUs (axir run's machinery) and the direct loop."""
    import tempfile
    from dataclasses import replace

    from axir.fmus.build import build_all
    from axir.orchestrator.envelope import cell_scenario, run_cell
    from axir.orchestrator.envelope_run import ANCHOR
    from axir.orchestrator.metrics import summarize
    from axir.orchestrator.run import run_scenario
    from axir.orchestrator.scenario import parse_scenario

    cell = replace(ANCHOR, duration=duration)
    direct = run_cell(cell)
    with tempfile.TemporaryDirectory() as d:
        build_all(Path(d))
        sc = parse_scenario(cell_scenario(cell), "<envelope cell>")
        _, rec = run_scenario(sc, Path(d), None, progress=False)
        fmu = summarize(rec)
    keys = ("lock_time", "first_confirmed_time", "held_fraction", "drops",
            "false_confirmations", "rms_range_error_m", "rms_angle_error_rad", "final_mode")
    print(f"cell {cell}")
    print(f"{'key':24s} {'direct loop':>22s} {'FMUs':>22s}")
    for k in keys:
        print(f"{k:24s} {direct.get(k)!s:>22s} {fmu.get(k)!s:>22s}")
