"""Coverage of the confirmed-tracking PRIs (issue 11, session 11; ``RadarManager.track_pri_bins``,
models/manager/pri_choice.py "Confirmed-tracking PRIs", docs/doppler_coverage.md).

For Dopplers over ±2·max_speed/λ (±1500 m/s, ±94 kHz; 5 Hz grid) computes the smallest predicted
canceller loss over a PRI set (:func:`axir.models.manager.pri_choice.predicted_loss_db`, order
``confirm_loss_mti_order``) and lists the bands where it exceeds ``confirm_max_loss_db`` (blind
at every PRI of the set), leaving out the clutter band around 0 Hz (blind at every PRI by
construction). Prints a markdown table for the three acquisition PRIs, the default set and
alternatives, and the scan of one added PRI over 100-400 bins that chose the default.
Usage: ``.venv/bin/python reports/track_pris.py`` (≈ 40 s).
"""

from __future__ import annotations

import math

import numpy as np

from axir.models.manager import RadarManager
from axir.models.manager.ambiguity import pri_seconds
from axir.models.manager.pri_choice import parse_track_pri_bins, predicted_loss_db

STEP_HZ = 5.0


def min_loss(freqs: np.ndarray, ks: tuple[int, ...], order: int) -> np.ndarray:
    """Smallest predicted loss [dB] over the PRIs ``ks`` [bins] at each Doppler [Hz]."""
    out = np.full(freqs.shape, np.inf)
    for k in ks:
        p = pri_seconds(k)
        out = np.minimum(out, [predicted_loss_db(f, p, order) for f in freqs])
    return out


def blind_bands(freqs: np.ndarray, loss: np.ndarray, max_db: float) -> list[tuple[float, float]]:
    """Runs of ``freqs`` where ``loss`` > ``max_db``, without the run through 0 Hz."""
    bands, start = [], None
    for f, b in zip(freqs, loss > max_db, strict=True):
        if b and start is None:
            start = f
        if not b and start is not None:
            bands.append((start, f - STEP_HZ))
            start = None
    if start is not None:
        bands.append((start, freqs[-1]))
    return [(a, b) for a, b in bands if not a <= 0.0 <= b]


def main() -> None:
    d = RadarManager.defaults()
    acq = (d["pri1_bins"], d["pri2_bins"], d["pri3_bins"])
    order, max_db = d["confirm_loss_mti_order"], d["confirm_max_loss_db"]
    f_max = 2.0 * d["max_speed"] / d["wavelength"]
    freqs = np.arange(-f_max, f_max, STEP_HZ)
    far = np.abs(freqs) >= 2200.0
    track = parse_track_pri_bins(d["track_pri_bins"], acq)
    print(f"Dopplers ±{f_max / 1e3:.1f} kHz (±{d['max_speed']:.0f} m/s), loss > {max_db} dB "
          "at every PRI (clutter band |f| < PRF_min/6 left out)\n")
    print("| PRIs [bins] | PRFs [kHz] | bands blind at every PRI | widest [Hz] | total [Hz] "
          "| worst best-PRI loss, |f| ≥ 2.2 kHz [dB] |")
    print("|---|---|---|---|---|---|")
    sets = [acq, (*acq, *track)] + [(*acq, k) for k in track] + [(*acq, 155), (*acq, 283)]
    for ks in sets:
        loss = min_loss(freqs, ks, order)
        bands = blind_bands(freqs, loss, max_db)
        txt = ", ".join(f"{a / 1e3:+.2f}..{b / 1e3:+.2f}" for a, b in bands if a > 0) or "none"
        widest = max((b - a + STEP_HZ for a, b in bands), default=0.0)
        total = sum(b - a + STEP_HZ for a, b in bands)
        prfs = "/".join(f"{1e-3 / pri_seconds(k):.2f}" for k in ks)
        print(f"| {'/'.join(map(str, ks))} | {prfs} | {txt} (and negatives) | {widest:.0f} "
              f"| {total:.0f} | {float(loss[far].max()):.2f} |")
    print("\nOne PRI added to the three, 100-400 bins: those leaving no band (worst loss, "
          "|f| ≥ 2.2 kHz):")
    base = min_loss(freqs, acq, order)
    ok = []
    for k in range(100, 401):
        if k in acq:
            continue
        p = pri_seconds(k)
        loss = np.minimum(base, [predicted_loss_db(f, p, order) for f in freqs])
        if not blind_bands(freqs, loss, max_db):
            ok.append(f"{k} ({float(loss[far].max()):.2f} dB)")
    print(", ".join(ok) if ok else "none")
    print(f"\nstep rate on a tracking PRI: {acq[1]}/k = "
          + ", ".join(f"{k}: ×{acq[1] / k:.2f}" for k in track)
          + f" (PRIs per simulated second {math.floor(1 / pri_seconds(acq[1]))} → "
          + ", ".join(f"{math.floor(1 / pri_seconds(k))}" for k in track) + ")")


if __name__ == "__main__":
    main()
