"""PRI set design and range-ambiguity resolution (seed 000, tentative tracking).

Seed 000: "Several Doppler measurements (coherent bursts) are operated with at least 3 different
Pulse Repetition Intervals (PRI) in order to solve the range-Doppler ambiguities … The new value
for R is R = Ro + N * 75 meters. It is the Radar Manager which calculates this value".

Conventions (:mod:`axir.models.radar.conventions`): every PRI is an integer number ``k`` of
range-bin durations (``PRI = k·BIN_S`` ≈ k·0.5 µs), so the unambiguous range ``Ru = c·PRI/2 = k·75
m`` is an integer number of 75 m bins. With the range window on the 75 m grid (the manager snaps
its gate commands to it), a target in true range bin ``B = round(R/75 m)`` is seen at apparent bin
``B mod k`` at that PRI, and ``R = R0 + N·Ru`` with ``R0`` the apparent range.

Resolver (coincidence / Chinese-remainder search): the candidates ``B = m1 + δ + n·k1``
(|δ| ≤ tol, n = −1, 0, 1, …) of the first measurement, limited to ``[0, max_bin + tol]``, are kept
when every other measurement agrees within ``tol`` bins (circular residual modulo its ``k``).
The survivors must form one cluster no wider than ``2·tol`` bins (else the measurements are
ambiguous → ``None``); the survivor with the smallest sum of squared residuals is returned
(ties → the lower). No survivor → inconsistent → ``None``.

Default PRI set, ``DEFAULT_PRI_BINS = (200, 211, 223)`` bins:

==========  ============  =============  ======================
k [bins]    PRI [µs]      PRF [kHz]      Ru [km]
==========  ============  =============  ======================
200         100.07        9.993          15.000
211         105.57        9.472          15.825
223         111.57        8.963          16.725
==========  ============  =============  ======================

(``BIN_S`` = 2·75/c = 0.50035 µs.) The three ``k`` are pairwise coprime (200 = 2³·5², 211 and
223 prime): without measurement error the set is unambiguous to lcm = 9 410 600 bins (705 795 km).
With ±1 bin measurement error two ranges can only be confused when their difference ``D``
satisfies ``|D mod k_i| ≤ 2`` (circularly) for all three PRIs; the smallest such ``D`` is
172 600 bins (12 945 km) for the set, and 3 798 bins (284.9 km) for the first two PRIs alone
(:func:`ghost_free_span_bins`). The manager's default maximum range (150 km, 10 × the shortest
Ru) is therefore resolved without ghosts by the first two PRIs; the third PRI is the coherence
check the seed asks for ("evaluate the coherence of the unfolded range measurements"). The
probability that three *random* apparent bins pass the check somewhere in [0, 150 km] is about
(2·tol + 1)·(max_bin/k1)·((2·tol + 1)/k2)·((2·tol + 1)/k3) ≈ 0.7 %.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..radar.conventions import BIN_M, BIN_S

DEFAULT_PRI_BINS: tuple[int, int, int] = (200, 211, 223)  # see module docstring (assumption)


def pri_seconds(k: int) -> float:
    """PRI [s] of ``k`` range-bin durations (``k·BIN_S``)."""
    return k * BIN_S


def unambiguous_range_m(k: int) -> float:
    """Ru [m] of a PRI of ``k`` bins (``k·75 m``, exactly ``c·PRI/2``)."""
    return k * BIN_M


def range_to_bin(r: float) -> int:
    """Nearest 75 m bin index of a range ``r`` [m]."""
    return int(np.floor(r / BIN_M + 0.5))


def circular_residual(b: np.ndarray | int, m: int, k: int) -> np.ndarray:
    """|b − m| modulo ``k``, folded to [0, k/2] [bins] (elementwise)."""
    d = np.mod(np.asarray(b) - m, k)
    return np.minimum(d, k - d)


def ghost_free_span_bins(pri_bins: Sequence[int], tol: int = 1, limit: int = 10_000_000) -> int:
    """Smallest separation D > 2·tol [bins] of two ranges that measurements with ±``tol`` bin
    errors at every PRI of ``pri_bins`` cannot tell apart (``limit`` if none below it).

    Any target range interval shorter than this is resolved without ghosts.
    """
    ks = [int(k) for k in pri_bins]
    chunk = 1_000_000
    start = 2 * tol + 1
    while start < limit:
        d = np.arange(start, min(start + chunk, limit), dtype=np.int64)
        ok = np.ones(d.shape, dtype=bool)
        for k in ks:
            ok &= circular_residual(d, 0, k) <= 2 * tol
        idx = np.flatnonzero(ok)
        if idx.size:
            return int(d[idx[0]])
        start += chunk
    return int(limit)


def candidates(m: int, k: int, max_bin: int, tol: int = 1) -> np.ndarray:
    """True-range bin candidates ``m + δ + n·k`` (|δ| ≤ tol, n ≥ −1) in [0, max_bin + tol]."""
    n = np.arange(-1, max_bin // k + 2, dtype=np.int64)
    b = (m + np.arange(-tol, tol + 1, dtype=np.int64))[None, :] + (n * k)[:, None]
    b = b.ravel()
    b = b[(b >= 0) & (b <= max_bin + tol)]
    return np.unique(b)


def consistent(cands: np.ndarray, m: int, k: int, tol: int = 1) -> np.ndarray:
    """The ``cands`` [bins] whose apparent bin at PRI ``k`` is within ``tol`` of ``m``."""
    return cands[circular_residual(cands, m, k) <= tol]


def resolve_bins(
    apparent_bins: Sequence[int],
    pri_bins: Sequence[int],
    max_bin: int,
    tol: int = 1,
) -> int | None:
    """True range bin from the apparent bins measured at each PRI (all in 75 m bins).

    Args:
        apparent_bins: measured apparent bin at each PRI (any integer; taken modulo its ``k``).
        pri_bins: PRI of each measurement in bins (same length, ≥ 1).
        max_bin: largest true range bin searched.
        tol: accepted measurement error [bins] at every PRI.

    Returns:
        The true bin ``B`` (``R = B·75 m``), or ``None`` when the measurements are
        inconsistent (no candidate) or ambiguous (candidates farther apart than ``2·tol``).
    """
    if len(apparent_bins) == 0 or len(apparent_bins) != len(pri_bins):
        return None
    ms = [int(m) % int(k) for m, k in zip(apparent_bins, pri_bins, strict=True)]
    ks = [int(k) for k in pri_bins]
    c = candidates(ms[0], ks[0], max_bin, tol)
    for m, k in zip(ms[1:], ks[1:], strict=True):
        c = consistent(c, m, k, tol)
        if c.size == 0:
            return None
    if c.size == 0 or int(c[-1] - c[0]) > 2 * tol:
        return None
    cost = np.zeros(c.shape, dtype=np.int64)
    for m, k in zip(ms, ks, strict=True):
        cost += circular_residual(c, m, k) ** 2
    return int(c[int(np.argmin(cost))])


def resolve_range(
    apparent_ranges: Sequence[float],
    pri_bins: Sequence[int],
    max_range: float,
    tol: int = 1,
) -> float | None:
    """True range [m] (``R0 + N·Ru``, quantised to 75 m) from apparent ranges [m] measured at
    the PRIs ``pri_bins``; ``None`` when inconsistent, ambiguous or non-finite."""
    if not all(np.isfinite(r) for r in apparent_ranges):
        return None
    b = resolve_bins([range_to_bin(r) for r in apparent_ranges], pri_bins,
                     range_to_bin(max_range), tol)
    return None if b is None else b * BIN_M


def hypothesis_windows(cands: np.ndarray, k: int, prior: int) -> list[tuple[int, int]]:
    """Gate windows to visit at a PRI of ``k`` bins to find a target whose true range bin is one
    of ``cands`` (assumption: hypothesis windows): the apparent bins ``cands mod k`` merged into
    clusters at most 3 bins wide, one window per cluster, centred on it; each with the member
    nearest to ``prior`` (the designated / last known true bin) as its hypothesis.

    Returns ``[(apparent centre bin, hypothesis true bin), ...]``, nearest to ``prior`` first.
    """
    app = np.mod(cands, k)
    order = np.argsort(app, kind="stable")
    windows: list[tuple[int, int, int]] = []  # (priority, centre bin, hypothesis bin)
    i = 0
    n = order.size
    while i < n:
        j = i
        start = int(app[order[i]])
        while j + 1 < n and int(app[order[j + 1]]) - start <= 2:
            j += 1
        members = cands[order[i : j + 1]]
        centre = (start + int(app[order[j]])) // 2
        dist = np.abs(members - prior)
        best = int(members[int(np.argmin(dist))])
        windows.append((int(dist.min()), centre, best))
        i = j + 1
    windows.sort()
    return [(c, b) for _, c, b in windows]
