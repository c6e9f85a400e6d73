"""How often the manager's three-filter Doppler reading lands within the coherence tolerance,
per amplitude model (RadarManager ``doppler_read``: 'excess', 'rician', 'both'), in seeded
Monte Carlo dwells beside a clutter filter (issue 11, session 18; docs/clutter.md "The Doppler
reading's two amplitude models").

Each trial: a target of peak amplitude A (per look, noise σ = 1) at a uniform offset δ from
the centre of filter 1 or 3 (spacing 1/3, pole 0.9: the resonator gains of
models/manager/doppler.py); filter 2 holds clutter of CNR [dB] (one complex Gaussian value per
dwell: the clutter decorrelates over ≈ 10 ms, longer than a dwell) on top of the noise; the
dwell mean of |target·e^{jφ} + clutter + noise| over ``--looks`` independent looks per filter,
and each filter's level the Rayleigh mean of its noise plus clutter. Printed: the fraction of
trials whose |reading − δ| is within ``doppler_tol_fraction`` (0.03 of the PRF) plus the
reading's own widening ('both'), the 90th percentile of |reading − δ| [cycles], and the mean
widening of 'both' [cycles] (the price: a wider Doppler hypothesis to search).

    python benchmarks/bench_doppler_reading.py [--trials 400] [--looks 8] [--seed 1]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from axir.models.manager import RadarManager
from axir.models.manager.doppler import resonator_gain

MODES = ("excess", "rician", "both")


def dwell(rng: np.random.Generator, a: float, delta: float, f: int, cnr_db: float,
          looks: int, spacing: float, pole: float) -> tuple[np.ndarray, np.ndarray]:
    """(dwell-mean amplitudes, levels) of the three filters for one trial (module docstring)."""
    h = resonator_gain(delta - (np.arange(3) - f) * spacing, pole) / float(
        resonator_gain(0.0, pole))
    sc = 10.0 ** (cnr_db / 20.0)
    acc, lev = np.empty(3), np.empty(3)
    for g in range(3):
        c = sc * complex(*rng.standard_normal(2)) / math.sqrt(2.0) if g == 1 else 0.0
        n = (rng.standard_normal(looks) + 1j * rng.standard_normal(looks)) / math.sqrt(2.0)
        ph = np.exp(2j * np.pi * rng.uniform(size=looks))
        acc[g] = np.abs(a * h[g] * ph + c + n).mean()
        lev[g] = math.sqrt(1.0 + (sc * sc if g == 1 else 0.0)) * math.sqrt(math.pi) / 2.0
    return acc, lev


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--trials", type=int, default=400)
    ap.add_argument("--looks", type=int, default=8, help="independent looks per dwell")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    mgrs = {m: RadarManager(doppler_read=m) for m in MODES}
    m0 = mgrs["excess"]
    s, pole, tol = m0.doppler_spacing_fraction, m0.doppler_pole, m0.doppler_tol_fraction
    prf = 1.0 / m0.pri
    print(f"{a.trials} trials per row, {a.looks} looks per dwell, tolerance {tol} of the PRF")
    print("target [dB/look] | CNR filter 2 [dB] | " + " | ".join(
        f"{m}: in tol, p90 [cycles]" for m in MODES) + " | 'both' mean widening [cycles]")
    for a_db in (15.0, 25.0, 35.0):
        for cnr in (0.0, 12.0):
            rng = np.random.default_rng([a.seed, int(a_db), int(cnr)])
            hit = {m: 0 for m in MODES}
            err: dict[str, list[float]] = {m: [] for m in MODES}
            widen = 0.0
            for _ in range(a.trials):
                f = int(rng.choice([0, 2]))
                delta = float(rng.uniform(-s / 2, s / 2))
                acc, lev = dwell(rng, 10.0 ** (a_db / 20.0), delta, f, cnr, a.looks, s, pole)
                truth = (f - 1) * s + delta
                for m, mgr in mgrs.items():
                    fd, extra = mgr._measured_doppler(acc, lev, f)
                    d = (fd - mgr._doppler) / prf - truth
                    e = abs((d + 0.5) % 1.0 - 0.5)
                    err[m].append(e)
                    hit[m] += e <= tol + extra / prf
                    if m == "both":  # the others' extra tolerance is 0
                        widen += extra / prf / a.trials
            print(f"{a_db:.0f} | {cnr:.0f} | " + " | ".join(
                f"{hit[m] / a.trials:.2f}, {np.quantile(err[m], 0.9):.3f}" for m in MODES)
                + f" | {widen:.3f}")


if __name__ == "__main__":
    main()
