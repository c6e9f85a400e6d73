"""Doppler ramp of a confirmed track: the rate of change of the target's Doppler [Hz/s],
estimated from the dither loop's own measurements (issue 11, branch env14;
docs/envelope.md "Which cells miss and why").

**Why.** A target with a radial acceleration a_r moves its Doppler at ḟ = −2·a_r/λ (from
f = −2ṙ/λ, the radar convention of :func:`..radar.conventions.doppler_hz`); in a level
5-7 g turn at X band that is 2-3.4 kHz/s. The dither loop (:mod:`.doppler_track`) is of type
one: it follows a ramp with a lag, and it only moves on pairs of dwells with a clear target
(``doppler_disc_snr``), so as the SNR falls it stops and the target runs out of the filter
(3 dB half-width ≈ 150-170 Hz) in 0.05-0.1 s. The manager's Doppler is the one seed 000 gives
it ("the Doppler frequency is calculated by the Radar Manager"); the Tracker's range rate lags
by 20-30 m/s (1.2-1.9 kHz) in such a turn and its derivative is too noisy at 0.1 s.

**Estimate.** Each pair whose offset the loop measured gives the target's unfolded Doppler at
that time, m = centre + δ. The ramp is the slope of an exponentially weighted least-squares
line through these measurements (weight e^(−age/τ), τ = ``doppler_ramp_time``): slope noise
≈ σ_m/(τ·√n) for n pairs within τ (σ_m ≈ 30-100 Hz at 17-40 dB, a pair every ≈ 6 ms:
≈ 60-150 Hz/s at τ = 0.15 s), a lag of ≈ τ behind a change of the ramp. The slope is bounded
by 2·``doppler_ramp_max_acc``/λ, is 0 until the weights sum to ``MIN_WEIGHT`` pairs or while
it is within ``SIGNIFICANCE`` of its own standard deviations (from the line's residuals) of 0
(measured at 42 km, +1000 m/s, no maneuver, ≈ 17 dB: without the test a slope of 0.8-2.3 kHz/s
fitted to the noisy pairs of a weak target ran the centre off it and dropped the track), and is
held through a gap in the measurements (a coast: after 0.2 s without a clear pair the old
weights have decayed below ``MIN_WEIGHT``, and no new information says the ramp changed).
The confirmed centre is then predicted along the ramp at every dwell (with or without a
clear pair, also while the target is missed), so the loop only corrects the residual.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: the weights of the measurements must sum to this many pairs before the slope is used
MIN_WEIGHT = 6.0
#: a slope is used only when it is this many of its standard deviations from 0
SIGNIFICANCE = 3.0


@dataclass
class Ramp:
    """Exponentially weighted sums of the (time, Doppler) measurements of one confirmed
    track, times and Doppler relative to the first measurement (``t0``, ``f0``)."""

    t0: float = math.nan  # time of the first measurement [s]
    f0: float = 0.0  # its Doppler [Hz]
    t_last: float = math.nan  # time of the last measurement [s]
    s0: float = 0.0  # Σ w
    st: float = 0.0  # Σ w·t
    sf: float = 0.0  # Σ w·f
    stt: float = 0.0  # Σ w·t²
    stf: float = 0.0  # Σ w·t·f
    sff: float = 0.0  # Σ w·f²
    k: float = 0.0  # the weighted least-squares slope [Hz/s] (held through gaps)

    def add(self, t: float, f: float, tau: float) -> None:
        """Add the measurement ``f`` [Hz] at time ``t`` [s]; older ones decay by
        e^(−Δt/``tau``)."""
        if not math.isfinite(self.t0):
            self.t0, self.f0, self.t_last = t, f, t
        decay = math.exp(-(t - self.t_last) / tau) if tau > 0.0 else 0.0
        self.s0 *= decay
        self.st *= decay
        self.sf *= decay
        self.stt *= decay
        self.stf *= decay
        self.sff *= decay
        x, y = t - self.t0, f - self.f0
        self.s0 += 1.0
        self.st += x
        self.sf += y
        self.stt += x * x
        self.stf += x * y
        self.sff += y * y
        self.t_last = t
        n = self.s0
        sxx = self.stt - self.st * self.st / n  # Σ w·(t − t̄)²
        if n < MIN_WEIGHT or not sxx > 1e-12 * self.stt:
            return
        k = (self.stf - self.st * self.sf / n) / sxx
        # residual variance of the line and the slope's: var(k) = s²/Σ w·(t − t̄)²
        rss = max(self.sff - self.sf * self.sf / n - k * k * sxx, 0.0)
        var_k = rss / (n - 2.0) / sxx
        self.k = k if k * k >= SIGNIFICANCE**2 * var_k else 0.0

    def slope(self, bound: float) -> float:
        """The slope [Hz/s] after the last measurement that left the weights at
        :data:`MIN_WEIGHT` or more (0 before, and 0 when not significant), clipped to
        ±``bound``."""
        return min(max(self.k, -bound), bound)
