"""Synthetic scene for the RadarManager tests: it plays the TargetGenerator + Tracker.

Noise is four Rayleigh beam magnitudes per cell and PRI (seeded generator), a target is four
Rice magnitudes (per-beam SNR chosen) in the range bins around its apparent range R mod Ru
(triangular 75 m response, models/radar/conventions.py: bin r samples gate_start + (r − 1)·75 m,
window at apparent delay gate_start mod Ru) and in the Doppler filter nearest to its folded
Doppler. Commands reach the scene one step late (co-simulation lag). Gate convention of
models/tracker/: ``gate.command`` is the gate start (bin 1); in modes 0-1 the tracker gates
there, in mode 2 the scene is a perfect tracker: gate start = true range − range.offset −
6·75 m, track.range = truth. The test noise is independent from PRI to PRI, so the manager is
built with ``doppler_pole = 0``.
"""

from __future__ import annotations

import math

import numpy as np

from axir.models.manager import RadarManager
from axir.models.manager import ambiguity as amb
from axir.models.radar import conventions as radar

LAM = radar.DEFAULT_WAVELENGTH


class Scene:
    """Synthetic generator + tracker around one target (true range r0 + rdot·t)."""

    def __init__(self, r0: float, rdot: float = -150.0, snr_db: float = 6.0, seed: int = 0):
        self.r0, self.rdot = r0, rdot
        self.amp = math.sqrt(2.0 * 10.0 ** (snr_db / 10.0))  # σ = 1 per quadrature → E|n|² = 2
        self.rng = np.random.default_rng(seed)
        self.t = 0.0
        self.prev: dict | None = None
        self.present = True
        self.bins = np.arange(radar.N_BINS) * radar.BIN_M

    def truth(self) -> float:
        return self.r0 + self.rdot * self.t

    def sum_array(self, gate_start: float, pri: float, dc: float) -> np.ndarray:
        ru = radar.unambiguous_range(pri)
        a = radar.apparent_range(self.truth(), pri)
        delta = (gate_start + self.bins - a + 0.5 * ru) % ru - 0.5 * ru
        tri = np.clip(1.0 - np.abs(delta) / radar.BIN_M, 0.0, None)
        prf = 1.0 / pri
        fd = radar.fold_doppler(radar.doppler_hz(self.rdot, LAM), pri)
        centres = dc + (np.arange(3) - 1) * prf / 3.0
        df = np.abs((fd - centres + 0.5 * prf) % prf - 0.5 * prf)
        mask = (df == df.min()).astype(float)
        s = (self.amp * self.present) * tri[:, None] * mask[None, :]
        n = self.rng.standard_normal((2, 4, radar.N_BINS, 3))
        return np.abs(s[None] + n[0] + 1j * n[1]).sum(axis=0)

    def inputs(self) -> dict:
        o = self.prev
        if o is None:
            pri, gate, dc, mode, off = amb.pri_seconds(200), 0.0, 0.0, 0, 0.0
        else:
            pri, gate, dc = o["pri"], o["gate.command"], o["doppler.centre"]
            mode, off = o["mode"], o["range.offset"]
        gs = gate  # modes 0-1: the tracker gates on gate.command (range of bin 1)
        if mode == radar.CONFIRMED:  # perfect tracker gates on its (true) track
            gs = radar.gate_start_for(self.truth() - off)
        return {
            "sum": self.sum_array(gs, pri, dc),
            "gate.start": gs,
            "track.range": self.truth(),
            "track.range_rate": self.rdot,
            "maneuver": False,
        }


def run(mgr: RadarManager, scene: Scene, n: int, until=None, extra=None) -> list[dict]:
    outs = []
    for _ in range(n):
        inp = scene.inputs()
        if extra:
            inp.update(extra(len(outs), outs))
        pri = scene.prev["pri"] if scene.prev else amb.pri_seconds(200)
        o = mgr.step(pri, inp)
        scene.prev = o
        scene.t += pri
        outs.append(o)
        if until is not None and until(o):
            break
    return outs


def make(**kw) -> RadarManager:
    # no clutter in the scene and no Doppler selectivity (pole 0): no clutter notch; the
    # scene's noise is σ = 1 per quadrature (E|n|² = 2 per beam and pulse: noise_power)
    base = {"designation_range": 37_000.0, "search_extent": 3_000.0, "doppler_pole": 0.0,
            "latency_pris": 2, "clutter_notch_speed": 0.0, "noise_power": 2.0}
    base.update(kw)
    return RadarManager(**base)


