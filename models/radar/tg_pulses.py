"""The TargetGenerator's N-pulse path (a step of several PRIs, vectorised), moved out of
``models/target_generator.py`` (issue 14, round 8: that module was at the 600-line limit):
:func:`pulses`, ``TargetGenerator._pulses`` with the generator as its first argument, its
:func:`draws` (``TargetGenerator._draws``, round 11) and the layout of the per-pulse normal
draws both paths share.
"""

from __future__ import annotations

import math
from math import sqrt
from typing import Any

import numpy as np

from . import pulse1
from .conventions import BIN_M, N_BEAMS, N_BINS, N_DOPPLER, C
from .geometry import boresight_offsets_array
from .mti import MTI_TAPS, cancel_chunk, mti_switch
from .tg_outputs import MIN_RANGE

N_NOISE = 2 * N_BEAMS * N_BINS  # normals per pulse for the thermal noise (128)
N_CLUT = 2 * N_BINS  # normals per pulse for the clutter innovation (32)
BIN_OFFSETS = np.arange(N_BINS) * BIN_M  # bin r samples gate_start + (r − 1)·75 m (radar.py)


def pulses(gen: Any, times: np.ndarray, u: dict[str, float]) -> None:
    """Generate the pulses of the TargetGenerator ``gen`` at ``times`` [s] (vectorised) and
    run its Doppler filters; ``u``: the inputs as floats (antenna.az, antenna.el [rad],
    gate.start [m], doppler.centre [Hz], pri [s])."""
    n = times.shape[0]
    pri = u["pri"]
    ru = 0.5 * C * pri  # Ru = c·PRI/2 (radar.py)
    draws = gen._draws(n)  # fixed layout per pulse
    p, _v, _a = gen._traj.state(times)
    r, g = gen._geometry(p, u["antenna.az"], u["antenna.el"])
    if gen.swerling == 1:  # F ~ CN(0, 1) drawn at each dwell start, held in the dwell
        idx = gen._pulse + np.arange(n)
        new = idx % gen.dwell_pulses == 0
        fresh = draws[:, N_NOISE + N_CLUT] + 1j * draws[:, N_NOISE + N_CLUT + 1]
        last = np.maximum.accumulate(np.where(new, np.arange(n), -1))
        fl = np.where(last >= 0, fresh[np.maximum(last, 0)], gen._fluct)
        gen._fluct = complex(fl[-1])
    else:
        fl = 1.0
    # a(R)·F·exp(−j4πR/λ): radar equation (R⁻⁴ power), carrier phase → Doppler (radar.py)
    coef = (gen._a0 / (r * r)) * fl * np.exp(-4j * math.pi / gen.wavelength * r)
    # pulse straddle: triangular response, distances folded modulo Ru into [−Ru/2, Ru/2)
    dist = r[:, None] - u["gate.start"] - BIN_OFFSETS
    dist = (dist + 0.5 * ru) % ru - 0.5 * ru
    tri = np.maximum(1.0 - np.abs(dist) * (1.0 / BIN_M), 0.0)
    x = (coef[:, None] * g)[:, :, None] * tri[:, None, :]  # (n, 4, 16)
    if gen.noise:
        x += draws[:, :N_NOISE].view(complex).reshape(n, N_BEAMS, N_BINS)
    if gen.clutter:
        rho_c = math.exp(-2.0 * math.pi * gen.clutter_spread * pri)
        b_c = sqrt(gen._cnr * (1.0 - rho_c * rho_c))
        innov = draws[:, N_NOISE : N_NOISE + N_CLUT].view(complex) * b_c  # (n, 16)
        # c[k] = ρc c[k−1] + innov[k]: the AR(1) recursion, in place (lfilter's bytes)
        c = pulse1.ar1_rows(innov, rho_c, gen._c)
        gen._c = c[-1].copy()
        x += gen._clutter_gains(u["antenna.el"])[None, :, None] * c[:, None, :]
    x *= 1.0 - gen.pole  # the filters' input gain, in front of the (linear) canceller
    if gen.mti:  # MTI canceller over the chunk, the last pulses of the previous one first
        gen._mti_on = mti_switch(gen._mti_on, u["antenna.el"], gen.mti_max_el,
                                  gen.mti_hysteresis)
        x, gen._xh = cancel_chunk(x, gen._xh, MTI_TAPS[gen.mti], gen._mti_on)
    # Doppler filters, closed form of the recursion: y_N = p^N y_0 + (1 − ρ) Σ p^(N−1−k) x_k
    pf = gen._filter_poles(u["doppler.centre"], pri)
    w = pf[None, :] ** np.arange(n - 1, -1, -1)[:, None]  # (n, 3)
    gen._y = gen._y * pf**n + np.tensordot(x, w, axes=([0], [0]))
    gen._pulse += n


def draws(gen: Any, n: int) -> np.ndarray:
    """(n, 162) normals × √½ for ``n`` pulses of the TargetGenerator ``gen``
    (``TargetGenerator._draws``): the unused rows of the one-pulse path's draw block first,
    then fresh draws (one stream whatever the step lengths)."""
    rows, gen._dnext = pulse1.take_rows(gen._dblock, gen._dnext, n, gen._rng)
    return rows


def geometry(gen: Any, p: np.ndarray, az_a: float, el_a: float) -> tuple[np.ndarray, np.ndarray]:
    """Range R (n,) [m] (floored at 1 m) and beam voltage gains (n, 4) of the target
    positions ``p`` (n, 3) [m] for the antenna pointing (az_a, el_a) [rad] (the array forms
    of geometry.cart_to_sph, boresight_offsets and the antenna gains); ``gen`` the
    TargetGenerator (``TargetGenerator._geometry``)."""
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    h = np.hypot(x, y)
    r = np.maximum(np.hypot(h, z), MIN_RANGE)
    lat, elo = boresight_offsets_array(np.arctan2(x, y), np.arctan2(z, h), az_a, el_a)
    return r, gen._antenna.gains_array(lat, elo)


def clutter_gains(gen: Any, el_a: float) -> np.ndarray:
    """Voltage gains (4,) toward the horizon at the antenna azimuth, floored (sidelobes);
    :func:`radar.pulse1.clutter_gains_tuple` as an array (``TargetGenerator._clutter_gains``)."""
    return np.array(pulse1.clutter_gains_tuple(gen._antenna, el_a, gen._sidelobe))


#: f − 2 of the Doppler filters f = 1 … 3 (int64, made once)
_DOPPLER_K = np.arange(N_DOPPLER) - 1


def filter_poles(gen: Any, centre: float, pri: float) -> np.ndarray:
    """p_f = ρ exp(j2π f_f T), f_f = centre + (f − 2)·spacing (radar.py), of the
    TargetGenerator ``gen`` (``TargetGenerator._filter_poles``); cached for (centre, pri)."""
    key = (centre, pri)
    if gen._pf_key != key:
        spacing = gen.doppler_spacing if gen.doppler_spacing > 0.0 else 1.0 / (3.0 * pri)
        fc = centre + _DOPPLER_K * spacing
        gen._pf = gen.pole * np.exp(2j * math.pi * fc * pri)
        gen._pf_key = key
    return gen._pf
