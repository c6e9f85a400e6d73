"""Acquisition (mode 0) of the radar manager, a mixin of
:class:`~axir.models.manager.machine.RadarManager` (the logic is described in its module
docstring, *Acquisition*; Doppler steps and PRI cycling: :mod:`.doppler_search`).

Seed 000: "The magnitudes of the … four squinted beams are accumulated … for the three Doppler
filters and for the sixteen range gates. Each channel is compared to a threshold. If one result
is trespassing this level, the target is declared present in the cell providing the largest
number."
"""

from __future__ import annotations

import math

import numpy as np

from ..radar.conventions import ACQUISITION, BIN_M, CENTRE_FILTER, GATE_BIN, N_DOPPLER
from .ambiguity import range_to_bin
from .doppler import doppler_offset, rician_amplitude
from .residue import class_shares

_C = GATE_BIN - 1  # 0-based index of bin 7
_CF = CENTRE_FILTER - 1  # 0-based central Doppler filter


class AcquisitionMixin:
    """Search sequence (range windows × Doppler steps, PRI cycled per pass) and Th1 test."""

    def _enter_acquisition(self, centre_true: float) -> None:
        """Mode 0: search windows around ``centre_true`` [m] folded modulo the acquisition Ru,
        every Doppler step of a window before the next window; the PRI cycles per pass."""
        self.mode = ACQUISITION
        self._peak.active = False
        self._search.centre_true = centre_true
        self._search.passes = 0
        self._start_pass()

    def _acq_pri_idx(self) -> int:
        """Acquisition PRI of the current pass (``acq_pri_cycle``: the three PRIs in turn,
        ``acq_pri_index`` first)."""
        first = self.acq_pri_index - 1
        return (first + self._search.passes) % 3 if self.acq_pri_cycle else first

    def _start_pass(self) -> None:
        """Windows of one pass: range offsets centre first, then alternately farther / nearer;
        every Doppler step of a window before the next; the ``acq_all_pri_windows`` innermost
        windows are searched again at the two other PRIs right after (a target whose folded
        Doppler is in the MTI notch at this pass' PRI is clear at another)."""
        idx = self._acq_pri_idx()
        k = self._ks[idx]
        step = self.search_step_bins
        if 2.0 * self.search_extent >= k * BIN_M:
            n_side = math.ceil(0.5 * k / step)
        else:
            n_side = math.ceil(self.search_extent / BIN_M / step)
        offs = [0]
        for i in range(1, n_side + 1):
            offs += [i * step, -i * step]
        pris = (idx, (idx + 1) % 3, (idx + 2) % 3)
        centre_bin = range_to_bin(self._search.centre_true)
        wins: list[tuple[int, int, int]] = []
        for n, o in enumerate(offs):
            every = self.acq_pri_cycle and n < self.acq_all_pri_windows
            for pi in pris if every else (idx,):
                kk = self._ks[pi]
                wins += [((centre_bin % kk + o) % kk, j, pi) for j in range(self._n_steps)]
        self._search.windows = wins
        self._search.pos = 0
        self._resolved_bin = -1
        self._tent.confirming = False
        self._goto_search()
        self._dwell.settle = self._settle_pris

    def _goto_search(self) -> None:
        gate_bin, j, idx = self._search.windows[self._search.pos]
        self._set_step(j, idx)
        self._command(gate_bin, idx, 0)

    def _measured_doppler(self, acc_row: np.ndarray, noise: np.ndarray, f: int
                          ) -> tuple[float, float]:
        """Folded Doppler [Hz] of a detection in filter ``f`` (0-based) and its extra
        tolerance [Hz]: the centre of the filter where the detected cell's excess over the
        noise level is largest (``f`` itself without selectivity, pole 0) plus the
        three-filter discriminator's offset (:func:`.doppler.doppler_offset`) on the filters'
        target amplitudes, the filters rolled so that this filter is the centre one (spacing
        1/3: the filters tile the PRF). The amplitudes per ``doppler_read``: the excess over
        each filter's level, Rice-inverted (:func:`.doppler.rician_amplitude`), or both: the
        midpoint of the two offsets, half their difference the extra tolerance (0 otherwise)."""
        prf = 1.0 / self.pri
        if self.doppler_pole > 0.0:
            # the target's amplitude peaks in the filter nearest to it, which need not be the
            # one that crossed its threshold first (a clutter filter has a higher threshold)
            f = int(np.argmax(acc_row - noise))
        centre = self._doppler + (f - _CF) * self.doppler_spacing_fraction * prf
        if self.doppler_pole <= 0.0:
            return centre, 0.0
        offsets = []
        mode = self.doppler_read
        if mode != "rician":
            offsets.append(doppler_offset(np.roll(acc_row - noise, _CF - f),
                                          self.doppler_spacing_fraction, self.doppler_pole))
        if mode != "excess":
            amp = np.array([rician_amplitude(a, n) for a, n in zip(acc_row, noise, strict=True)])
            offsets.append(doppler_offset(np.roll(amp, _CF - f),
                                          self.doppler_spacing_fraction, self.doppler_pole))
        lo, hi = min(offsets), max(offsets)  # both within the filter's half-spacing
        return centre + 0.5 * (lo + hi) * prf, 0.5 * (hi - lo) * prf

    def _end_acquisition_dwell(self, ok: bool) -> None:
        if self._peak.active:
            self._peak_dwell(ok)
            return
        if ok:
            # seed 000: accumulated cells compared to Th1; noise level per Doppler filter
            # (assumption: median over the 16 range bins, robust to one target and to clutter
            # confined to a filter), smoothed over dwells per filter position class
            self._update_shape(self._dwell.acc)
            med = np.median(self._dwell.acc, axis=0)
            pos = self._positions()
            noise_f = self._noise_pos[pos]
            # a class never measured, or whose dwell median exceeds noise_attack_ratio × its
            # level (the front end changed: the MTI canceller switched, the beam moved into
            # clutter; designer's choice, session 21), restarts from this dwell's median
            new = np.isnan(noise_f)
            if self.noise_attack_ratio > 0.0:
                new |= med > self.noise_attack_ratio * noise_f
            noise_f = np.where(new, med, noise_f + (med - noise_f) / self.noise_avg_dwells)
            self._noise_pos[pos] = noise_f
            # thermal level > 0: noise_power > 0 and doppler_pole < 1 (params.py)
            self._class_shares = class_shares(self._noise_pos.tolist(), self._thermal_level,
                                              self._class_gains)
            th = self._factors(self.pfa_acq, 0) * noise_f
            ratio = self._dwell.acc / th
            i = int(np.argmax(ratio))
            f = i % N_DOPPLER
            self._noise = float(noise_f[f])
            self._threshold = float(th[f])
            if ratio.flat[i] > 1.0:
                # seed 000: "the target is declared present in the cell providing the largest
                # number" among the cells above Th1
                i = int(np.argmax(np.where(ratio > 1.0, self._dwell.acc, -np.inf)))
                f = i % N_DOPPLER
                self._threshold = float(th[f])
                self._detection = True
                r = i // N_DOPPLER
                m0 = (range_to_bin(self._gate) + r - _C) % self._k
                excess = self._reading_excess(self._dwell.acc[r], noise_f)
                # acq_peak_side (session 28): a strong detection in the clutter filter (position
                # class 0: centred on 0 Hz) whose side filters hold only noise would be read at
                # the filter's centre whatever its offset: it gets the peak search
                # (docs/clutter.md "The side test at the acquisition detection")
                side = (self._side_excess(self._dwell.acc[r], noise_f)
                        if self.acq_peak_side and pos[f] == 0 else math.inf)
                if self._peak_wanted(excess, side):  # the largest Doppler cell (doppler_peak)
                    # from the cell that crossed Th1 (not the largest excess: a clutter
                    # filter's fluctuation can exceed a target's skirt below its threshold)
                    gate_bin, j, _ = self._search.windows[self._search.pos]
                    self._start_peak(r, f, m0, j, gate_bin, 0, excess, "acq")
                    return
                fd, fd_tol = self._measured_doppler(self._dwell.acc[r], noise_f, f)
                self._enter_tentative(m0, fd, fd_tol)
                return
        self._search.pos += 1
        if self._search.pos >= len(self._search.windows):
            self._search.passes += 1
            self._start_pass()
            return
        self._goto_search()
