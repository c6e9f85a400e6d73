"""Error table of the seed-002 fixed-point SVD filter (Table 3 word lengths) vs float64.

Runs the one reduced-form implementation (:class:`axir.models.filters.svd.SVDReducedFilter`)
in float64 and with the Table 3 quantiser (:class:`axir.models.filters.fixedpoint.TableQuantiser`)
on the same seeded measurements of the shipped svd-1 and svd-2 scenarios (σm and maneuver
profile read from the scenario files) and prints, per Table 3 variable, the LSB, the seed's
maximum error, the largest rounding per operation, the saturations and the propagated error
(docs/fixed_point.md).

Usage: ``.venv/bin/python reports/fixed_point.py`` (≈ 3 s; prints markdown).
"""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any

import numpy as np

from axir.models.filters.base import FilterConfig
from axir.models.filters.fixedpoint import TABLE3, TableQuantiser
from axir.models.filters.svd import SVDReducedFilter
from axir.orchestrator.scenario import load_scenario

#: registers compared between the fixed-point and the float64 reduced filter
REGISTERS = ("X1", "X2", "P11", "P12", "P21", "P22", "K1", "K2", "u", "Pu", "Ku", "U1", "U2",
             "V1", "V2", "L")
#: format of each compared register
REGISTER_FORMAT = {"P11": "P", "P12": "P", "P21": "P", "P22": "P", "K1": "K", "K2": "K"}

#: the seed-002 scenarios of the table (shipped scenario files)
SCENARIO_NAMES = ("svd-1", "svd-2")


def radial_scenario(name: str) -> tuple[float, float, float, list[tuple[float, float, float]]]:
    """(σm [m/s²], r(0) [m], v(0) [m/s], radial acceleration profile [(onset s, end s, m/s²)])
    of a shipped seed-002 scenario (target receding along the x axis: range = x)."""
    sc = load_scenario(name)
    sigma_m = float(sc.units["Tracker"]["parameters"]["filter_sigma_m"])
    traj = json.loads(sc.units["TargetGenerator"]["parameters"]["trajectory"])
    profile = [(float(s["onset"]), float(s["offset"]), float(s["acceleration"][0]))
               for s in traj["segments"]]
    return sigma_m, float(traj["position"][0]), float(traj["velocity"][0]), profile


def radial_truth(profile: list[tuple[float, float, float]], n: int, r0: float = 1000.0,
                 v0: float = 250.0) -> tuple[np.ndarray, np.ndarray]:
    """True range [m] and range rate [m/s] at t = 1 … n s of a target receding from ``r0`` [m]
    at ``v0`` [m/s] (seed 002 §7: 1000 m, 250 m/s) with the acceleration steps ``profile``."""
    t = np.arange(1.0, n + 1.0)
    r = r0 + v0 * t
    v = np.full_like(t, v0)
    for on, off, acc in profile:
        tau = np.clip(t - on, 0.0, off - on)
        r += acc * tau * tau / 2 + acc * (off - on) * np.clip(t - off, 0.0, None)
        v += acc * tau
    return r, v


def _registers(f: Any) -> dict[str, float]:
    return {name: (f.fmd.L if name == "L" else getattr(f, name)) for name in REGISTERS}


def error_table(runs: int = 50, n: int = 100, transient: int = 10, seed: int = 1,
                sigma_r: float = 100.0) -> dict[str, Any]:
    """Run the reduced SVD filter in float64 and in Table-3 fixed point on the same seeded
    measurements (svd-1 and svd-2, ``runs`` Monte Carlo runs each, T = 1 s) and collect, per
    register: max |fixed − float| over all steps and after the first ``transient`` steps; the
    quantiser's per-operation statistics; per scenario the RMS output errors against the truth
    (float and fixed, steps ≥ ``transient``) and the maneuver-flag agreement.
    """
    rng = np.random.default_rng(seed)
    worst = dict.fromkeys(REGISTERS, 0.0)
    worst_late = dict.fromkeys(REGISTERS, 0.0)
    quant = TableQuantiser()
    scen: dict[str, dict[str, float]] = {}
    for name in SCENARIO_NAMES:
        sigma_m, r0, v0, profile = radial_scenario(name)
        cfg = FilterConfig(sigma_m=sigma_m, sigma_meas=sigma_r)
        truth_r, truth_v = radial_truth(profile, n, r0, v0)
        sq = np.zeros(4)  # Σ squared errors: range float, range fixed, velocity float, fixed
        count = flags_equal = steps = 0
        for _ in range(runs):
            z = truth_r + rng.normal(0.0, sigma_r, n)
            ref = SVDReducedFilter(cfg)
            fix = SVDReducedFilter(replace(cfg, quant=quant))
            for k, zk in enumerate(z):
                ref.update(float(zk), 1.0)
                fix.update(float(zk), 1.0)
                if k < 2:
                    continue
                a, b = _registers(ref), _registers(fix)
                for reg in REGISTERS:
                    e = abs(a[reg] - b[reg])
                    worst[reg] = max(worst[reg], e)
                    if k >= transient:
                        worst_late[reg] = max(worst_late[reg], e)
                steps += 1
                flags_equal += ref.maneuver == fix.maneuver
                if k >= transient:
                    xr, xf = ref.x, fix.x
                    sq += np.square([xr[0] - truth_r[k], xf[0] - truth_r[k],
                                     xr[1] - truth_v[k], xf[1] - truth_v[k]])
                    count += 1
        rms = np.sqrt(sq / count)
        scen[name] = {"rms_range_float": rms[0], "rms_range_fixed": rms[1],
                      "rms_vel_float": rms[2], "rms_vel_fixed": rms[3],
                      "flag_agreement": flags_equal / steps}
    return {"worst": worst, "worst_late": worst_late, "quant": quant, "scenarios": scen,
            "runs": runs, "n": n, "transient": transient}


def format_table(res: dict[str, Any]) -> str:
    """Markdown table of :func:`error_table` results."""
    q: TableQuantiser = res["quant"]
    rows = ["| variable | Table 3 range | bits | LSB | LSB/2 | seed max error | max rounding "
            "per operation | saturated / operations | max error vs float64 (all steps) | "
            f"(steps ≥ {res['transient']}) |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    names = list(TABLE3)
    for name in names:
        fmt = TABLE3[name]
        regs = [r for r in REGISTERS if REGISTER_FORMAT.get(r, r) == name]
        prop = ", ".join(f"{r} {res['worst'][r]:.4g}" for r in regs) or "—"
        late = ", ".join(f"{r} {res['worst_late'][r]:.4g}" for r in regs) or "—"
        rows.append(
            f"| {name} | {fmt.text} | {fmt.bits} | {fmt.lsb:.4g} | {fmt.lsb / 2:.4g} | "
            f"{fmt.paper_error:g} | {q.max_rounding.get(name, 0.0):.4g} | "
            f"{q.saturated.get(name, 0)} / {q.ops.get(name, 0)} | {prop} | {late} |")
    return "\n".join(rows)


def main() -> None:
    """Print the fixed-point error table (``.venv/bin/python reports/fixed_point.py``)."""
    res = error_table()
    print(f"SVD reduced form, Table 3 fixed point vs float64: svd-1 and svd-2, "
          f"{res['runs']} runs x {res['n']} s each, T = 1 s, σr = 100 m")
    print(format_table(res))
    print()
    print(f"| scenario | RMS range error float / fixed [m] | RMS range-rate error float / fixed "
          f"[m/s] | maneuver flag equal |  (steps ≥ {res['transient']})")
    print("|---|---|---|---|")
    for name, v in res["scenarios"].items():
        print(f"| {name} | {v['rms_range_float']:.1f} / {v['rms_range_fixed']:.1f} | "
              f"{v['rms_vel_float']:.1f} / {v['rms_vel_fixed']:.1f} | "
              f"{100 * v['flag_agreement']:.1f} % |")


if __name__ == "__main__":
    main()
