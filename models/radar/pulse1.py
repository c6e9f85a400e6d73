"""Helpers of the TargetGenerator's one-pulse path (issue 14: per-PRI overhead).

No equation of their own: they prepare operands of the front-end equations of
``models/target_generator.py`` (module docstring: target echo, AR(1) clutter, Doppler
filters y = p·y + (1 − ρ)·x) so that numpy forms the same products with fewer or cheaper calls.
"""

from __future__ import annotations

import math
import struct
from functools import partial
from typing import Any

import numpy as np

from .antenna import FOUR_LN2, MonopulseAntenna
from .conventions import N_BEAMS, N_BINS, N_DOPPLER


def complex0d(v: float) -> np.ndarray:
    """``v`` as a 0-d complex array. numpy casts a Python float that multiplies a complex array
    to exactly this (v + 0j) and forms the same products; a 0-d array skips the per-call
    conversion of the Python scalar (≈ 1 µs per operation on a (4, 16) array)."""
    return np.array(complex(v))


def ar1_rows(x: np.ndarray, rho: float, prev: np.ndarray) -> np.ndarray:
    """The AR(1) clutter recursion c[k] = ρc·c[k − 1] + x[k] (TargetGenerator module
    docstring, c[n] = ρc c[n−1] + √(CNR (1 − ρc²)) u[n]; x = the scaled innovation) over
    axis 0 of ``x`` (pulses, 16) complex [√W], in place, from c[−1] = ``prev`` (16,); returns
    ``x``. Row by row on the float64 views: per value x + ρ·c, the very products and sums of
    scipy's ``lfilter([1], [1, −ρ], x, axis=0, zi=ρ·prev)`` (y = b0·x + z, z = −a1·y, with
    b0 = 1 and −a1 = ρ), so the same bytes for finite values (tested against lfilter) without
    importing scipy.signal (≈ 1 s of every start-up; issue 14, session 6). ``x`` must be
    C-contiguous along its last axis, ``prev`` no row of ``x``."""
    xf = x.view(np.float64)
    ar1_float_rows(list(xf), rho, np.ascontiguousarray(prev), np.empty(xf.shape[1:]))
    return x


def ar1_float_rows(rows: list[np.ndarray], rho: float, prev: np.ndarray, t: np.ndarray
                   ) -> None:
    """:func:`ar1_rows`' loop on ``rows``, the float64 views (2·bins,) of the complex rows,
    in place from c[−1] = ``prev`` (complex, C-contiguous, no row of ``rows``); ``t`` a
    float64 scratch of a row's shape. The owner of a block keeps its row views (issue 14,
    round 4: no view made per row and block)."""
    r = np.array(float(rho))  # 0-d: no per-call conversion of the Python scalar
    p = prev.view(np.float64)
    mul, add = np.multiply, np.add
    for row in rows:  # out passed positionally: no keyword parsing (≈ 0.1 µs per pair)
        mul(p, r, t)  # ρ·c[k − 1] (complex × real: ρ·re, ρ·im)
        add(row, t, row)  # x[k] + ρ·c[k − 1]
        p = row


def target_row_struct(j: int, b0: int = 0, b1: int = N_BEAMS) -> struct.Struct:
    """``struct`` layout of a (4, 16, 3) complex row (C order, native float64 = numpy's
    layout) holding the target's two bins j, j + 1 of each beam, each value once per Doppler
    filter: per beam 12 floats (re, im of bin j for filters 1, 2, 3, then of bin j + 1), every
    other byte written as zero (pad bytes ``x``); ``pack_into`` fills the whole row. With
    ``b0``, ``b1``: the part of the row of beams b0 … b1 − 1 only (offset b0 × a beam's bytes),
    12·(b1 − b0) floats."""
    item = np.dtype(complex).itemsize
    per_beam = N_BINS * N_DOPPLER * item
    n = 2 * N_DOPPLER * 2  # floats per beam
    fmt, pos = "=", 0
    for b in range(b1 - b0):
        start = b * per_beam + j * N_DOPPLER * item
        fmt += f"{start - pos}x{n}d"
        pos = start + n * 8
    st = struct.Struct(fmt + f"{(b1 - b0) * per_beam - pos}x")
    assert st.size == (b1 - b0) * per_beam
    return st


class PulseCache:
    """Derived buffers of the one-pulse path (issue 14, round 3); not part of the state: rebuilt
    from it (draw block, clutter c, PRI, ρ, pre-added clutter gains) when any of them changes.

    For the rows i … of the draw block ``blk`` (pulses, 162) [normals × √½] it holds the
    Doppler-filter input before the target echo, already scaled by s = 1 − ρ (the filters'
    input gain, folded in front of the MTI canceller: both are linear):

        xb[k] = s·w[k] + (s·gp) ⊗ c[k]        (gp: the clutter gains pre-added for the block)

    with the AR(1) clutter c[k] = ρc c[k − 1] + b u[k] (TargetGenerator module docstring) run
    over the block by :func:`ar1_rows` (the same products and sums as the per-pulse
    recursion c = ρc c + b u: bit-identical, tested), and the same rows replicated over the
    3 Doppler filters (``x3b``), into which the owner adds the pulse's target echo.
    """

    def __init__(self, blk: np.ndarray, n_noise: int) -> None:
        cx = blk[:, : n_noise + 2 * N_BINS].view(complex)  # CN(0, 1) pairs
        n = blk.shape[0]
        self.blk = blk
        self.noise = cx[:, : n_noise // 2].reshape(n, N_BEAMS, N_BINS)  # w (pulses, 4, 16)
        self.u = cx[:, n_noise // 2 :]  # clutter innovation u (pulses, 16)
        self.xb = np.empty((n, N_BEAMS, N_BINS), dtype=complex)
        #: the rows replicated over the 3 Doppler filters (pulses, 4, 16, 3), C order, made by
        #: ``fill``: the filters' input x[n] broadcast once per block, so that the per-pulse
        #: adds (target, filters) are same-shape contiguous operations — numpy's fast path,
        #: ≈ 0.6 µs each instead of ≈ 1.9 for the (4, 16, 1) broadcast and ≈ 1.8 for the
        #: (4, 2) strided target block (issue 14, spd13). Each copy holds the same values.
        self.x3b = np.empty((n, N_BEAMS, N_BINS, N_DOPPLER), dtype=complex)
        # per-row views made once (a list index is cheaper than an array index per pulse)
        self.x3rows = list(self.x3b)
        self.x3f = [self.x3b[:, :, :, f] for f in range(N_DOPPLER)]  # each filter's copies
        self.xrows = [r[:, :, 0] for r in self.x3rows]  # x[n] (4, 16) (filter 1's copy)
        self.row1 = [self.x3b[k : k + 1, :, :, 0] for k in range(n)]  # as (1, 4, 16) views
        #: the target's contribution to a row (4, 16, 3), zero outside its two bins;
        #: t3_lo[j](24 floats) and t3_hi[j](24 floats) write it for bins j, j + 1, beams 0-1
        #: and 2-3 (``struct.pack_into`` on its buffer, :func:`target_row_struct`), every
        #: other value +0.0: two calls of 24 arguments, as CPython 3.11 passes up to 30 on the
        #: stack and builds a list, then a tuple, for more (48 LIST_APPENDs per pulse, issue 14)
        self.t3 = np.zeros((N_BEAMS, N_BINS, N_DOPPLER), dtype=complex)
        mv = memoryview(self.t3).cast("B")
        half = N_BEAMS // 2
        off = half * N_BINS * N_DOPPLER * self.t3.itemsize
        self.t3_lo = [partial(target_row_struct(j, 0, half).pack_into, mv, 0)
                      for j in range(N_BINS - 1)]
        self.t3_hi = [partial(target_row_struct(j, half, N_BEAMS).pack_into, mv, off)
                      for j in range(N_BINS - 1)]
        self.cb: np.ndarray = np.empty((n, N_BINS), dtype=complex)  # c[k] of the block
        self.crows = list(self.cb)
        self.cfrows = list(self.cb.view(np.float64))  # c[k] as float64 (re, im) rows
        self.ct = np.empty(2 * N_BINS)  # scratch row of the AR(1) loop
        #: s·gp (1, 4, 1) and the (pulses, 4, 32) float64 product (s·gp) ⊗ c of ``fill``
        self.gs = np.zeros((1, N_BEAMS, 1))
        self.gc = np.empty((n, N_BEAMS, 2 * N_BINS))
        self.mo = np.empty((N_BEAMS, N_BINS), dtype=complex)  # MTI output
        self.mo3 = self.mo[:, :, None]
        self.mt = np.empty((N_BEAMS, N_BINS), dtype=complex)  # MTI product scratch
        self.xc = np.empty((N_BEAMS, N_BINS), dtype=complex)  # clutter correction scratch
        self.xc3 = self.xc[:, :, None]
        self.key: tuple[Any, ...] | None = None  # (pri, s, gp, noise) of the rows
        self.c_last: Any = None  # the row of cb the owner's c refers to (identity)
        self.dkey: Any = None  # (gains, gp) of the correction column ``dcol``
        self.dcol = np.zeros((N_BEAMS, 1))
        self.pkey: Any = None  # the filter poles p_f (3,) that ``P`` broadcasts (identity)
        #: (doppler.centre [Hz], PRI [s]) of ``P``: the owner re-forms it when they change
        self.pin: tuple[float, float] = (math.nan, math.nan)
        self.P = np.zeros((N_BEAMS, N_BINS, 3), dtype=complex)  # p_f over every cell

    def __deepcopy__(self, memo: dict[int, Any]) -> None:
        """A copied owner rebuilds its own buffers (views of its own draw block)."""
        return None

    def __reduce__(self) -> tuple[Any, tuple[()]]:
        """Pickled as None, like a deep copy: an unpickled owner rebuilds its buffers (they
        hold a memoryview and a ``struct.Struct`` method, which do not pickle)."""
        return _no_cache, ()

    def fill(self, i: int, s: float, c: np.ndarray, clutter: tuple[float, float] | None,
             gp: tuple[float, ...], noise: bool) -> None:
        """Build rows i … of ``xb``, ``x3b`` (and ``cb``) from the clutter ``c`` (16,) of the pulse
        before row i; ``s`` = 1 − ρ; ``clutter`` = (ρc, b) or None (off); ``gp`` the (4)
        clutter gains [1] pre-added (zeros: none); ``noise`` thermal noise on/off."""
        xb = self.xb[i:]
        if noise:
            np.multiply(self.noise[i:], s, out=xb)
        else:
            xb.fill(0.0)
        if clutter is not None:
            rho_c, b_c = clutter
            c = c.copy()  # it may be a row of cb (the last one at a new block): read it first
            cb = np.multiply(self.u[i:], b_c, out=self.cb[i:])
            ar1_float_rows(self.cfrows[i:], rho_c, c, self.ct)  # = ar1_rows(cb, rho_c, c)
            if any(gp):  # xb += (s·gp) ⊗ c: the complex × real products on the parts
                self.gs[0, :, 0] = [g * s for g in gp]
                gc = np.multiply(self.gs, cb.view(np.float64)[:, None, :], out=self.gc[i:])
                xbf = xb.view(np.float64)
                xbf += gc
        for x3f in self.x3f:  # the rows' copies for the 3 filters (3 strided copies:
            x3f[i:] = xb  # ≈ 9 µs per block, a (…, 1) → (…, 3) broadcast ≈ 15 µs)

    def poles(self, pf: np.ndarray) -> np.ndarray:
        """The filter poles ``pf`` (3,) broadcast to every cell (4, 16, 3), formed once per
        ``pf`` array: y *= P forms the products of y *= pf without a per-call broadcast."""
        if self.pkey is not pf:  # written into P in place (a broadcast copy: ≈ 4 µs more)
            self.P[...] = pf
            self.pkey = pf
        return self.P

    def correction(self, g: tuple[float, ...], gp: tuple[float, ...], s: float) -> np.ndarray:
        """Column (4, 1) s·g − s·gp [1]: the clutter gains ``g`` of this pulse minus those
        pre-added in the rows (``gp``), scaled by ``s``; cached for the last (g, gp)."""
        if self.dkey is None or self.dkey[0] is not g or self.dkey[1] is not gp:
            self.dcol = np.array([a * s - b * s for a, b in zip(g, gp, strict=True)]
                                 ).reshape(N_BEAMS, 1)
            self.dkey = (g, gp)
        return self.dcol


def _no_cache() -> None:
    """What an unpickled :class:`PulseCache` becomes: nothing (its owner rebuilds it)."""
    return None


def take_rows(blk: np.ndarray, i: int, n: int, rng: np.random.Generator
              ) -> tuple[np.ndarray, int]:
    """(``n`` rows of normals × √½, the next unused row): the unused rows i … of the draw block
    ``blk`` (pulses, 162) first, then fresh draws from ``rng`` (one stream whatever the step
    lengths; the N-pulse path's draws)."""
    left = blk[i : i + n]
    if left.shape[0] == n:
        return left.copy(), i + n
    fresh = rng.standard_normal((n - left.shape[0], blk.shape[1])) * math.sqrt(0.5)
    return (np.concatenate((left, fresh)) if left.shape[0] else fresh), i + left.shape[0]


def clutter_gains_tuple(antenna: MonopulseAntenna, el_a: float, floor: float
                        ) -> tuple[float, float, float, float]:
    """Voltage gains (up, right, down, left) [1] of ``antenna`` toward the horizon at the
    antenna azimuth for antenna elevation ``el_a`` [rad], floored at ``floor`` [1] (sidelobes;
    TargetGenerator module docstring, ground clutter).

    geometry.boresight_offsets(az_a, 0, az_a, el_a) reduces exactly to lateral = 0 (π if the
    antenna is flipped past the zenith, cos el_a < 0) and elevation = asin(−sin el_a) (tested
    equal). max(g, floor) of Python floats: np.maximum's values, NaN kept.
    """
    lat_c = 0.0 if math.cos(el_a) >= 0.0 else math.pi
    el_c = math.asin(-math.sin(el_a))
    g0, g1, g2, g3 = (g if g >= floor or g != g else floor
                      for g in antenna.gains_tuple(lat_c, el_c))
    return g0, g1, g2, g3


#: upper end [rad] of the elevations where :func:`clutter_floor_elevation` applies (cos > 0)
FLOOR_EL_MAX = 1.5


def clutter_floor_elevation(antenna: MonopulseAntenna, floor: float) -> float:
    """Antenna elevation el_lo [rad] above which (up to :data:`FLOOR_EL_MAX`) every gain of
    :func:`clutter_gains_tuple` is the ``floor`` [1] (0 < floor ≤ 1).

    For 0 < s < el_a < π/2 the horizon is at elevation offset −el_a, and of the four gains
    (antenna.py) exp(−a(el_a + s)²) (up), exp(−a(el_a − s)²) (down), exp(−a(el_a² + s²))
    (right, left), the down beam's is the largest, decreasing in el_a; it equals the floor at
    s + √(−ln(floor)/a). A margin of 1e-6 rad (a relative gain margin ≈ 2a·1e-6·√(−ln(floor)/a),
    far above rounding) makes every gain strictly below the floor beyond el_lo.
    """
    a = 0.5 * FOUR_LN2 / antenna.beamwidth**2  # v(θ) = exp(−a θ²) (antenna.py)
    return antenna.squint + math.sqrt(-math.log(floor) / a) + 1e-6
