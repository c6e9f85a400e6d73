"""Fixed-point emulation of the seed-002 SVD filter (Table 3 word lengths), and its error table.

Seed 002 §"The Simulation Level" sizes every bus of the FPGA SVD filter to 8, 12 or 16 bits
and lists, per variable, the range, the bus width and a "maximum error" (Table 3). This module
turns that table into quantisers and injects them into the one reduced-form implementation
(:class:`axir.models.svd.SVDReducedFilter`: every register assignment passes through the hook
``Q(name, value)``; no second copy of the equations).

Number format (# assumption: the seed gives only range and width):

- sign-magnitude: the n bits hold |x| with LSB = max/2ⁿ (max = the upper end of the stated
  range), plus a sign. With LSB = max/2ⁿ, LSB/2 reproduces the seed's maximum-error column for
  X1 (38), P (1.22), K (0.002), P_u (0.014), K_u (0.0001), u (0.1); the innovation R, the
  velocity X2 and the acceleration u are signed in any maneuver, which "0 to …" ranges cannot
  hold, hence the sign;
- rounding to nearest, ties to even (Python ``round``), as a rounding adder would after a
  multiplier or divider; saturation at ±(2ⁿ − 1)·LSB, as a saturating hardware register;
- the scalar constants without a stated range (σr "like 100", σm "like 5 / 20", I1 "like 7.5",
  I2 "like 11.04") share one 8-bit format whose LSB is twice the stated error 0.2: LSB = 0.4,
  range 0…102; a_f has its stated range 0…1 on 8 bits (LSB 1/256);
- not in Table 3, with the format of the bus they feed: the measurement Y (X1 format), the
  process-noise products q·q_ij (P format), Q_u (P_u format), the predicted covariances
  h1, h2, g3 + f2 of Table 6 (format "h" = the N bus: 12 bits, 0…7·10⁴; N = h1 + σr², and at
  the start h1 ≈ 5σr² = 5·10⁴ would saturate the 0…10⁴ P bus) and P(0/0) (the U02
  multiplexers feed σr²[[1, 1], [1, 2]] into the first prediction; 2σr² exceeds the P bus).
  T = 1 s is a wire (no bus).
- With P(0/0) and the predicted covariances on the 0…10⁴ P bus instead, the covariance
  saturates in the first steps, loses positive definiteness and the filter diverges (N → 0):
  that is why these two choices are needed to make Table 3 work at all.

Where the seed's error column is not LSB/2 of its own row it is the largest LSB/2 of the row's
group: L, N, R, d all list 9 (N: 7·10⁴/2¹²/2 = 8.5); V1, V2, U1, U2, P_u list 0.014 (P_u:
0.0134); X2 lists 38, the X1 figure (its own LSB/2 is 0.076 m/s); a_f lists 0.2, the
constants' figure. The table printed by ``python -m axir.models.fixedpoint`` gives both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Format:
    """Sign-magnitude fixed-point format: ``bits`` magnitude bits, LSB = ``max_abs``/2^bits.

    Attributes:
        bits: magnitude bits (the seed's bus width).
        max_abs: upper end of the seed's range [unit of the variable].
        paper_error: the seed's "maximum error" for this variable (Table 3).
        text: the seed's range as printed.
    """

    bits: int
    max_abs: float
    paper_error: float
    text: str = ""

    @property
    def lsb(self) -> float:
        return self.max_abs / 2 ** self.bits

    @property
    def largest(self) -> float:
        """Largest representable magnitude (2ⁿ − 1)·LSB."""
        return (2 ** self.bits - 1) * self.lsb

    def quantise(self, x: float) -> tuple[float, bool]:
        """(stored value, saturated): nearest multiple of the LSB (ties to even), clipped to
        ±(2ⁿ − 1)·LSB. NaN stays NaN."""
        if math.isnan(x):
            return x, False
        lsb = self.lsb
        top = 2 ** self.bits - 1
        m = abs(x) / lsb
        if m > top:
            return math.copysign(top * lsb, x), True
        return math.copysign(round(m) * lsb, x), False


_CONST = 102.4  # 8-bit constants: LSB 0.4 = 2 × the seed's 0.2 maximum error

#: Seed 002 Table 3 (variable names of the reduced form, eqs. 30-39) → format.
TABLE3: dict[str, Format] = {
    "X1": Format(16, 5e6, 38.0, "0 to 5e6 m"),
    "X2": Format(16, 1e4, 38.0, "0 to 1e4 m/s"),
    "P": Format(12, 1e4, 1.22, "0 to 1e4"),
    "K": Format(8, 1.0, 0.002, "0 to 1"),
    "s_r": Format(8, _CONST, 0.2, "like 100 m"),
    "s_m": Format(8, _CONST, 0.2, "like 5 and 20 m/s²"),
    "L": Format(12, 7000.0, 9.0, "0 to 7000"),
    "N": Format(12, 7e4, 9.0, "0 to 7e4 m²"),
    "h": Format(12, 7e4, 9.0, "(N bus) predicted P, P(0/0)"),
    "R": Format(12, 6000.0, 9.0, "0 to 6000 m"),
    "d": Format(12, 2e4, 9.0, "0 to 2e4"),
    "I1": Format(8, _CONST, 0.2, "like 7.5"),
    "I2": Format(8, _CONST, 0.2, "like 11.04"),
    "a_f": Format(8, 1.0, 0.2, "0 to 1"),
    "V1": Format(12, 21.0, 0.014, "0 to 21"),
    "V2": Format(12, 7.0, 0.014, "0 to 7"),
    "U1": Format(12, 28.0, 0.014, "0 to 28"),
    "U2": Format(12, 8.0, 0.014, "0 to 8"),
    "Pu": Format(12, 110.0, 0.014, "0 to 110"),
    "Ku": Format(8, 0.05, 0.0001, "0 to 0.05"),
    "u": Format(8, 60.0, 0.1, "0 to 60 m/s²"),
}


@dataclass
class TableQuantiser:
    """The hook ``Q(name, value)`` of :class:`axir.models.svd.SVDReducedFilter` for Table 3.

    Keeps statistics per register name: number of operations, saturations, and the largest
    rounding error |Q(v) − v| of a non-saturated operation (the error one register adds to the
    value computed from its — already quantised — inputs).
    """

    formats: dict[str, Format] = field(default_factory=lambda: dict(TABLE3))
    ops: dict[str, int] = field(default_factory=dict)
    saturated: dict[str, int] = field(default_factory=dict)
    max_rounding: dict[str, float] = field(default_factory=dict)

    def __call__(self, name: str, value: float) -> float:
        q, sat = self.formats[name].quantise(value)
        self.ops[name] = self.ops.get(name, 0) + 1
        if sat:
            self.saturated[name] = self.saturated.get(name, 0) + 1
        else:
            err = abs(q - value)
            if err > self.max_rounding.get(name, 0.0):
                self.max_rounding[name] = err
        return q


# ------------------------------------------------------------------ error table
#: registers compared between the fixed-point and the float64 reduced filter
REGISTERS = ("X1", "X2", "P11", "P12", "P21", "P22", "K1", "K2", "u", "Pu", "Ku", "U1", "U2",
             "V1", "V2", "L")
#: format of each compared register
REGISTER_FORMAT = {"P11": "P", "P12": "P", "P21": "P", "P22": "P", "K1": "K", "K2": "K"}

#: seed-002 scenarios (svd-1, svd-2 as the shipped scenario files define them):
#: σm [m/s²] and the radial acceleration profile [(onset s, end s, m/s²)]
SCENARIOS: dict[str, tuple[float, list[tuple[float, float, float]]]] = {
    "svd-1": (5.0, [(30.0, 50.0, 20.0)]),
    "svd-2": (20.0, [(30.0, 40.0, 50.0), (60.0, 70.0, -50.0)]),
}


def radial_truth(profile: list[tuple[float, float, float]], n: int
                 ) -> tuple[np.ndarray, np.ndarray]:
    """True range and range rate at t = 1 … n s of a target receding from 1000 m at 250 m/s
    with the acceleration steps ``profile`` (seed 002 §7)."""
    t = np.arange(1.0, n + 1.0)
    r = 1000.0 + 250.0 * t
    v = np.full_like(t, 250.0)
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
    from .axisfilter import FilterConfig
    from .svd import SVDReducedFilter

    rng = np.random.default_rng(seed)
    worst = dict.fromkeys(REGISTERS, 0.0)
    worst_late = dict.fromkeys(REGISTERS, 0.0)
    quant = TableQuantiser()
    scen: dict[str, dict[str, float]] = {}
    for name, (sigma_m, profile) in SCENARIOS.items():
        cfg = FilterConfig(sigma_m=sigma_m, sigma_meas=sigma_r)
        truth_r, truth_v = radial_truth(profile, n)
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
    """Print the fixed-point error table (``python -m axir.models.fixedpoint``)."""
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
