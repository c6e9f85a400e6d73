"""Seed 002: what the constants the paper does not state do to the SVD-vs-VD verdict.

Four measurements (issue 13; docs/filters.md "Constants the seed does not state"):

1. **Sweep** (through the FMUs): the svd-1 / svd-2 campaigns of ``reports/seed002.py`` (same
   seeds, paired) for the SVD filter over σa (``Tracker.filter_sigma_a``, Q_u = σa²·T) and
   both readings of I2 (``Tracker.fmd_end``), and for the VD filter over its jerk noise σj
   (``Tracker.filter_sigma_j``, white-jerk density σj²/s); SVD/VD ratios of the RMS range error
   per period for every (σa, σj) pair.
2. **Table 3** (no FMUs): the peaks of the reduced SVD filter's registers (eqs. 30-39) on the
   recorded measurements of those campaigns, for several Q_u, against the register ranges of
   seed 002 Table 3; and the Q_u that puts the peak of P_u at 110 and of K_u at 0.05. P_u, K_u,
   U, V do not depend on the measurements (covariance recursion), u, L, d, R do.
3. **Thresholds** (no FMUs): detection delay and false alarms per step of the fading-memory
   test L(k) > I (a_f = 0.8, the two-state filter's innovations, the same for SVD, VD and
   Kalman before the detection) for the χ²-based thresholds and the paper's 7.5, on the same
   recorded measurements; the false-alarm rate of L > I for white χ²₁ innovations (4·10⁶
   seeded samples) beside it.
4. The range filter's own flag is used throughout (``seed002.range_filter_replay``).

Usage: ``.venv/bin/python reports/seed002_constants.py [--runs 50] [--workers 2]
[--fmu-dir DIR] [--out DIR]`` (≈ 36 campaigns of 50 × 100 steps; a few minutes on the shared
2-core VM). Writes ``seed002_constants.md`` and ``seed002_constants.json``.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from common import OUT, fmt, fmu_directory
from scipy.signal import lfilter
from seed002 import (
    SCENARIOS,
    SETTLE,
    _clean,
    maneuver_windows,
    metrics,
    periods,
    range_filter_replay,
)

from axir.models.filters.base import FilterConfig
from axir.models.filters.fmd import detection_threshold, end_threshold
from axir.models.filters.svd import SVDReducedFilter
from axir.orchestrator.campaign import LOCAL_CLUSTER_QUIET, CampaignResult, run_campaign
from axir.orchestrator.scenario import load_scenario

SIGMA_A = (1.0, 2.0, 3.0, 5.0, 7.0, 10.0)  # [m/s²] SVD acceleration noise (Q_u = σa²)
SIGMA_J = (1.0, 2.0, 5.0, 10.0)  # [m/s²] VD jerk noise (density σj²/s)
END_RULES = ("acceleration", "hysteresis")
QU_TABLE3 = (4.0, 9.0, 16.0, 25.0, 36.0)  # [m²/s⁴] Q_u values of the register table
#: seed 002 Table 3 register ranges (upper ends) of the acceleration filter and the detector
TABLE3 = {"Pu": 110.0, "Ku": 0.05, "U1": 28.0, "V1": 21.0, "U2": 8.0, "V2": 7.0, "u": 60.0,
          "L": 7000.0, "d": 2e4, "R": 6000.0, "N": 7e4}
A_F = 0.8  # fading factor of the threshold table (the Tracker's default maneuver_fading)
PAPER_I1 = 7.5  # seed 002 Table 3: I1 "like 7.5"


# ----------------------------------------------------------------------------- campaigns
def run_sweep(fmu_dir: Path, runs: int, workers: int, seed: int
              ) -> dict[tuple[str, str, float, str], CampaignResult]:
    """(scenario, filter, σ, end rule) → campaign: SVD over σa × end rule, VD over σj."""
    from distributed import Client, LocalCluster

    jobs: list[tuple[str, str, float, str]] = []
    for name in SCENARIOS:
        jobs += [(name, "svd", sa, end) for end in END_RULES for sa in SIGMA_A]
        jobs += [(name, "vd", sj, "acceleration") for sj in SIGMA_J]
    out = {}
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      silence_logs=logging.ERROR, **LOCAL_CLUSTER_QUIET) as cluster, \
            Client(cluster) as client:
        for name, f, sigma, end in jobs:
            par: dict[str, Any] = {"filter_range": f, "fmd_end": end}
            par["filter_sigma_a" if f == "svd" else "filter_sigma_j"] = sigma
            t0 = time.perf_counter()
            res = run_campaign(name, fmu_dir, runs, client=client, seed=seed,
                               parameters={"Tracker": par}, progress=False)
            print(f"seed002_constants: {name} {f} σ={sigma:g} {end}: "
                  f"{res.summary['succeeded']}/{runs} in {time.perf_counter() - t0:4.1f} s",
                  flush=True)
            out[(name, f, sigma, end)] = res
    return out


def sweep_tables(m: dict[tuple[str, str, float, str], dict[str, Any]]) -> dict[str, Any]:
    """SVD/VD RMS range ratios per period for every (σa, end rule, σj)."""
    rows = []
    for (name, f, sa, end), svd in m.items():
        if f != "svd":
            continue
        for sj in SIGMA_J:
            vd = m[(name, "vd", sj, "acceleration")]
            row = {"scenario": name, "sigma_a": sa, "fmd_end": end, "sigma_j": sj}
            for q in ("range", "velocity"):
                for p in ("maneuver", "after", "quiet"):
                    a, b = svd[f"rms_{q}_{p}"], vd[f"rms_{q}_{p}"]
                    row[f"ratio_{q}_{p}"] = a / b
            rows.append(row)
    return {"rows": rows}


# ----------------------------------------------------------------------------- Table 3
def _recorded(res: CampaignResult, ref: str) -> np.ndarray:
    j = 1 + res.spec.record.index(ref)
    return np.stack([r["data"][1:, j] for r in res.results if r["status"] == "ok"])


def register_peaks(z: np.ndarray, sigma_m: float, qu: float) -> dict[str, float]:
    """Largest |register| of the float reduced SVD filter over all runs of ``z`` (runs × time,
    T = 1 s, σr = 100 m) with Q_u = ``qu`` (σa = √qu at T = 1 s); ``Pu_pred`` is the
    predicted P_u(k/k−1) = P_u + Q_u (the value the P_u register holds before eq. 36)."""
    cfg = FilterConfig(sigma_m=sigma_m, sigma_meas=100.0, sigma_a=math.sqrt(qu))
    peak: dict[str, float] = {}
    for row in z:
        f = SVDReducedFilter(cfg)
        for k, zk in enumerate(row):
            f.update(float(zk), 1.0)
            if k < 2:
                continue
            vals = {"Pu": f.Pu, "Pu_pred": f.Pu / (1.0 - f.Ku * f.U1) if f.Ku * f.U1 < 1.0
                    else math.nan, "Ku": f.Ku, "U1": f.U1, "U2": f.U2, "V1": f.V1, "V2": f.V2,
                    "u": f.u, "L": f.fmd.L, "R": f.nu}
            # N = h1 + σr² (eq. 14): h1 = P11(k/k) / (1 − K1)
            n_var = f.P11 / (1.0 - f.K1) + 1e4 if f.K1 < 1.0 else math.nan
            vals["N"] = n_var
            vals["d"] = f.nu * f.nu / n_var
            for key, v in vals.items():
                peak[key] = max(peak.get(key, 0.0), abs(v))
    return peak


def qu_for_peak(sigma_m: float, register: str, target: float) -> float:
    """Q_u [m²/s⁴] whose peak of ``register`` (Pu or Ku; measurement-independent) is
    ``target`` (bisection on log Q_u; both peaks increase with Q_u)."""
    z = np.zeros((1, 100))  # the covariance recursion does not see the measurements
    lo, hi = 0.1, 1000.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if register_peaks(z, sigma_m, mid)[register] > target:
            hi = mid
        else:
            lo = mid
    return math.sqrt(lo * hi)


# ----------------------------------------------------------------------------- thresholds
def thresholds(seed: int = 2) -> list[tuple[float, str, float]]:
    """(I, origin, rate of L > I for white χ²₁ innovations) for the table (a_f = 0.8)."""
    rng = np.random.default_rng(seed)
    d = rng.standard_normal(4_000_000) ** 2
    stat = lfilter([1.0], [1.0, -A_F], d)[100:]  # seed 002 eq. (11), d ~ χ²₁ (eq. 12)
    m = round(1.0 / (1.0 - A_F))
    out = [(PAPER_I1, "seed 002 Table 3 (I1 \"like 7.5\")")]
    for p in (0.05, 0.01, 0.001):
        out.append((float(np.quantile(stat, 1.0 - p)), f"exact (simulated) {p:g} quantile of L"))
    out.append((end_threshold(m, 0.05), "χ²₅ 95 % (I2 default; L read as χ²_M)"))
    out.append((end_threshold(m, 0.01), "χ²₅ 99 %"))
    out.append((detection_threshold(A_F, 1e-3), "moment-matched 1e-3 (I1 default)"))
    return sorted((i, o, float(np.mean(stat > i))) for i, o in out)


def delay_table(meas: dict[str, np.ndarray], t: np.ndarray, sigma_m: dict[str, float]
                ) -> list[dict[str, Any]]:
    """Mean delay of L > I after each onset and false alarms per quiet step, per threshold,
    from L of the two-state filter (via a Kalman-filter replay of each run's measurements)."""
    from axir.models.filters.kalman import KalmanCV

    Ls = {}
    for name, z in meas.items():
        cfg = FilterConfig(sigma_m=sigma_m[name], sigma_meas=100.0, a_f=A_F)
        arr = np.empty_like(z)
        for i, row in enumerate(z):
            f = KalmanCV(cfg)
            for k, zk in enumerate(row):
                f.update(float(zk), 1.0)
                arr[i, k] = f.statistic
        Ls[name] = arr
    rows = []
    for thr, origin, chi_rate in thresholds():
        row: dict[str, Any] = {"I": thr, "origin": origin, "white_chi2_rate": chi_rate}
        for name, stat in Ls.items():
            win = maneuver_windows(load_scenario(name))
            p = periods(t, win)
            above = stat > thr
            row[f"{name}_false_alarm"] = float(above[:, p.quiet].mean())
            delays = []
            for on, off, _a in win:
                w = (t >= on) & (t < off + SETTLE)
                d = [float(t[w][np.argmax(r[w])] - on) for r in above if r[w].any()]
                delays.append((float(np.mean(d)) if d else math.nan, len(d) / len(above)))
            row[f"{name}_delays"] = delays
        rows.append(row)
    return rows


# ----------------------------------------------------------------------------- report
def markdown(blob: dict[str, Any]) -> str:
    L = ["# Seed 002: sensitivity to the unstated constants", "",
         f"Generated by `reports/seed002_constants.py`; {blob['runs']} runs per campaign, seeds "
         f"{blob['seed']}..{blob['seed'] + blob['runs'] - 1} (the seeds of `reports/seed002.py`"
         "), range filter's own flag. RMS errors per period as in `seed002.md` (*maneuver* = "
         "[onset, offset), *after* = 20 s after each offset, *quiet* = the rest from 10 s).", ""]
    L += ["## 1. SVD/VD as a function of σa (SVD Q_u = σa²) and σj (VD jerk density σj²)", ""]
    for name in SCENARIOS:
        for end in END_RULES:
            L += [f"### {name}, SVD with `fmd_end = {end}`: SVD/VD RMS range ratio maneuver / "
                  "after / quiet", "",
                  "| σa [m/s²] (Q_u) | " + " | ".join(f"VD σj = {sj:g}" for sj in SIGMA_J)
                  + " |", "|---|" + "---|" * len(SIGMA_J)]
            for sa in SIGMA_A:
                cells = []
                for sj in SIGMA_J:
                    r = next(x for x in blob["sweep"]["rows"] if x["scenario"] == name
                             and x["fmd_end"] == end and x["sigma_a"] == sa
                             and x["sigma_j"] == sj)
                    cells.append(" / ".join(fmt(r[f"ratio_range_{p}"], 2)
                                            for p in ("maneuver", "after", "quiet")))
                L.append(f"| {sa:g} ({sa * sa:g}) | " + " | ".join(cells) + " |")
            L.append("")
        L += [f"### {name}: RMS range error [m] maneuver / after / quiet, and detection", "",
              "| filter | setting | range RMS | mean delay per maneuver [s] | false alarms |",
              "|---|---|---|---|---|"]
        for key, x in blob["metrics"].items():
            n, f, sigma, end = key.split("|")
            if n != name:
                continue
            setting = (f"σa = {sigma}, {end}" if f == "svd" else f"σj = {sigma}")
            rms = " / ".join(fmt(x[f"rms_range_{p}"], 1) for p in ("maneuver", "after", "quiet"))
            dl = ", ".join(fmt(d["mean_delay_s"], 1) for d in x["detection"])
            L.append(f"| {f} | {setting} | {rms} | {dl} | "
                     f"{fmt(100 * x['false_alarm_fraction'], 2)} % |")
        L.append("")
    t3 = blob["table3"]
    L += ["## 2. Table 3 register ranges vs Q_u (reduced SVD, float, recorded measurements)", "",
          "Peaks of |register| over all runs and steps ≥ 2; `Pu` is the register of eq. (36) "
          "(Table 5 U23: P_u = [1 − K_u U1]·(P_u + Q_u), the sum P_u + Q_u = `Pu_pred` is an "
          "adder output, not a register). P_u, K_u, U, V do not depend on the measurements.",
          "",
          "| Q_u [m²/s⁴] | σm | " + " | ".join(TABLE3_COLUMNS) + " |",
          "|---|---|" + "---|" * len(TABLE3_COLUMNS),
          "| Table 3 | — | " + " | ".join(f"0 to {TABLE3[c.replace('_pred', '')]:g}"
                                          for c in TABLE3_COLUMNS) + " |"]
    for r in t3["peaks"]:
        L.append(f"| {r['qu']:g} | {r['sigma_m']:g} | "
                 + " | ".join(f"{r['peak'][c]:.3g}" for c in TABLE3_COLUMNS) + " |")
    L += ["", "Q_u that puts the peak at the Table 3 upper end: "
          + "; ".join(f"σm = {k}: P_u → 110 at Q_u = {v['Pu']:.1f}, "
                      f"K_u → 0.05 at Q_u = {v['Ku']:.1f}" for k, v in t3["fit"].items()) + ".",
          ""]
    L += ["## 3. Detection threshold vs delay vs false alarms (a_f = 0.8)", "",
          "L(k) of the two-state filter (the same for SVD, VD and Kalman until the detection) on "
          "the recorded measurements; delay = mean time from the onset to the first L > I "
          "(fraction of runs detecting in brackets); false alarms = fraction of quiet steps "
          "with L > I; white χ²₁ = rate of L > I for ideal innovations (4·10⁶ samples).", "",
          "| I | origin | white χ²₁ | svd-1 false alarms | svd-1 delay | svd-2 false alarms "
          "| svd-2 delays |", "|---|---|---|---|---|---|---|"]
    for r in blob["thresholds"]:
        cells = [fmt(r["I"], 2), r["origin"], f"{100 * r['white_chi2_rate']:.2f} %"]
        for name in SCENARIOS:
            cells.append(f"{100 * r[f'{name}_false_alarm']:.2f} %")
            cells.append(", ".join(f"{fmt(d, 1)} s ({fmt(p, 2)})" for d, p in
                                   r[f"{name}_delays"]))
        L.append("| " + " | ".join(cells) + " |")
    L.append("")
    return "\n".join(L) + "\n"


TABLE3_COLUMNS = ("Pu", "Pu_pred", "Ku", "U1", "V1", "U2", "V2", "u", "L")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--fmu-dir", type=Path, default=None)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    with fmu_directory(args.fmu_dir) as fmu_dir:
        results = run_sweep(fmu_dir, args.runs, args.workers, args.seed)
    windows = {n: maneuver_windows(load_scenario(n)) for n in SCENARIOS}
    m = {key: metrics(res, windows[key[0]], range_filter_replay(res))
         for key, res in results.items()}
    sigma_m = {n: float(load_scenario(n).units["Tracker"]["parameters"]["filter_sigma_m"])
               for n in SCENARIOS}
    meas = {n: _recorded(results[(n, "vd", SIGMA_J[0], "acceleration")],
                         "TargetGenerator.meas.range") for n in SCENARIOS}
    t = results[(SCENARIOS[0], "vd", SIGMA_J[0], "acceleration")].aggregates.t
    peaks = [{"qu": qu, "sigma_m": sigma_m[n], "scenario": n,
              "peak": register_peaks(meas[n], sigma_m[n], qu)}
             for qu in QU_TABLE3 for n in SCENARIOS]
    fit = {f"{sigma_m[n]:g}": {reg: qu_for_peak(sigma_m[n], reg, target)
                               for reg, target in (("Pu", 110.0), ("Ku", 0.05))}
           for n in SCENARIOS}
    blob = {"runs": args.runs, "seed": args.seed,
            "metrics": {f"{n}|{f}|{s:g}|{e}": v for (n, f, s, e), v in m.items()},
            "sweep": sweep_tables(m), "table3": {"peaks": peaks, "fit": fit},
            "thresholds": delay_table(meas, t, sigma_m)}
    (args.out / "seed002_constants.md").write_text(markdown(blob), encoding="utf-8")
    (args.out / "seed002_constants.json").write_text(json.dumps(_clean(blob), indent=1) + "\n",
                                                     encoding="utf-8")
    print(f"seed002_constants: wrote {args.out}/seed002_constants.md, .json", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
