"""Per-PRI and dwell-end helpers of the radar manager written for speed (issue 14, session 8:
"Faster than the radar"), each the same IEEE operations as the array code it replaced, so the
manager's outputs stay bit-identical (tests/test_manager_hotpath.py compares them).

Kept out of :mod:`.machine` (at its size limit); the state machine calls them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..radar.conventions import BIN_M, CENTRE_FILTER, CONFIRMED, GATE_BIN, N_DOPPLER

_CF = CENTRE_FILTER - 1  # 0-based central Doppler filter
_GATE0_M = (GATE_BIN - 1) * BIN_M  # [m] gate centre − gate start (bin 7 − bin 1)
#: −1, 0, 1: the Doppler filters counted from the centre one
_FILTER_STEPS = tuple(f - _CF for f in range(N_DOPPLER))


#: a filter position whose acquisition level exceeds the quietest one's by this ratio holds
#: clutter (designer's choice: 15 %, ≈ 3 × the 16-cell median's scatter on thermal noise)
CLUTTER_LEVEL_RATIO = 1.15


def clutter_flags_array(noise_pos: np.ndarray, pos: np.ndarray | list[int],
                        thermal_level: float, residue_ratio: float
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The array form of :func:`clutter_flags` (the former code; also its fallback)."""
    levels = noise_pos[pos]
    # np.nanmin of a float ndarray is np.fmin.reduce (a finite value is present, so nanmin's
    # all-NaN warning cannot apply); a NaN compares False (nan_to_num's 1.0 and 0.0 did too)
    floor = np.fmin.reduce(noise_pos) if np.isfinite(noise_pos).any() else np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        return levels / floor > CLUTTER_LEVEL_RATIO, levels / thermal_level > residue_ratio


def clutter_flags(noise_pos: np.ndarray, pos: list[int], thermal_level: float,
                  residue_ratio: float) -> tuple[list[bool], list[bool]]:
    """Clutter flags of the Doppler filters at position classes ``pos`` (issue 11): *excess*,
    the class's acquisition noise level (``noise_pos``, NaN: not measured) above
    ``CLUTTER_LEVEL_RATIO`` × the quietest class's (partly clutter), and *common*, above
    ``residue_ratio`` × ``thermal_level`` (the calibrated thermal level [SUM units]: clutter
    residue after the MTI canceller). A NaN level or floor compares False.

    In Python floats (issue 14, session 8: six numpy calls before): the floor is the smallest
    non-NaN level (``np.fmin.reduce``) when a finite one exists, the same divisions and
    comparisons; a zero floor or thermal level (x/0) takes :func:`clutter_flags_array`."""
    lv = noise_pos.tolist()
    valid = [v for v in lv if v == v]
    floor = math.nan
    if valid:
        lo = min(valid)
        if math.isfinite(lo) or any(math.isfinite(v) for v in valid):
            floor = lo
    if floor == 0.0 or thermal_level == 0.0:
        e, c = clutter_flags_array(noise_pos, pos, thermal_level, residue_ratio)
        return e.tolist(), c.tolist()
    levels = [lv[p] for p in pos]
    return ([x / floor > CLUTTER_LEVEL_RATIO for x in levels],
            [x / thermal_level > residue_ratio for x in levels])


def ema_at(values: np.ndarray, pos: list[int], est: np.ndarray, avg: float) -> None:
    """``values[pos] += (est − values[pos]) / avg`` (:func:`.thresholds.update_spread` on the
    classes ``pos``) in Python floats: the old values read first, the same two operations per
    class, written in order (a repeated class keeps the last, as numpy's fancy assignment)."""
    old = [values.item(p) for p in pos]
    for p, s, e in zip(pos, old, est.tolist(), strict=True):
        values[p] = s + (e - s) / avg


def filter_positions_array(doppler: float, pri: float, n_steps: int,
                           spacing: float) -> np.ndarray:
    """The array form of :func:`filter_positions` (the former code; also its fallback)."""
    n_pos = N_DOPPLER * n_steps
    prf = 1.0 / pri
    grid = spacing * prf / n_steps
    c = doppler + (np.arange(N_DOPPLER) - _CF) * spacing * prf
    p = np.mod(np.rint(c / grid).astype(np.int64), n_pos)
    return np.minimum(p, n_pos - p)


def filter_positions(doppler: float, pri: float, n_steps: int, spacing: float) -> np.ndarray:
    """Position classes (3,) int64 of the Doppler filters centred on ``doppler`` [Hz] at PRI
    ``pri`` [s]: the distance from 0 Hz of the nearest of the 3·``n_steps`` grid positions
    over the PRF (grid step ``spacing``·PRF/``n_steps``), in grid steps.

    In Python scalars (issue 14: five numpy calls on (3,) arrays before): c_f = doppler +
    (f − 1)·spacing·PRF, p = rint(c_f / grid) mod 3n (``round`` rounds half to even as
    ``np.rint``; ``%`` on integers takes the divisor's sign as ``np.mod``), min(p, 3n − p).
    A non-finite centre or grid takes :func:`filter_positions_array`."""
    n_pos = N_DOPPLER * n_steps
    prf = 1.0 / pri
    grid = spacing * prf / n_steps
    out = []
    try:
        for st in _FILTER_STEPS:
            p = round((doppler + st * spacing * prf) / grid) % n_pos
            out.append(min(p, n_pos - p))
    except (OverflowError, ValueError, ZeroDivisionError):  # inf / NaN / zero grid
        return filter_positions_array(doppler, pri, n_steps, spacing)
    return np.array(out, dtype=np.int64)


class StepOutputsMixin:
    """The outputs of a step (issue 14, session 8): in the common confirmed PRI (no dwell end,
    no mode change, the same steady gains) only ``gate.command`` and ``bandwidth`` can differ
    from the previous step's outputs, so they are set on a copy of a template (the last full
    outputs with ``detection`` and ``dwell.done`` False) instead of building the 15-entry
    mapping from the state. Every other step builds it in full (:meth:`_outputs`) and, in
    confirmed mode, refreshes the template. Every step returns a fresh dict."""

    _out_tmpl: dict[str, Any] | None
    _tmpl_gains_key: object

    def _step_outputs(self) -> dict[str, Any]:
        tmpl = self._out_tmpl
        if (tmpl is not None and not self._dwell_done and self.mode == CONFIRMED
                and self._gains_key is self._tmpl_gains_key):
            # what a confirmed PRI without a dwell end changes (RadarManager.step: the gate
            # follows track.range; the bandwidth decays); the test replays check the rest
            out = tmpl.copy()
            out["gate.command"] = self._gate - _GATE0_M
            out["bandwidth"] = self._bw
            return out
        out = self._outputs()
        if self.mode == CONFIRMED:
            tmpl = out.copy()
            tmpl["detection"] = tmpl["dwell.done"] = False
            self._out_tmpl, self._tmpl_gains_key = tmpl, self._gains_key
        else:
            self._out_tmpl = None
        return out

    def outputs(self) -> dict[str, Any]:
        """Current outputs (at the initial state right after reset)."""
        return self._outputs()

    def _outputs(self) -> dict[str, Any]:
        # the unfolded track Doppler changes only at a dwell's end (_follow_doppler, a PRI
        # switch, the confirmation), where the outputs are built here in full
        f = self._track.doppler_unf if self.mode == CONFIRMED else math.nan
        resolved = math.isfinite(f)
        rate = -0.5 * self.wavelength * f if resolved else 0.0
        return {
            "mode": self.mode,
            "pri": self._all_pris[self._pri_idx],
            "alpha": self._alpha,
            "beta": self._beta,
            "bandwidth": self._bw,
            "range.offset": self._offset,
            "gate.command": self._gate - _GATE0_M,
            "doppler.centre": self._doppler,
            "threshold": self._threshold,
            "noise.level": self._noise,
            "detection": self._detection,
            "dwell.done": self._dwell_done,
            "ambiguity.resolved": self._resolved_bin >= 0,
            "range.resolved": self._resolved_bin * BIN_M if self._resolved_bin >= 0 else math.nan,
            "tracking.index": self._lambda,
            "doppler.range_rate": rate,
            "doppler.resolved": resolved,
        }
