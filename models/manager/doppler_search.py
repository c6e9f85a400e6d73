"""Doppler coverage and Doppler coherence of the radar manager (issue 11; seed 000: acquisition
"for the three Doppler filters and for the sixteen range gates"; tentative tracking "evaluates
the coherence of the unfolded range measurements and Doppler frequencies").

**Filters.** The generator's three Doppler filters are first-order resonators of pole radius ρ
centred at ``doppler.centre + (f − 2)·s·PRF`` (s = ``doppler_spacing_fraction``, 1/3: they
tile the folded band), with the gain |H(δ)| of :func:`.doppler.resonator_gain` at an offset δ
[cycles per PRI]. With ρ = 0.9 a filter's 3 dB half-width is 0.0168·PRF and the loss midway
between two filters (δ = 1/6) is 19.6 dB: one filter position cannot cover the band.

**Coverage: Doppler steps** (designer's choice, the seed is silent). The manager steps the
filter bank's centre over ``n`` dwells by s·PRF/n: the 3·n filter positions then lie on a grid of
spacing s·PRF/n, and a target is never farther than half a grid step, s/(2n) cycles, from a
filter centre. :func:`coverage_steps` picks the smallest n whose worst-case loss
(:func:`worst_loss_db`) is within a bound (4 dB: 9 steps for ρ = 0.9, worst 3.45 dB).
Acquisition visits every step of a range window (step 0 first, so a target near the
undisplaced filters is found as fast as before) before moving to the next window, and cycles
the acquisition PRI from one pass over the windows to the next (PRI staggering: a target whose
folded Doppler hides in the clutter filter at one PRF is clear at another).

**Coherence: unfolded Doppler candidates.** A detection at PRI k in filter f measures the
folded Doppler f̂_k (filter centre + the three-filter discriminator's offset,
:func:`.doppler.doppler_offset`). The unfolded Doppler candidates are the points of a grid over
[−F, F] (F = 2·``max_speed``/λ, the physical bound; grid step ``CAND_STEP_HZ``) whose folded
value at PRF_k is within ``tol`` of f̂_k (:func:`candidates_hz`); each further PRI keeps the
candidates consistent with its measurement (:func:`consistent_hz`) — the Doppler analogue of
:mod:`.ambiguity`. At a new PRI the manager visits only the Doppler steps whose filters hold a
candidate (:func:`steps_for`). No candidate left → the detections are not one target
(incoherent) → rejected. Candidates within ``notch`` of 0 Hz left after the three PRIs → the
detection is ground clutter (or a target at a blind speed, folded into the clutter notch on
every PRI at once) → rejected.
"""

from __future__ import annotations

import math

import numpy as np

from .doppler import resonator_gain

CAND_STEP_HZ = 10.0  # grid step of the unfolded Doppler candidates [Hz] (≪ any tolerance)


def step_centre(base: float, step: int, n_steps: int, spacing: float, prf: float) -> float:
    """Doppler centre [Hz] of step ``step`` of ``n_steps``: base + step·s·PRF/n (unfolded)."""
    return base + step * spacing * prf / n_steps


def worst_loss_db(n_steps: int, spacing: float, pole: float) -> float:
    """Worst-case loss [dB] of a target against a filter-centred one when the 3 filters are
    stepped ``n_steps`` times by spacing/n: the gain at half a grid step, −20·log10|H(s/(2n))|."""
    return float(-20.0 * np.log10(resonator_gain(0.5 * spacing / n_steps, pole)))


def coverage_steps(spacing: float, pole: float, max_loss_db: float, n_max: int = 64) -> int:
    """Smallest number of Doppler steps whose worst-case loss is ≤ ``max_loss_db`` (n_max if
    none)."""
    for n in range(1, n_max + 1):
        if worst_loss_db(n, spacing, pole) <= max_loss_db:
            return n
    return n_max


def loss_db(f_hz: np.ndarray, prf: float, base: float, n_steps: int, spacing: float,
            pole: float, n_filters: int = 3) -> np.ndarray:
    """Loss [dB] of targets at Doppler ``f_hz`` against a filter-centred target, with the best
    of the n_filters·n_steps filter positions (folded at ``prf``)."""
    f = np.asarray(f_hz, dtype=np.float64)[..., None]
    g = np.zeros(f.shape[:-1])
    for j in range(n_steps):
        centres = step_centre(base, j, n_steps, spacing, prf) + (
            np.arange(n_filters) - (n_filters // 2)) * spacing * prf
        d = (f - centres) / prf
        g = np.maximum(g, resonator_gain(d, pole).max(axis=-1))
    return -20.0 * np.log10(np.maximum(g, 1e-300))


def fold_cycles(f: np.ndarray | float, prf: float) -> np.ndarray:
    """Circular distance of ``f`` [Hz] from 0 modulo ``prf`` [cycles per PRI], in [0, 1/2]."""
    x = np.mod(np.asarray(f, dtype=np.float64) / prf, 1.0)
    return np.minimum(x, 1.0 - x)


def candidates_hz(f_meas: float, prf: float, f_max: float, tol: float) -> np.ndarray:
    """Unfolded Doppler candidates [Hz] in [−f_max, f_max] (grid ``CAND_STEP_HZ``) whose folded
    value at ``prf`` is within ``tol`` [Hz] of the measured folded Doppler ``f_meas``."""
    return consistent_hz(candidate_grid(f_max), f_meas, prf, tol)


def candidate_grid(f_max: float) -> np.ndarray:
    """Every unfolded Doppler candidate [Hz]: the grid of step ``CAND_STEP_HZ`` over
    [−f_max, f_max]."""
    n = math.ceil(f_max / CAND_STEP_HZ)
    return np.arange(-n, n + 1) * CAND_STEP_HZ


def consistent_hz(cands: np.ndarray, f_meas: float, prf: float, tol: float) -> np.ndarray:
    """The ``cands`` [Hz] whose folded value at ``prf`` is within ``tol`` [Hz] of ``f_meas``."""
    return cands[fold_cycles(cands - f_meas, prf) * prf <= tol]


def blind_mask(cands: np.ndarray, prf: float, fraction: float) -> np.ndarray:
    """True where the unfolded Dopplers ``cands`` [Hz] fold within ``fraction`` of the PRF
    ``prf`` [Hz] of 0 Hz: blind there (the MTI canceller's notch and the clutter filter)."""
    return fold_cycles(cands, prf) <= fraction


def blind_share(cands: np.ndarray, prf: float, fraction: float) -> float:
    """Fraction of the candidates ``cands`` [Hz] blind at ``prf`` (:func:`blind_mask`); 1.0
    without candidates."""
    if cands.size == 0:
        return 1.0
    return float(np.count_nonzero(blind_mask(cands, prf, fraction))) / cands.size


def consistent_notch_hz(cands: np.ndarray, prf: float, width: float) -> np.ndarray:
    """The ``cands`` [Hz] folding within ``width`` [cycles per PRI] of 0 Hz at ``prf`` [Hz]:
    the Doppler coherence of a detection made in the MTI notch, whose folded Doppler is only
    known to lie in the notch (docs/clutter.md, *Tentative in the notch*)."""
    return cands[blind_mask(cands, prf, width)]


def steps_for(cands: np.ndarray, prf: float, base: float, n_steps: int,
              spacing: float, near: float | None = None) -> list[int]:
    """Doppler steps whose filters hold the folded candidates ``cands`` [Hz] at ``prf``: each
    candidate goes to the step of its nearest filter position (grid s·PRF/n); steps ordered
    by the number of candidates they hold (most first, ties by index), or, given ``near``
    [Hz], by the folded distance of their nearest candidate from it (nearest first)."""
    if cands.size == 0:
        return []
    grid = spacing * prf / n_steps
    pos = np.rint(np.mod(cands - base, prf) / grid).astype(np.int64)
    steps = np.mod(pos, n_steps)
    if near is not None:
        dist = fold_cycles(cands - near, prf)
        best = np.full(n_steps, np.inf)
        np.minimum.at(best, steps, dist)
        return sorted((int(s) for s in np.flatnonzero(np.isfinite(best))),
                      key=lambda s: (best[s], s))
    counts = np.bincount(steps, minlength=n_steps)
    order = sorted((int(s) for s in np.flatnonzero(counts)), key=lambda s: (-counts[s], s))
    return order
