"""Tentative tracking (mode 1) of the radar manager, a mixin of
:class:`~axir.models.manager.machine.RadarManager` (the logic is described in its module
docstring, *Tentative*): range hypotheses (:mod:`.ambiguity`) × Doppler steps
(:mod:`.doppler_search`) at each of the three PRIs, range AND Doppler coherence, then M of N.

Seed 000: "Several Doppler measurements (coherent bursts) are operated with at least 3
different PRIs in order to solve the range-Doppler ambiguities"; tentative tracking "evaluates
the coherence of the unfolded range measurements and Doppler frequencies".
"""

from __future__ import annotations

import math

import numpy as np

from ..radar.conventions import BIN_M, CENTRE_FILTER, GATE_BIN, N_DOPPLER, TENTATIVE
from .ambiguity import candidates, consistent, hypothesis_windows, range_to_bin, resolve_bins
from .doppler_search import (
    blind_mask,
    blind_share,
    candidates_hz,
    consistent_hz,
    consistent_notch_hz,
    fold_cycles,
    steps_for,
)
from .pri_choice import MIN_MARGIN_BINS, choose_confirm_pri, eclipse_margin
from .range_walk import candidate_steps, coupled, step_walks, walk_bins

_C = GATE_BIN - 1  # 0-based index of bin 7
_CF = CENTRE_FILTER - 1  # 0-based central Doppler filter


class TentativeMixin:
    """Hypothesis windows, coherence checks, range/Doppler resolution, M-of-N confirmation."""

    def _enter_tentative(self, m0: int, fd: float, fd_tol: float = 0.0) -> None:
        """Mode 1 from an acquisition detection at apparent bin ``m0`` of the current PRI and
        folded Doppler ``fd`` [Hz] (its first PRI: a weak reading in the notch is handled by
        the tentative measurement there, rule 1 of docs/clutter.md "Tentative in the notch");
        ``fd_tol`` [Hz]: the reading's own extra tolerance (``doppler_read``)."""
        self.mode = TENTATIVE
        t = self._tent
        t.steps = 0
        first = self._pri_idx
        t.order = [first] + [i for i in range(3) if i != first]
        t.order_pos = 0
        t.skipped = -1
        t.notch = -1
        t.notch_fd = math.nan
        t.meas = []
        t.before2 = None
        t.weak = []
        # plausibility (issue 11): only true ranges inside the designation window are
        # hypotheses; none → not the designated target, the search goes on
        cands = candidates(m0, self._k, self._max_bin, self.tol_bins)
        t.cands = cands[self._in_window(cands)]
        # the acquisition dwell's Doppler is trusted only to acq_doppler_tol_fraction of the
        # PRF (a weak target between two filter positions can be measured in the wrong
        # filter): the first tentative PRI searches the steps within it, nearest first
        t.dcands = candidates_hz(fd, 1.0 / self.pri, self._f_max,
                                 max(self._tol_hz(), self.acq_doppler_tol_fraction / self.pri)
                                 + fd_tol)
        t.fd_acq = fd
        t.dmeas = []
        t.doppler = np.nan
        t.confirming = False
        if t.cands.size == 0 or t.dcands.size == 0:
            self._enter_acquisition(self._search.centre_true)
            return
        self._start_pri_search()

    def _notch_rule(self) -> bool:
        """The notch-interval rule is on (``tent_notch_interval``, with a blind fraction and
        Doppler selectivity)."""
        return (self.tent_notch_interval and self.tent_blind_fraction > 0.0
                and self.doppler_pole > 0.0)

    def _weak(self, excess: float) -> bool:
        """A detection of excess ``excess`` (:meth:`_reading_excess`) is weak
        (``tent_weak_excess``): found near its threshold, its Doppler reading may be a false
        alarm's or biased by the MTI notch (NaN: not weak)."""
        return excess < self.tent_weak_excess

    def _reading_excess(self, acc_row: np.ndarray, noise: np.ndarray) -> float:
        """Excess (A − N)/N of a detected cell's accumulated amplitudes ``acc_row`` (3,) over
        the noise levels ``noise`` (3,) in the filter where it is largest (the one the Doppler
        reading is centred on); inf when that level is not positive."""
        ex = acc_row - noise
        f = int(np.argmax(ex))
        n = float(noise[f])
        return float(ex[f]) / n if n > 0.0 else math.inf

    def _in_notch(self, fd: float, idx: int) -> bool:
        """The folded Doppler ``fd`` [Hz] measured at PRI ``idx`` lies within
        ``tent_blind_fraction`` of 0 Hz (the MTI notch, ≥ 7 dB of canceller loss)."""
        return bool(blind_mask(fd, 1.0 / self._pris[idx], self.tent_blind_fraction))

    def _notch_width(self) -> float:
        """Doppler coherence interval of a detection in the notch [cycles per PRI]: the notch
        (``tent_blind_fraction``) widened by the coherence tolerance (a target at the edge)."""
        return self.tent_blind_fraction + self.doppler_tol_fraction

    def _order_rest(self) -> None:
        """Order the PRIs still to be measured: those where more than half of the Doppler
        candidates are blind go last (stable otherwise): a PRI where the target is likely in
        the notch is measured last, where it can be given up (``tent_notch_interval``); so
        does a PRI where a range candidate is eclipsed (``tent_eclipse_last``)."""
        t = self._tent
        end = len(t.order)
        if not self._notch_rule() or t.order_pos >= end - 1:
            return
        rest = t.order[t.order_pos:end]
        share = {i: blind_share(t.dcands, 1.0 / self._pris[i], self.tent_blind_fraction)
                 for i in rest}
        # only a PRI where most candidates are blind moves back (a weak hint otherwise: with
        # the ≈ 19 aliases of one reading every PRI has a blind share near 0.2)
        # a PRI whose gate would straddle the transmit pulse for a range candidate goes last
        # too (measured, 30 km = 2 Ru of PRI 1: searched second in vain for 0.2-0.4 s)
        ecl = {i: self.tent_eclipse_last and self._eclipsed(i) for i in rest}
        t.order[t.order_pos:end] = sorted(
            rest, key=lambda i: (ecl[i] or share[i] > 0.5, rest.index(i)))

    def _eclipsed(self, idx: int) -> bool:
        """A true range candidate of the attempt folds within ``MIN_MARGIN_BINS`` of 0 / Ru
        at PRI ``idx`` (:func:`.pri_choice.eclipse_margin`): the gate straddles the transmit
        pulse there."""
        cands = self._tent.cands
        if cands.size == 0:
            return False
        k = self._ks[idx]
        return any(eclipse_margin(int(b), k) < MIN_MARGIN_BINS for b in cands)

    def _tol_hz(self) -> float:
        """Doppler coherence tolerance [Hz] at the current PRI: ``doppler_tol_fraction`` of the
        PRF, or half the filter spacing without frequency selectivity (pole 0: the filter only
        tells which third of the PRF)."""
        if self.doppler_pole <= 0.0:
            return 0.5 * self.doppler_spacing_fraction / self.pri
        return self.doppler_tol_fraction / self.pri

    def _in_window(self, bins: np.ndarray | int) -> np.ndarray:
        """True where the true range bin(s) lie within ``designation_window`` of the prior
        (designated or last plausible track) range (issue 11 plausibility)."""
        w = self.designation_window / BIN_M + self.tol_bins
        return np.abs(np.asarray(bins) - self._prior_bin()) <= w

    def _prior_bin(self) -> int:
        return range_to_bin(self._search.centre_true)

    def _start_pri_search(self) -> None:
        """Windows for the PRI ``order[order_pos]``: each range hypothesis window × each Doppler
        step whose filters hold a Doppler candidate."""
        t = self._tent
        idx = t.order[t.order_pos]
        k = self._ks[idx]
        prf = 1.0 / self._pris[idx]
        rwins = hypothesis_windows(t.cands, k, self._prior_bin())
        dsteps = steps_for(t.dcands, prf, self.doppler_search_centre, self._n_steps,
                           self.doppler_spacing_fraction,
                           near=t.fd_acq if t.order_pos == 0 and self.acq_doppler_tol_fraction > 0
                           else None)
        t.rwins, t.dsteps = rwins, dsteps
        t.cycles = 0
        self._build_windows()
        self._goto_window()

    def _elapsed(self) -> float:
        """Time since the attempt began [s] (PRIs counted × the current PRI)."""
        return self._tent.steps * self.pri

    def _build_windows(self) -> None:
        """Windows of one pass over the current PRI: each range hypothesis window × each
        Doppler step holding a candidate × each distinct range walk of that step's candidates
        at the window's expected dwell time (``tent_range_walk``, :mod:`.range_walk`; 0
        otherwise)."""
        t = self._tent
        idx = t.order[t.order_pos]
        pri = self._pris[idx]
        per = (self._settle_pris + self.dwell_tent) * pri  # one window's dwell [s]
        mid = (self._settle_pris + 0.5 * self.dwell_tent) * pri
        steps = candidate_steps(t.dcands, 1.0 / pri, self.doppler_search_centre,
                                self._n_steps, self.doppler_spacing_fraction)
        t0 = self._elapsed()
        wins: list[tuple[int, int, int, int]] = []
        for c, h in t.rwins:
            for j in t.dsteps:
                if self.tent_range_walk:
                    dt = t0 + len(wins) * per + mid
                    walks = step_walks(walk_bins(t.dcands, self.wavelength, dt), steps, j)
                else:
                    walks = [0]
                wins += [(c, h, j, w) for w in walks]
        t.windows = wins
        t.win_pos = 0

    def _window_command(self) -> tuple[int, int, int]:
        """(gate bin, offset [bins], Doppler step) of the current window, moved by its walk."""
        t = self._tent
        k = self._ks[t.order[t.order_pos]]
        centre, hyp, j, walk = t.windows[t.win_pos]
        t.walk = walk
        hyp += walk
        return (centre + walk) % k, hyp - (hyp % k), j

    def _goto_window(self) -> None:
        t = self._tent
        idx = t.order[t.order_pos]
        gate_bin, offset, j = self._window_command()
        self._set_step(j, idx)
        self._command(gate_bin, idx, offset)

    def _end_tentative_dwell(self, ok: bool) -> None:
        if self._peak.active:
            self._peak_dwell(ok)
            return
        t = self._tent
        r, f = self._track_test(slice(0, N_DOPPLER)) if ok else (-1, -1)
        if t.confirming:
            # M of N on the resolved range and Doppler: the target must be in the central
            # filter, now centred on the resolved Doppler (Doppler coherence kept; pole 0:
            # no Doppler selectivity, any filter)
            if r >= 0 and (f == _CF or self.doppler_pole <= 0.0):
                t.hits += 1
                t.filter_energy[f] += 1.0
                t.bin_hits[r - _C + 1] += 1
            else:
                t.nmiss += 1
            if t.hits >= self.confirm_m:
                self._enter_confirmed()
            elif t.nmiss > self.confirm_n - self.confirm_m:
                self._enter_acquisition(self._search.centre_true)
            else:
                self._restart_dwell(settle=False)
            return
        idx = t.order[t.order_pos]
        k = self._ks[idx]
        if r >= 0:
            m = (range_to_bin(self._gate) + r - _C) % k
            noise = self._dwell.acc[self._th2_noise_bins].mean(axis=0)
            excess = self._reading_excess(self._dwell.acc[r], noise)
            # session 9 (doppler_peak_side): a reading at the 2nd or 3rd PRI picks the alias
            # among ≈ 1 000 candidates and nothing after it checks it; the first PRI's is
            # checked against the acquisition's reading (coherence)
            side = (self._side_excess(self._dwell.acc[r], noise) if t.order_pos >= 1
                    else math.inf)
            if self._peak_wanted(excess, side):  # the largest Doppler cell (doppler_peak)
                gate_bin, offset, j = self._window_command()  # the cell that crossed Th2
                self._start_peak(r, f, m, j, gate_bin, offset, excess, "tent")
                return
            fd, fd_tol = self._measured_doppler(self._dwell.acc[r], noise, f)
            self._tent_reading(m, fd, self._weak(excess), fd_tol)
            return
        self._next_window()

    def _tent_reading(self, m: int, fd: float, weak: bool, fd_tol: float = 0.0) -> None:
        """A tentative detection at apparent bin ``m`` with folded Doppler reading ``fd`` [Hz]
        (``weak``: :meth:`_weak`; ``fd_tol`` [Hz]: the reading's extra tolerance,
        ``doppler_read``): kept when coherent in range AND Doppler (then the next PRI), else
        the search goes on (:meth:`_next_window`)."""
        t = self._tent
        idx = t.order[t.order_pos]
        k = self._ks[idx]
        # the one blind PRI of the attempt: a weak reading in the notch says only "in the
        # notch"; once that exception is used (a PRI given up or read in the notch) a
        # reading is a value again (a blind speed, in the notch at every PRI: the only
        # information left)
        notch = (self._notch_rule() and t.skipped < 0 and t.notch < 0 and weak
                 and self._in_notch(fd, idx))
        if notch:
            dcands = consistent_notch_hz(t.dcands, 1.0 / self.pri, self._notch_width())
        else:
            dcands = consistent_hz(t.dcands, fd, 1.0 / self.pri, self._tol_hz() + fd_tol)
        if self.tent_range_walk:  # range-Doppler coupling (range_walk): the window's walk
            m, cands, dcands = coupled(t.cands, dcands, m, k, self.tol_bins, self.wavelength,
                                       self._elapsed(), t.walk)
        else:
            cands = consistent(t.cands, m, k, self.tol_bins)
        if not (cands.size and dcands.size) and not notch:
            cands, dcands = self._retro_skip(m, fd, fd_tol)
        if cands.size and dcands.size:  # coherent in range AND Doppler
            if t.order_pos == 1:
                t.before2 = (t.cands, t.dcands)
            t.meas.append((k, m))
            if weak:
                t.weak.append(idx)
            if notch:
                t.notch = idx
                t.notch_fd = fd
            else:
                t.dmeas.append((1.0 / self.pri, fd))
            t.cands, t.dcands = cands, dcands
            t.order_pos += 1
            self._next_pri()
            return
        self._next_window()

    def _next_window(self) -> None:
        """No coherent detection in this window: the next one (after ``tent_window_cycles``
        passes the PRI is given up or the attempt ends)."""
        t = self._tent
        t.win_pos += 1
        if t.win_pos >= len(t.windows):
            t.cycles += 1
            self._build_windows()  # the walks at the new pass' times
            if t.cycles >= self.tent_window_cycles:
                if self.tent_blind_fraction > 0.0 and t.skipped < 0 and t.order_pos >= 1:
                    # not found at this PRI: give it up, under the hypothesis that the target
                    # is blind there: only the Doppler candidates blind at it remain. With a
                    # PRI read in the notch already (two blind PRIs: a blind speed), that
                    # reading is taken as a value after all (as without the notch rule)
                    dc = t.dcands
                    prf_n = 1.0 / self._pris[t.notch] if t.notch >= 0 else math.nan
                    if t.notch >= 0:
                        dc = consistent_hz(dc, t.notch_fd, prf_n,
                                           self.doppler_tol_fraction * prf_n)
                    blind = dc[blind_mask(dc, 1.0 / self.pri, self.tent_blind_fraction)]
                    if blind.size:
                        if t.notch >= 0:
                            t.dmeas.append((prf_n, t.notch_fd))
                            t.notch = -1
                        t.skipped = t.order.pop(t.order_pos)
                        t.dcands = blind
                        self._next_pri()
                        return
                self._enter_acquisition(self._search.centre_true)
                return
        self._goto_window()

    def _retro_skip(self, m: int, fd: float, fd_tol: float = 0.0
                    ) -> tuple[np.ndarray, np.ndarray]:
        """At the third PRI, a detection (apparent bin ``m``, folded Doppler ``fd`` [Hz],
        extra tolerance ``fd_tol`` [Hz])
        incoherent with the second PRI's measurement but coherent with the first's: the second
        one was a false alarm at a PRI where the target is blind (found there only by noise or
        clutter residue, docs/clutter.md "Tentative in the notch"). It becomes the given-up
        PRI: its measurement is dropped and only the candidates blind at it remain. Returns the
        (range, Doppler) candidates, empty when that hypothesis fails too (or is not open:
        ``tent_notch_interval`` off, not the third PRI, the blind-PRI exception used, the
        second PRI's detection not weak, ``tent_weak_excess``)."""
        t = self._tent
        none = (t.cands[:0], t.dcands[:0])
        if (not self._notch_rule() or t.order_pos != 2 or len(t.order) != 3
                or t.skipped >= 0 or t.notch >= 0 or t.before2 is None or len(t.dmeas) != 2):
            return none
        s = t.order[1]
        if s not in t.weak:  # a strong reading at the second PRI is not a false alarm
            return none
        cands0, dcands0 = t.before2
        k = self._ks[t.order[2]]
        cands = consistent(cands0, m, k, self.tol_bins)
        dc = consistent_hz(dcands0, fd, 1.0 / self.pri, self._tol_hz() + fd_tol)
        dc = dc[blind_mask(dc, 1.0 / self._pris[s], self.tent_blind_fraction)]
        if not (cands.size and dc.size):
            return none
        t.skipped = t.order.pop(1)
        t.order_pos = 1
        del t.meas[1]
        del t.dmeas[1]
        return cands, dc

    def _notch_rejects(self, cost: np.ndarray | float, best: int) -> bool:
        """The resolution is clutter (``clutter_notch_speed``): with ``notch_reject``
        "resolved", when the resolved Doppler (candidate ``best``) is in the notch or a
        candidate in the notch explains the readings nearly as well, its RMS residual within
        ``notch_fit_ratio`` × the resolved one's (``cost``: each candidate's sum of squared
        folded residuals [Hz²]); with "any" (session 4), when any candidate is in it."""
        t = self._tent
        inn = np.abs(t.dcands) < 2.0 * self.clutter_notch_speed / self.wavelength
        if not inn.any():
            return False
        if self.notch_reject == "any" or inn[best]:
            return True
        c = np.broadcast_to(cost, inn.shape)  # (no reading: 0, every candidate alike)
        return bool(c[inn].min() <= self.notch_fit_ratio ** 2 * c[best])

    def _next_pri(self) -> None:
        """Search the next PRI of the order, or resolve once every PRI left was measured."""
        t = self._tent
        if t.order_pos < len(t.order):
            self._order_rest()
            self._start_pri_search()
        else:
            self._resolve()

    def _resolve(self) -> None:
        """After three coherent PRIs (or two, the third given up: accepted only when the
        resolved Doppler folds within ``tent_blind_fraction`` of 0 Hz at it): resolved range
        inside the designation window, Doppler clear of the clutter notch, else back to
        acquisition; then M of N at the kept PRI (a measured one) with the Doppler centre on
        the resolved Doppler."""
        t = self._tent
        meas = t.meas
        b = resolve_bins([mm for _, mm in meas], [kk for kk, _ in meas], self._max_bin,
                         self.tol_bins)
        if b is None or not bool(self._in_window(b)):
            self._enter_acquisition(self._search.centre_true)
            return
        # the candidate with the smallest sum of squared folded residuals (ties: the first)
        cost = sum((fold_cycles(t.dcands - f, prf) * prf) ** 2 for prf, f in t.dmeas)
        best = int(np.argmin(cost))
        if self._notch_rejects(cost, best):
            self._enter_acquisition(self._search.centre_true)
            return
        t.doppler = float(t.dcands[best])
        if self.tent_range_walk:  # b is the range at the attempt's start: move it to now
            b += int(walk_bins(np.array([t.doppler]), self.wavelength, self._elapsed())[0])
        self._resolved_bin = b
        if t.skipped >= 0:
            # two PRIs only: accepted when the third is blind for this Doppler
            prf_s = 1.0 / self._pris[t.skipped]
            if fold_cycles(t.doppler, prf_s) > self.tent_blind_fraction:
                self._enter_acquisition(self._search.centre_true)
                return
        # PRIs where the resolved Doppler is blind (given up, measured in the notch, or
        # folding into it unless measured there by a strong detection): never kept for
        # confirmation while another one is clear
        strong = {self._ks.index(kk) for kk, _ in meas} - set(t.weak)
        blind = {t.skipped, t.notch} | {
            i for i, p in enumerate(self._pris)
            if self.tent_blind_fraction > 0.0 and i not in strong
            and fold_cycles(t.doppler, 1.0 / p) <= self.tent_blind_fraction}
        if len(blind - {-1}) >= 3:
            blind = {t.skipped}
        if self.confirm_pri_index == 0 or self.confirm_pri_index - 1 in blind:
            # the PRI with the largest eclipse margin, never a blind one, or the least
            # predicted canceller loss (pri_choice, confirm_max_loss_db)
            ci = choose_confirm_pri(b, self._ks, self._pris, t.doppler, blind,
                                    self.confirm_max_loss_db, self.confirm_loss_mti_order)
        else:
            ci = self.confirm_pri_index - 1
        kc = self._ks[ci]
        t.confirming = True
        t.filter_energy.fill(0.0)
        t.bin_hits = [0, 0, 0]
        t.hits = 0
        t.nmiss = 0
        self._set_doppler(t.doppler, ci)
        self._command(b % kc, ci, b - b % kc)
