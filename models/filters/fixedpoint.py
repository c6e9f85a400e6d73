"""Fixed-point emulation of the seed-002 SVD filter: the Table 3 word lengths as quantisers.

Seed 002 §"The Simulation Level" sizes every bus of the FPGA SVD filter to 8, 12 or 16 bits
and lists, per variable, the range, the bus width and a "maximum error" (Table 3). This module
turns that table into quantisers and injects them into the one reduced-form implementation
(:class:`axir.models.filters.svd.SVDReducedFilter`: every register assignment passes through
the hook ``Q(name, value)``; no second copy of the equations).

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
constants' figure. The error table printed by ``reports/fixed_point.py`` gives both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


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
    """The hook ``Q(name, value)`` of :class:`axir.models.filters.svd.SVDReducedFilter` for Table 3.

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
