"""Engagement cells of the envelope benchmark (issue 11, point 5): one target at range R,
radial speed v, elevation el, RCS σ and maneuver g (or no target), clutter on, designated to
the radar as in the default scenario, run in the direct model loop (:mod:`axir.models.loop`,
same models, no FMI) or as a scenario through the FMUs, and summarised by
:func:`.metrics.summarize` (on-target lock time, held fraction, drops, false confirmations,
RMS errors).

Cell geometry (# assumption: all values below are parameters of :class:`Cell`):

- the target starts at range R, azimuth ``az_deg`` (30°), elevation el; its velocity is
  v·u (u the line of sight: a purely radial target, constant angles) plus ``tangential``
  m/s horizontally across the line of sight;
- maneuver g > 0: a level coordinated turn (trajectory type ``turn``, left) of load g from
  ``maneuver_onset`` s to the end (the velocity must have a horizontal component);
- target-free cell (σ = 0): the same trajectory with RCS 0; every confirmation is false;
- designation as the default scenario's (orchestrator/scenarios/closed-loop.toml): +0.5° az,
  −0.3° el, +300 m off the truth at t = 0; the pedestal starts on the designation; the Tracker
  and the RadarManager are given the designated range;
- every unit's seed is :func:`axir.models.system.unit_seed` (seed, unit), as ``axir run``.

Detectability (the SNR criterion of the benchmark's goals): the single-pulse SNR of the
TargetGenerator's radar equation (models/target_generator.py: SNR(R) = SNR_ref·(σ/σ_ref)·
(R_ref/R)⁴ with its ``snr_ref_db``, ``snr_ref_range``, ``rcs_ref`` defaults) at the largest
range of the first second, plus the coherent gain of a filter-centred IIR Doppler filter
(1 + ρ)/(1 − ρ) (ρ = ``pole``, white-noise power gain (1 − ρ)/(1 + ρ), target gain 1), must
reach Albersheim's single-look SNR for Pd = 0.9 at the acquisition Pfa (``pfa_acq``):
SNR_dB = (6.2 + 4.54/√1.44)·log10(A + 0.12·A·B + 1.7·B), A = ln(0.62/Pfa),
B = ln(Pd/(1 − Pd)) (Albersheim 1981, N = 1 look; 12.5 dB at Pfa 1e-5;
a documented choice: the seeds give no detection law).

Clutter enters the criterion only as the floor that no Doppler filtering can remove
(:func:`clutter_loss_db`, docs/clutter.md): the signal-to-clutter-plus-noise loss of a
filter-centred target at its folded Doppler, behind the MTI canceller where the generator
applies it (elevation below ``mti_max_el``), with the AR(1) clutter spectrum of the
TargetGenerator's defaults seen through the mean power gain of the 4 beams toward the horizon,
on the second-best of the three PRIs (tentative tracking needs the target on at least two).
Approximations (their net effect on the criterion is not quantified): the beams' mean clutter
power stands for the SUM's (the generator's clutter is one process seen by the 4 beams, so it
does not average out across them as the independent thermal noise does), and the canceller is
judged on or off from the cell's elevation, without the designation error or the switch's
hysteresis.
A radial speed within the manager's ``clutter_notch_speed`` of zero is blind by design (the
manager rejects it as clutter, issue 11 point 1): not detectable.
Doppler-filter straddle loss and beam shape loss are NOT in the criterion: a detectable cell
the radar misses because of them is a miss of the radar (issue 11 points 1-2).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from axir.models.loop import DirectLoop
from axir.models.manager import RadarManager
from axir.models.pedestal import Pedestal
from axir.models.radar import conventions as radar
from axir.models.radar.mti import mti_power_gain
from axir.models.system import (
    PEDESTAL,
    RADAR_MANAGER,
    TARGET_GENERATOR,
    TRACKER,
    UNITS,
    unit_seed,
)
from axir.models.target_generator import TargetGenerator
from axir.models.tracker import Tracker

from .metrics import ANGLE_GATE_RAD, RANGE_GATE_M, SUMMARY_VARIABLES, ArrayRecord, summarize

G0 = 9.80665  # [m/s²] standard gravity (a maneuver's load factor g)
#: designation offsets of the default scenario: az [deg], el [deg], range [m]
DESIGNATION_ERROR = (0.5, -0.3, 300.0)
PD_DETECT = 0.9  # probability of detection of the detectability criterion
_CLASSES = {TARGET_GENERATOR: TargetGenerator, TRACKER: Tracker, PEDESTAL: Pedestal,
            RADAR_MANAGER: RadarManager}


@dataclass(frozen=True)
class Cell:
    """One engagement: range [m], radial speed [m/s] (< 0 closing), elevation [deg], RCS
    [m²] (0: no target), maneuver [g], seed, duration [s] and the fixed geometry choices."""

    range_m: float
    speed: float
    el_deg: float
    rcs: float
    g: float = 0.0
    seed: int = 1
    duration: float = 3.0
    az_deg: float = 30.0
    tangential: float = 0.0
    maneuver_onset: float = 0.5
    clutter: bool = True

    def key(self) -> str:
        """A stable text key (the cache's row key)."""
        return json.dumps(asdict(self), sort_keys=True)

    @property
    def target_free(self) -> bool:
        return self.rcs <= 0.0


def _los(az: float, el: float) -> np.ndarray:
    return np.array([math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)])


def trajectory_spec(cell: Cell) -> dict[str, Any]:
    """The TargetGenerator trajectory spec (models/radar/trajectory.py) of a cell."""
    az, el = math.radians(cell.az_deg), math.radians(cell.el_deg)
    p = cell.range_m * _los(az, el)
    across = np.array([math.cos(az), -math.sin(az), 0.0])  # horizontal, ⟂ line of sight
    v = cell.speed * _los(az, el) + cell.tangential * across
    base = {"position": [float(x) for x in p], "velocity": [float(x) for x in v], "t0": 0.0}
    if cell.g <= 0.0:
        return {"type": "cv", **base}
    return {"type": "piecewise", **base, "segments": [
        {"type": "cv", "onset": 0.0},
        {"type": "turn", "g": cell.g, "direction": "left", "onset": cell.maneuver_onset},
    ]}


def cell_parameters(cell: Cell) -> dict[str, dict[str, Any]]:
    """Per-unit parameters of a cell (seeds included): the direct loop's and the FMU run's."""
    daz, del_, dr = DESIGNATION_ERROR
    az = math.radians(cell.az_deg + daz) % (2.0 * math.pi)
    el = math.radians(cell.el_deg + del_)
    rng = cell.range_m + dr
    return {
        TARGET_GENERATOR: {"trajectory": json.dumps(trajectory_spec(cell)), "rcs": cell.rcs,
                           "clutter": cell.clutter},
        TRACKER: {"designation_az": az, "designation_el": el, "designation_range": rng,
                  "gate_latency": 1},
        PEDESTAL: {"az0": az, "el0": el},
        RADAR_MANAGER: {"designation_range": rng},
    }


def seeded(params: dict[str, dict[str, Any]], seed: int) -> dict[str, dict[str, Any]]:
    """``params`` with seed = unit_seed(seed, unit) for every unit that has a ``seed``
    parameter (as :func:`.run.seeded_parameters` does for an FMU run)."""
    out = {u: dict(p) for u, p in params.items()}
    for u, cls in _CLASSES.items():
        if any(p.name == "seed" for p in cls.PARAMS):
            out.setdefault(u, {})["seed"] = unit_seed(seed, u)
    return out


def albersheim_snr_db(pfa: float, pd: float = PD_DETECT, n: int = 1) -> float:
    """Albersheim's required SNR [dB] for ``n`` non-coherently integrated looks (n = 1: one)."""
    a = math.log(0.62 / pfa)
    b = math.log(pd / (1.0 - pd))
    return -5.0 * math.log10(n) + (6.2 + 4.54 / math.sqrt(n + 0.44)) * math.log10(
        a + 0.12 * a * b + 1.7 * b)


def snr_db(range_m: float, rcs: float) -> float:
    """Single-pulse SNR [dB] of one beam at peak gain (the TargetGenerator's default law)."""
    d = TargetGenerator.defaults()
    if rcs <= 0.0:
        return -math.inf
    return (d["snr_ref_db"] + 10.0 * math.log10(rcs / d["rcs_ref"])
            - 40.0 * math.log10(max(range_m, 1.0) / d["snr_ref_range"]))


def filter_gain_db() -> float:
    """Coherent SNR gain [dB] of a filter-centred IIR Doppler filter: (1 + ρ)/(1 − ρ)."""
    rho = TargetGenerator.defaults()["pole"]
    return 10.0 * math.log10((1.0 + rho) / (1.0 - rho))


def required_snr_db() -> float:
    """Filtered SNR [dB] a detectable cell must reach (Albersheim, Pd 0.9, Pfa = pfa_acq)."""
    return albersheim_snr_db(RadarManager.defaults()["pfa_acq"])


def detection_snr_db(cell: Cell, window: float = 1.0) -> float:
    """Filtered SNR [dB] of a filter-centred target at the cell's largest range over the first
    ``window`` s (the acquisition time goal)."""
    r_max = cell.range_m + max(cell.speed, 0.0) * min(window, cell.duration)
    return snr_db(r_max, cell.rcs) + filter_gain_db()


def _filter_output_powers(nu_t: float, pri: float, clutter_power: float,
                          mti_order: int) -> tuple[float, float, float]:
    """(target, noise, clutter) output powers of the IIR Doppler filter centred on the
    folded Doppler ``nu_t`` [cycles/pulse], per unit input powers (target 1, thermal noise 1,
    clutter ``clutter_power``), behind the canceller of ``mti_order`` (0: none).

    Filter (models/target_generator.py): |H(ν)|² = (1 − ρ)²/(1 − 2ρ cos 2π(ν − ν_t) + ρ²),
    unit gain at its centre. Clutter: the generator's AR(1) process, density
    P (1 − ρc²)/|1 − ρc e^{−j2πν}|², ρc = exp(−2π B_c T). Canceller: models/radar/mti.py
    ``mti_power_gain``. Powers by a 4096-point quadrature over one PRF."""
    d = TargetGenerator.defaults()
    rho = d["pole"]
    rho_c = math.exp(-2.0 * math.pi * d["clutter_spread"] * pri)
    nu = (np.arange(4096) + 0.5) / 4096.0
    h2 = (1.0 - rho) ** 2 / (1.0 - 2.0 * rho * np.cos(2.0 * np.pi * (nu - nu_t)) + rho * rho)
    m2 = mti_power_gain(nu, mti_order)
    s_c = clutter_power * (1.0 - rho_c**2) / np.abs(1.0 - rho_c * np.exp(-2j * np.pi * nu)) ** 2
    target = float(mti_power_gain(nu_t, mti_order))
    return target, float(np.mean(h2 * m2)), float(np.mean(h2 * m2 * s_c))


def clutter_loss_db(cell: Cell) -> float:
    """Loss [dB] of the filtered SNR to clutter (and to the canceller's notch) for a
    filter-centred target of the cell, on the second-best of the manager's three PRIs
    (module docstring): 10·log10((S/N)_clean / (S/(N + C))) with (S/N)_clean = the thermal
    filter gain (1 + ρ)/(1 − ρ). 0 for a target-free cell."""
    if cell.target_free:
        return 0.0
    tg, rm = TargetGenerator.defaults(), RadarManager.defaults()
    gen = TargetGenerator()
    g2 = float(np.mean(gen._clutter_gains(math.radians(cell.el_deg)) ** 2))
    cnr = 10.0 ** (tg["cnr_db"] / 10.0) * g2 if tg["clutter"] and cell.clutter else 0.0
    order = tg["mti"] if math.radians(cell.el_deg) < tg["mti_max_el"] else 0
    clean = (1.0 + tg["pole"]) / (1.0 - tg["pole"])
    f_d = radar.doppler_hz(cell.speed, tg["wavelength"])
    losses = []
    for k in ("pri1_bins", "pri2_bins", "pri3_bins"):
        pri = rm[k] * radar.BIN_S
        s, n, c = _filter_output_powers((f_d * pri) % 1.0, pri, cnr, order)
        snr = s / (n + c) if s > 0.0 else 1e-30
        losses.append(10.0 * math.log10(clean / snr))
    return sorted(losses)[1]


def detectable(cell: Cell) -> bool:
    """The benchmark's detectability criterion (module docstring): the filtered SNR less
    the clutter loss reaches Albersheim's SNR."""
    if cell.target_free or abs(cell.speed) < RadarManager.defaults()["clutter_notch_speed"]:
        return False  # no target, or in the manager's clutter notch (a blind speed by design)
    return detection_snr_db(cell) - clutter_loss_db(cell) >= required_snr_db()


def run_cell(cell: Cell, decimation: int = 1,
             overrides: Mapping[str, Mapping[str, Any]] | None = None) -> dict[str, Any]:
    """Run one cell in the direct loop; its summary (metrics.summarize; target-free: every
    confirmation counts as false) plus ``tentatives`` (entries into tentative mode) and
    ``steps``. ``overrides``: unit → parameters set over :func:`cell_parameters`' own."""
    params = cell_parameters(cell)
    for unit, values in (overrides or {}).items():
        params[unit].update(values)
    loop = DirectLoop.from_params(seeded(params, cell.seed))
    refs = [r.split(".", 1) for r in SUMMARY_VARIABLES]
    n_est = int(cell.duration / 5e-5 / decimation) + 16
    buf = np.empty((n_est, 1 + len(refs)))
    n = 0
    tentatives = 0
    prev_mode = -1

    def sample() -> None:
        nonlocal buf, n
        if n == len(buf):
            buf = np.concatenate([buf, np.empty_like(buf)])
        row = buf[n]
        row[0] = loop.t
        o = loop.out
        for i, (u, v) in enumerate(refs, start=1):
            row[i] = o[u][v]
        n += 1

    loop.out[TARGET_GENERATOR] = loop.gen.outputs()  # the truth at t = 0
    sample()
    while loop.t < cell.duration:
        loop.step()
        m = loop.out[RADAR_MANAGER]["mode"]
        if m == 1 and prev_mode != 1:
            tentatives += 1
        prev_mode = m
        if loop.steps % decimation == 0:
            sample()
    if buf[n - 1, 0] != loop.t:
        sample()
    rec = ArrayRecord(buf[:n, 0], {r: buf[:n, i] for i, r in enumerate(SUMMARY_VARIABLES, 1)})
    gate = -1.0 if cell.target_free else RANGE_GATE_M  # no target: nothing is on target
    out = summarize(rec, range_gate_m=gate, angle_gate_rad=ANGLE_GATE_RAD)
    out["tentatives"] = tentatives
    out["steps"] = loop.steps
    return out


def cell_scenario(cell: Cell) -> dict[str, Any]:
    """The cell as a scenario dict (orchestrator/scenario.py format) for ``axir run``-style
    FMU runs (seed: the cell's; record: every step, the summary's variables)."""
    params = cell_parameters(cell)
    return {
        "scenario": {"name": "envelope-cell", "duration": cell.duration, "seed": cell.seed,
                     "algorithm": "gauss-seidel",
                     "order": [PEDESTAL, TARGET_GENERATOR, TRACKER, RADAR_MANAGER],
                     "step": "variable", "step_from": f"{RADAR_MANAGER}.pri"},
        "record": {"decimation": 1, "variables": list(SUMMARY_VARIABLES)},
        "units": {u: {"fmu": f"{u}.fmu", "parameters": params[u]} for u in UNITS},
    }


__all__ = [
    "Cell",
    "albersheim_snr_db",
    "cell_parameters",
    "cell_scenario",
    "clutter_loss_db",
    "detectable",
    "detection_snr_db",
    "filter_gain_db",
    "required_snr_db",
    "run_cell",
    "seeded",
    "snr_db",
    "trajectory_spec",
]
