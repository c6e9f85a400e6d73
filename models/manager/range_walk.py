"""Range walk of the tentative hypotheses (issue 11, docs/clutter.md "Range walk in
tentative"): the range-Doppler coupling of a moving target during a long tentative attempt.

A tentative attempt measures the apparent range at up to three PRIs; its range candidates are
the true range bins at the attempt's start (:mod:`.ambiguity`). When one PRI is searched in
vain (the target in the clutter filter there) the attempt lasts 0.2-0.3 s, and a target
closing at 800 m/s walks 2-3 range bins (75 m) out of the hypothesis window, whose central
bins 6-8 are the Th2 test (seed 000): traced at 42 km / −800.77 m/s, where every Doppler
reading was right and the attempts still died on the third PRI. Each unfolded Doppler
candidate f is also a range rate ṙ = −λ·f/2 (the radar's convention f = −2ṙ/λ), so the manager
moves each hypothesis window by the walk of the candidates its Doppler step holds,
rint(ṙ·Δt / 75 m) bins at the window's expected dwell time Δt after the attempt's start, and
keeps only the Doppler candidates whose walk matches the one of the window where the target
was found (within one bin): range AND Doppler coherence, now coupled. For Δt·|ṙ| below half a
bin (a short attempt) every walk is 0 and nothing changes. Designer's choice; the seed is
silent.
"""

from __future__ import annotations

import numpy as np

from ..radar.conventions import BIN_M
from .ambiguity import consistent

#: windows are placed at walks that are multiples of this many bins: a target within ±1 bin of
#: a window's walk is in its central bins 6-8 (the Th2 test), so a short attempt (every walk
#: within ±1 bin) keeps one window per range hypothesis and Doppler step, as without the walk
WALK_QUANTUM = 3


def walk_bins(dcands: np.ndarray, wavelength: float, dt: float) -> np.ndarray:
    """Range walk [bins] of the unfolded Doppler candidates ``dcands`` [Hz] over ``dt`` [s]:
    rint(ṙ·dt / BIN_M), ṙ = −λ·f/2 [m/s] (``wavelength`` λ [m])."""
    return np.rint(-0.5 * wavelength * np.asarray(dcands) * dt / BIN_M).astype(np.int64)


def candidate_steps(dcands: np.ndarray, prf: float, base: float, n_steps: int,
                    spacing: float) -> np.ndarray:
    """Doppler step holding each candidate ``dcands`` [Hz] at ``prf`` [Hz] (its nearest
    filter position on the grid spacing·PRF/n, as :func:`.doppler_search.steps_for`)."""
    grid = spacing * prf / n_steps
    pos = np.rint(np.mod(np.asarray(dcands) - base, prf) / grid).astype(np.int64)
    return np.mod(pos, n_steps)


def step_walks(walks: np.ndarray, steps: np.ndarray, step: int) -> list[int]:
    """The distinct window walks [bins] of the candidates in Doppler step ``step`` (their walks
    rounded to multiples of ``WALK_QUANTUM``), smallest |walk| first ([0] when the step holds
    none)."""
    q = WALK_QUANTUM
    w = np.unique(q * np.rint(walks[steps == step] / q).astype(np.int64))
    if w.size == 0:
        return [0]
    return sorted((int(x) for x in w), key=lambda x: (abs(x), x))


def coupled(cands: np.ndarray, dcands: np.ndarray, m: int, k: int, tol: int,
            wavelength: float, dt: float, walk: int) -> tuple[int, np.ndarray, np.ndarray]:
    """Range and Doppler coherence of a detection at apparent bin ``m`` (PRI of ``k`` bins)
    made ``dt`` [s] after the attempt began in a window of walk ``walk`` [bins]: the Doppler
    candidates ``dcands`` [Hz] (already coherent with the reading) whose walk rounds to the
    window's (within ``WALK_QUANTUM``/2), and the range candidates ``cands`` [bins, at the
    attempt's start] consistent within ``tol`` with m less the walk of one of them (the
    Doppler candidates kept: those with a consistent range). Returns (m at the start, for the
    most common walk; range candidates; Doppler candidates)."""
    dc = np.asarray(dcands)
    w = walk_bins(dc, wavelength, dt)
    dc, w = dc[np.abs(w - walk) <= WALK_QUANTUM // 2], w[np.abs(w - walk) <= WALK_QUANTUM // 2]
    if dc.size == 0:
        return m % k, cands[:0], dc
    keep = np.zeros(dc.size, dtype=bool)
    out = []
    for x in np.unique(w):
        c = consistent(cands, (m - int(x)) % k, k, tol)
        if c.size:
            out.append(c)
            keep |= w == x
    if not out:
        return m % k, cands[:0], dc[:0]
    vals, counts = np.unique(w[keep], return_counts=True)
    m0 = (m - int(vals[int(np.argmax(counts))])) % k
    return m0, np.unique(np.concatenate(out)), dc[keep]
