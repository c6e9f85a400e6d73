"""State machine of the adaptive Radar Manager (AXIR_C, seed 000): modes, PRIs, gains, servo.

The manager runs the three AXIR modes (seed 000 "Operating Modes"):

**Acquisition** (mode 0). Seed: "The magnitudes of the … four squinted beams are accumulated … for
the three Doppler filters and for the sixteen range gates. Each channel is compared to a threshold.
If one result is trespassing this level, the target is declared present in the cell providing the
largest number." The Tracker sends SUM(R, f) (seed eq. 1); the manager accumulates it
non-coherently over a dwell of ``dwell_acq`` PRIs, estimates the noise level of each Doppler filter
as the median of its 16 accumulated range cells (robust to one target, and to clutter confined to
some filters), smoothed over dwells (``noise_avg_dwells``) per PRI and filter position, and
sets Th1_f = c1_f·noise_f with c1_f
the ratio of the (1 − pfa_acq) quantile to the median of the accumulated statistic (exact law
of the IIR-filtered noise, or one look in a clutter-dominated filter: see *Thresholds*); the
target is the largest cell above its Th1. The gate search steps ``gate.command`` across
±``search_extent`` around the designated range (taken modulo the acquisition PRI's Ru), one
window per dwell, ``search_step_bins`` apart (16-bin windows, so 16 − step bins overlap), centre
first then alternately farther / nearer; a whole-Ru search when the extent covers Ru. On a Th1
crossing the gate is re-centred so the detected bin becomes bin 7 and the manager goes tentative.
Issue 11 (designer's choices, :mod:`.doppler_search`, docs/doppler_coverage.md): every window is
searched at ``n`` Doppler steps of the filter bank (PRF/(3n) apart, n = 9 for ≤
``doppler_max_loss_db`` = 4 dB), step 0 first; the acquisition PRI cycles over the passes
(``acq_pri_cycle``) and the ``acq_all_pri_windows`` innermost windows are searched at the
three PRIs in a row (a speed blind at one PRI is clear at another); a detection's folded
Doppler is measured (filter centre + discriminator).

**Tentative** (mode 1). Seed: "Several Doppler measurements (coherent bursts) are operated with
at least 3 different PRIs in order to solve the range-Doppler ambiguities … 'target present' is
determined by the central range gates and the threshold (Th2). Side range bins are accumulated to
give the ambient noise level used to determine Th2 … R = Ro + N*75 m. It is the Radar Manager
which calculates this value". The manager measures the apparent range at each of the 3 PRIs
(acquisition PRI first). Per dwell (``dwell_tent`` PRIs) and per Doppler filter,
Th2_f = c2_f·(mean of side bins 1-3, 11-16 of that filter); "target present" when a cell of
bins 6-8 exceeds its filter's Th2 (assumption: per filter rather than Σ_f, so clutter in one
filter does not mask or fake the target); the apparent bin is that of the largest central cell
relative to Th2. *Finding the target after a PRI change* (assumption: hypothesis windows): the
candidate true range bins B consistent with the measurements so far (±``tol_bins``) predict the
apparent bin B mod k at the new PRI; the predictions are merged into 3-bin clusters, each visited
with a window centred on it (nearest to the designated / last known range first), and
``range.offset`` is set to that hypothesis' N·Ru so "true = apparent + offset" stays physically
consistent while the window is on it. After two PRIs the candidates are usually reduced to one
cluster (the first two default PRIs are ghost-free to 285 km), so the third PRI is a single
window: the seed's coherence check. Issue 11: only true ranges within ``designation_window``
of the designated (or last plausible) range are hypotheses; each PRI also visits only the
Doppler steps holding an unfolded Doppler candidate, and a detection counts only when it is
coherent in range AND Doppler (:mod:`.doppler_search`); a resolved Doppler in the clutter notch,
or a notch candidate that fits the readings nearly as well (``clutter_notch_speed``,
``notch_reject``, ``notch_fit_ratio``), is clutter → acquisition. The three measurements go to
:func:`.ambiguity.resolve_bins`; inconsistent → acquisition. The resolved range sets
the PRI kept for confirmed tracking (``confirm_pri_index``; 0 = automatic: the PRI whose apparent
range is farthest from the eclipse at 0 / Ru, or the least predicted canceller loss:
:mod:`.pri_choice`), its gate and ``range.offset`` = N·Ru; then
``confirm_m`` detections out of ``confirm_n`` dwells → confirmed, else acquisition. Tentative
also falls back after ``tent_timeout_pris`` PRIs or after ``tent_window_cycles`` unsuccessful
passes over a PRI's hypothesis windows.

**Confirmed** (mode 2). Seed: "The bandwidths of the servo-loops are progressively reduced up to
a certain limit … the Doppler frequency is calculated by the Radar Manager and only the central
Doppler filter is used". One PRI is kept (the generator does not model eclipsing; the kept PRI
is chosen with the largest eclipse margin or the least predicted canceller loss) until the
tracked Doppler predicts more than ``confirm_max_loss_db`` of canceller loss there and another
PRI ``confirm_switch_db`` less (a turning target's Doppler walking into the clutter line,
:mod:`.pri_choice`): the gate and ``range.offset`` are then re-expressed at the new Ru for the
same true range and the Doppler centre refolded. Per dwell
(``dwell_conf``) Th2 is applied on the central filter only (bins 6-8 vs side bins);
``miss_limit`` consecutive missed dwells → track lost → acquisition, searching around the last
track range (option ``blind_coast_time``, off: not while the Doppler crosses a blind band);
kept while the Tracker's range rate crosses the clutter notch (``notch_coast_time``, session 30).
Plausibility (issue 11): a track leaving [0, ``max_range``], moving faster than
``max_speed`` from its anchor (:meth:`RadarManager.step`) or, once
``doppler_track_delay`` old, with |range rate| > ``max_speed`` is dropped the same way, around
its last plausible range. ``bandwidth`` falls log-linearly (geometrically) from ``bw_start``
to ``bw_floor``
over ``bw_decay_time`` and then holds (monotonic; assumption: the seed gives no law).
``doppler.centre`` is the resolved Doppler of tentative (folded at the kept PRI) until
``doppler_track_delay`` seconds of confirmed tracking ("As the trajectory is perfectly
smoothed"), then fold(−2ṙ/λ, PRF) from ``track.range_rate`` (radar.py convention), re-computed
at each dwell end and held in between, plus the discriminator's bias, bounded by
``doppler_bias_max_speed`` and dropped after ``doppler_bias_reset_misses`` missed dwells
(issue 11: the bias diverged in clutter). Steady α-β gains (seed: "The Radar Manager is
responsible for updating the Alpha-Beta coefficients"; "the unknown target manoeuvres must
influence the Alpha-Beta parameters") come from the tracking index Λ = σ_m·T²/σ_n (Kalata 1984,
:func:`axir.models.filters.gains.kalata_gains`), T = the current PRI (assumption: the tracker
updates once per PRI, seed 000 Conclusion), σ_m = ``sigma_man``, or ``sigma_man_high`` while
``maneuver`` is True and for ``maneuver_hold`` s after it. They are sent throughout mode 2 and
are 0 in modes 0-1 (SYSTEM.md: evolutive gains "until the manager's steady gains take over"):
the Tracker uses max(evolutive α(n), steady α) per gain (filters.gains.scheduled_gains), so it
hands over by itself once its α(n) = 2(2n − 1)/(n(n + 1)) has fallen below the steady value.

**Timing.** Every command change (gate, PRI, Doppler centre, mode) is followed by ``latency_pris`` +
⌈settle_db / (−20·log10 doppler_pole)⌉ ignored PRIs (3 + 44 = 47 by default): the co-simulation
loop manager → tracker → generator → tracker → manager lags a few steps, and the generator's
IIR Doppler filters (pole ρ) keep the previous gate's echoes for ~1/(1 − ρ) PRIs. In modes 0
and 1 a sample is also ignored while the ``gate.start`` reported by the Tracker differs (modulo
Ru) from ``gate.command`` (the Tracker has not taken the command); if no sample comes for
``stall_pris`` PRIs the dwell counts as a miss. A non-finite or misshaped ``sum`` (or a
non-finite ``gate.start``) marks the current dwell as a miss and is never accumulated; non-finite
``track.*``/``maneuver``/``dt`` inputs are ignored (previous values held, dt → PRI).

**Thresholds** (:mod:`.thresholds`): Th1 = c1_f·noise_f and Th2 = c2_f·(side-bin mean), c the
(1 − Pfa) quantile of the dwell sum of the Doppler-filtered noise over its median (Th1) or mean
(Th2), exact for thermal noise, iid Rayleigh looks for a clutter-dominated filter
(``adaptive_looks``). **Doppler discriminator** (confirmed mode): :mod:`.doppler`. **Range
ambiguity** (tentative mode): :mod:`.ambiguity`.

**Integration contract** (what the other units must do): see :mod:`axir.models.manager`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from ..filters.gains import kalata_gains
from ..radar.conventions import (
    ACQUISITION,
    BIN_M,
    CENTRE_FILTER,
    CONFIRMED,
    GATE_BIN,
    N_BINS,
    N_DOPPLER,
    TENTATIVE,
    fold_doppler,
)
from ..radar.params import Param
from ..radar.unit import Unit
from .acquisition import AcquisitionMixin
from .ambiguity import pri_seconds, range_to_bin
from .cfar import ThresholdsMixin
from .doppler_peak import DopplerPeakMixin, Peak
from .doppler_search import coverage_steps, step_centre
from .doppler_track import DopplerTrackMixin
from .hotpath import StepOutputsMixin, filter_positions
from .params import PARAMS, check_params
from .ports import _F64, _SUM_SHAPE, INPUTS, OUTPUTS, finite_or_none, read_sum
from .pri_choice import parse_track_pri_bins
from .residue import class_thermal_gains
from .state import Dwell, Search, Tentative, Track
from .tentative import TentativeMixin
from .thresholds import dwell_sum_factors, initial_spread

_C = GATE_BIN - 1  # 0-based index of bin 7
_CENTRAL = slice(_C - 1, _C + 2)  # bins 6, 7, 8
_add_reduce = np.add.reduce  # what ndarray.sum / mean call, without their Python wrappers
# round 12: module globals for step (numpy's module __getattr__ keeps np.X unspecialised)
_np_add, _ndarray, _isfinite = np.add, np.ndarray, math.isfinite
_GATE0_M = _C * BIN_M  # [m] gate centre − gate start (bin 7 − bin 1)
# Side range bins for Th2 (seed: "Side range bins are accumulated to give the ambient noise
# level"): bins at least 4 bins from the gate centre, 1-3 and 11-16 (assumption: clear of the
# straddle of a target anywhere in bins 6-8). Not the Tracker's noise bins (its own choice).
_TH2_NOISE_BINS = np.array([r for r in range(N_BINS) if abs(r - _C) >= 4])
_CF = CENTRE_FILTER - 1  # 0-based central Doppler filter
#: plausibility anchor of a confirmed track (designer's choice): re-anchored every second,
#: a 3-bin margin for the measurement noise and the resolution quantisation
ANCHOR_PERIOD = 1.0  # [s]
ANCHOR_MARGIN_M = 3 * BIN_M


def _scalar_inputs(dt: Any, inputs: Mapping[str, Any]
                   ) -> tuple[float | None, float | None, float | None, float | None]:
    """``dt`` [s], ``track.range`` [m], ``track.range_rate`` [m/s] and ``maneuver`` one by one
    (:func:`.ports.finite_or_none`; None: absent, not a number or non-finite, held)."""
    man = inputs.get("maneuver")
    return (finite_or_none(dt), finite_or_none(inputs.get("track.range")),
            finite_or_none(inputs.get("track.range_rate")),
            None if man is None else finite_or_none(man))


class RadarManager(AcquisitionMixin, TentativeMixin, DopplerPeakMixin, DopplerTrackMixin,
                   ThresholdsMixin, StepOutputsMixin, Unit):
    """AXIR_C adaptive radar manager (see the module docstring for the logic and the contract).

    ``step(dt, inputs)``: ``dt`` [s] is the communication step (nominally ``pri``; time in
    confirmed mode and the maneuver hold advance by ``dt``); ``inputs`` and the returned outputs
    are keyed as in :data:`INPUTS` / :data:`OUTPUTS`.
    """

    INPUTS = INPUTS
    OUTPUTS = OUTPUTS

    PARAMS: ClassVar[tuple[Param, ...]] = PARAMS

    # -------------------------------------------------------------------------------- set-up
    def _check(self) -> None:
        check_params(self)

    def reset(self) -> None:
        ks = (self.pri1_bins, self.pri2_bins, self.pri3_bins)
        self._ks: tuple[int, int, int] = ks
        self._pris = tuple(pri_seconds(k) for k in ks)
        # + the confirmed-tracking PRIs (indices ≥ 3: confirmed mode only, pri_choice.py)
        self._all_ks = ks + parse_track_pri_bins(self.track_pri_bins, ks)
        self._all_pris = tuple(pri_seconds(k) for k in self._all_ks)
        self._max_bin = range_to_bin(self.max_range)
        # independent fraction φ of the looks_per_pri·K looks of a dwell, per Doppler filter:
        # model value from doppler_pole, then (adaptive_looks) estimated from the data
        for k in {self.dwell_acq, self.dwell_tent, self.dwell_conf}:  # warm the factor caches
            dwell_sum_factors(self.looks_per_pri, k, self.doppler_pole, self.pfa_acq)
            dwell_sum_factors(self.looks_per_pri, k, self.doppler_pole, self.pfa_track)
        # EMA of the normalised spread s_f = (IQR/median)·√(looks_per_pri·K) = 0.705/√φ_f
        # Doppler steps covering the PRF within doppler_max_loss_db (doppler_search), and the
        # physical Doppler bound 2·max_speed/λ of the unfolded candidates
        self._n_steps = coverage_steps(self.doppler_spacing_fraction, self.doppler_pole,
                                       self.doppler_max_loss_db) if self.doppler_pole > 0 else 1
        self._f_max = 2.0 * self.max_speed / self.wavelength
        # per filter position class (distance from 0 Hz on the grid of 3·n_steps positions
        # over the PRF, in cycles: the clutter leakage and the noise level are the same at ±δ
        # and at every PRF): EMA of the normalised spread s = (IQR/median)·√(looks_per_pri·K)
        # = 0.705/√φ and of the acquisition noise level
        n_cls = N_DOPPLER * self._n_steps // 2 + 1
        s0 = initial_spread(self.looks_per_pri, self.dwell_acq, self.doppler_pole)[0]
        self._spread_pos = np.full(n_cls, s0)
        self._spread_seen = np.zeros(n_cls, dtype=bool)
        self._noise_pos = np.full(n_cls, math.nan)
        # per class: filtered thermal power behind the canceller (residue_share_looks)
        self._class_gains = class_thermal_gains(
            n_cls, self.doppler_spacing_fraction / self._n_steps, self.doppler_pole,
            self.confirm_loss_mti_order)
        self._class_shares = [0.0] * n_cls  # beam-common residue share (residue.class_shares)
        self._th2_noise_bins = _TH2_NOISE_BINS
        self._pos_key: tuple[float, float, int, float] | None = None  # _positions' cache
        self._pos = np.zeros(N_DOPPLER, dtype=np.int64)
        self._pos_list: list[int] = [0] * N_DOPPLER  # the same as Python ints
        # median of the thermal acquisition dwell sum (exact law, in SUM units): mean
        # looks·K·(√π/2)·σ_y, σ_y² = noise_power·(1 − ρ)/(1 + ρ) the filtered noise power
        qmed, qmean = dwell_sum_factors(self.looks_per_pri, self.dwell_acq, self.doppler_pole,
                                        self.pfa_acq)
        sig_y = math.sqrt(self.noise_power * (1.0 - self.doppler_pole)
                          / (1.0 + self.doppler_pole))
        self._thermal_level = (self.looks_per_pri * self.dwell_acq * 0.5 * math.sqrt(math.pi)
                               * sig_y * qmean / qmed)
        self._dop_changed = False
        # PRIs ignored after a command change: loop latency + IIR transient below settle_db
        ring = 0
        if self.doppler_pole > 0.0:
            ring = math.ceil(self.settle_db / (-20.0 * math.log10(self.doppler_pole)))
        self._settle_pris = self.latency_pris + ring
        self._dwell = Dwell(settle=self._settle_pris)
        # outputs / shared state
        self.mode = ACQUISITION
        self._pri_idx = self.acq_pri_index - 1
        self._gate = 0.0
        self._offset = 0.0
        self._doppler = self.doppler_search_centre
        self._threshold = math.nan
        self._noise = math.nan
        self._detection = False
        self._dwell_done = False
        self._resolved_bin = -1
        self._bw = self.bw_start
        self._alpha = 0.0
        self._beta = 0.0
        self._lambda = math.nan
        self._gains_key: tuple[float, float] = (math.nan, math.nan)
        self._gains = (0.0, 0.0)
        self._out_tmpl = None  # hotpath.StepOutputsMixin
        self._tmpl_gains_key = None
        self._track = Track(doppler_base=self._doppler)
        self._tent = Tentative()
        self._peak = Peak()
        self._search = Search(centre_true=self.designation_range)
        self._enter_acquisition(self.designation_range)
        self._dwell.settle = self._settle_pris

    # ------------------------------------------------------------------------------ helpers
    @property
    def _k(self) -> int:
        return self._all_ks[self._pri_idx]

    @property
    def pri(self) -> float:
        """Current PRI [s] (a confirmed-tracking PRI too)."""
        return self._all_pris[self._pri_idx]

    def _command(self, gate_bin: int, pri_idx: int, offset_bins: int) -> None:
        """Set gate (apparent bin of the gate centre), PRI and offset; restart the dwell."""
        changed = (gate_bin * BIN_M != self._gate or pri_idx != self._pri_idx
                   or offset_bins * BIN_M != self._offset or self._dop_changed)
        self._dop_changed = False
        self._gate = gate_bin * BIN_M
        self._pri_idx = pri_idx
        self._offset = offset_bins * BIN_M
        self._restart_dwell(settle=changed)

    def _set_doppler(self, f: float, pri_idx: int) -> None:
        """Doppler centre ``f`` [Hz] folded at PRI ``pri_idx``; a change settles the dwell
        at the next :meth:`_command`."""
        d = fold_doppler(f, self._pris[pri_idx])
        self._dop_changed = self._dop_changed or d != self._doppler
        self._doppler = d

    def _set_step(self, j: int, pri_idx: int) -> None:
        """Doppler centre of step ``j`` (:func:`.doppler_search.step_centre`) at PRI
        ``pri_idx``."""
        prf = 1.0 / self._pris[pri_idx]
        self._set_doppler(step_centre(self.doppler_search_centre, j, self._n_steps,
                                      self.doppler_spacing_fraction, prf), pri_idx)

    def _positions(self) -> np.ndarray:
        """Position classes (3,) of the current Doppler filters: the distance from 0 Hz of the
        nearest of the 3·n_steps grid positions over the PRF, in grid steps. Cached while the
        Doppler centre, PRI, n_steps and spacing are unchanged (issue 14: a dwell end asks up
        to three times); callers only index with it."""
        pri = self._all_pris[self._pri_idx]
        key = (self._doppler, pri, self._n_steps, self.doppler_spacing_fraction)
        if key == self._pos_key:
            return self._pos
        self._pos = filter_positions(*key)
        self._pos_list = self._pos.tolist()
        self._pos_key = key
        return self._pos

    def _restart_dwell(self, settle: bool = True) -> None:
        self._dwell.acc.fill(0.0)
        self._dwell.n_seen = 0
        self._dwell.bad = False
        self._dwell.stall = 0
        if settle:
            self._dwell.settle = self._settle_pris

    def _enter_confirmed(self) -> None:
        self.mode = CONFIRMED
        self._track.conf_time = 0.0
        self._track.misses = 0
        self._track.notch = False
        # the resolved unfolded Doppler (tentative) folded at the kept PRI, moved to the filter
        # that held the M-of-N hits (the centre one, except without selectivity, pole 0)
        unfolded = math.nan
        if math.isfinite(self._tent.doppler):
            f = int(np.argmax(self._tent.filter_energy))
            shift = (f - _CF) * self.doppler_spacing_fraction / self.pri
            unfolded = self._tent.doppler + shift
            self._doppler = fold_doppler(unfolded, self.pri)
        self._start_doppler_track(self._doppler, unfolded)
        lo, mid, hi = self._tent.bin_hits  # confirm_range_recentre (session 26)
        if self.confirm_range_recentre and max(lo, hi) > mid and lo != hi:
            b = round((self._gate + self._offset) / BIN_M) + (-1 if lo > hi else 1)
            if b >= 0:  # (range.resolved: the moved true bin)
                kc = self._ks[self._pri_idx]
                self._gate, self._offset = (b % kc) * BIN_M, (b - b % kc) * BIN_M
                self._resolved_bin = b
        self._track.pri_switches = 0
        self._track.last_range = self._gate + self._offset
        self._track.good_range = self._track.last_range
        self._track.anchor_range = self._track.last_range
        self._track.anchor_time = 0.0
        self._restart_dwell(settle=True)

    def _drop_track(self) -> None:
        """Track lost or implausible: re-acquisition around the last plausible track range."""
        centre = self._track.good_range
        if not math.isfinite(centre):
            centre = self._search.centre_true
        self._enter_acquisition(min(max(centre, 0.0), self.max_range))

    # ----------------------------------------------------------------------------- dwell ends
    def _track_test(self, filters: slice) -> tuple[int, int]:
        """Th2 test (seed 000: "target present" from the central range bins 6-8, Th2 from the
        ambient noise of the side range bins), per Doppler filter in ``filters``.

        Returns the 0-based (bin, filter) of the largest central cell relative to its filter's
        Th2, or (−1, −1) if none exceeds it; sets ``threshold`` / ``noise.level``.
        """
        acc = self._dwell.acc[:, filters]
        self._update_shape(self._dwell.acc[_TH2_NOISE_BINS])
        side = acc[_TH2_NOISE_BINS]
        # issue 14: side.mean(axis=0) without its wrapper: numpy's mean is this sum divided in
        # place by the count
        noise = _add_reduce(side, 0)
        noise /= side.shape[0]
        th = self._factors(self.pfa_track, 1)[filters] * noise
        ratio = acc[_CENTRAL] / th
        i = int(ratio.argmax())  # np.argmax without its wrapper
        j, f = divmod(i, ratio.shape[1])
        self._noise = noise.item(f)  # issue 14: float(a[f]) and a.flat[i] without the
        self._threshold = th.item(f)  # numpy scalar / flat iterator
        f += filters.start or 0
        if ratio.item(i) > 1.0:
            self._detection = True
            return _C - 1 + j, f
        return -1, -1

    def _end_confirmed_dwell(self, ok: bool) -> None:
        r = -1
        if ok:
            r, _ = self._track_test(slice(_CF, _CF + 1))
        tr = self._track
        if r >= 0:
            tr.misses, tr.seen_time = 0, tr.conf_time
        else:
            tr.misses += 1
        if r >= 0:
            tr.notch = False
        if tr.misses >= self.miss_limit and not (self._notch_coast() or self._blind_coast()):
            self._drop_track()
            return
        self._follow_doppler(ok)
        self._restart_dwell(settle=False)
        if self._dithering():  # the filter's transient after the displacement
            self._dwell.settle = self.doppler_dither_settle
        self._switch_confirmed_pri()

    # ----------------------------------------------------------------------------------- step
    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """Advance one communication step ``dt`` [s] (nominally one PRI); see class docstring."""
        tr = self._track  # track inputs (held when non-finite)
        try:  # issue 14: the common case, every scalar input a finite number, screened at once
            dtv: float | None = float(dt)
            rng: float | None = float(inputs["track.range"])
            rate: float | None = float(inputs["track.range_rate"])
            mv: float | None = float(inputs["maneuver"])
            # one isfinite for the four (inf/NaN propagate; a finite sum that overflows only
            # takes the one-by-one rule, which gives these same values: issue 14, round 7)
            if not _isfinite(dtv + rng + rate + mv):
                raise ValueError
        except (TypeError, ValueError, KeyError):
            dtv, rng, rate, mv = _scalar_inputs(dt, inputs)
            dt_eff = dtv if dtv is not None and dtv > 0.0 else self._all_pris[self._pri_idx]
            if rng is not None:
                tr.last_range = rng
            if rate is not None:
                tr.last_rate = rate
            if mv is not None:
                tr.maneuver = mv != 0.0
            man = tr.maneuver
        else:  # round 12: none held, so no None tests
            dt_eff = dtv if dtv > 0.0 else self._all_pris[self._pri_idx]
            tr.last_range = rng
            tr.last_rate = rate
            tr.maneuver = man = mv != 0.0
        self._detection = False
        self._dwell_done = False
        if man:
            tr.since_maneuver = 0.0
        else:
            tr.since_maneuver += dt_eff

        mode = self.mode
        if mode == CONFIRMED:
            tr.conf_time += dt_eff
            # confirmed-track plausibility (issue 11; written out here, issue 14 round 7): the
            # track range stays inside the instrumented range [0, max_range] and moves no
            # faster than max_speed from an anchor (the resolved range at confirmation, then
            # the track range each ANCHOR_PERIOD), within ANCHOR_MARGIN_M; once the track is
            # doppler_track_delay old (its velocity has converged, the Doppler centre follows
            # it) also |track.range_rate| ≤ max_speed. Records the last plausible range; a held
            # (absent or non-finite) range is plausible and moves nothing
            if rng is not None:
                conf = tr.conf_time
                age = conf - tr.anchor_time
                if (not rng >= 0.0 or not rng <= self.max_range
                        or abs(rng - tr.anchor_range) > self.max_speed * age + ANCHOR_MARGIN_M
                        or (conf >= self.doppler_track_delay
                            and abs(tr.last_rate) > self.max_speed)):
                    self._drop_track()
                else:
                    if age >= ANCHOR_PERIOD:
                        tr.anchor_range, tr.anchor_time = rng, conf
                    tr.good_range = rng
                    self._gate = rng - self._offset
        elif mode == TENTATIVE:
            self._tent.steps += 1

        # sample
        dw = self._dwell
        if dw.settle > 0:
            dw.settle -= 1
        else:
            s = inputs.get("sum")
            # read_sum(s), its common case written out (issue 14, round 7): a float64 (16, 3)
            # array is accumulated as it is; its finiteness is tested once per dwell, on the
            # accumulated sum (_end_dwell; session 17: a non-finite sample makes the dwell bad
            # as the per-PRI test did, and a bad dwell's sum is never read)
            if not (type(s) is _ndarray and s.shape == _SUM_SHAPE and s.dtype == _F64):
                s = read_sum(s)
            gate_ok = True
            mode = self.mode  # as _dwell_length()
            if mode != CONFIRMED and "gate.start" in inputs:
                gs = finite_or_none(inputs["gate.start"])
                if gs is None:
                    s = None
                else:
                    ru = self._ks[self._pri_idx] * BIN_M
                    d = (gs - (self._gate - _GATE0_M)) % ru
                    gate_ok = min(d, ru - d) <= 0.5 * BIN_M
            n_dwell = (self.dwell_conf if mode == CONFIRMED else
                       self.dwell_acq if mode == ACQUISITION else self.dwell_tent)
            if not gate_ok:
                dw.stall += 1
                if dw.stall >= self.stall_pris:
                    dw.n_seen = n_dwell
                    dw.bad = True
            else:
                dw.n_seen += 1
                if s is None:
                    dw.bad = True
                else:
                    _np_add(dw.acc, s, dw.acc)  # out positional: no keyword parsing
            if dw.n_seen >= n_dwell:
                self._end_dwell()

        mode = self.mode
        if mode == TENTATIVE and self._tent.steps > self.tent_timeout_pris:
            self._enter_acquisition(self._search.centre_true)
            mode = self.mode

        # servo bandwidth and α-β gain schedule (seed 000: "The bandwidths of the servo-loops
        # are progressively reduced up to a certain limit"; "The Radar Manager is responsible
        # for updating the Alpha-Beta coefficients"; laws in the module docstring, *Confirmed*),
        # then the common case of _step_outputs(), written out here (issue 14, round 9: no call
        # per PRI; hotpath.py documents the outputs)
        confirmed = mode == CONFIRMED
        if not confirmed:  # bandwidth: bw_start → bw_floor over bw_decay_time of confirmed
            self._bw = bw = self.bw_start
        else:
            decay = self.bw_decay_time
            conf_time = tr.conf_time
            if decay <= 0.0 or conf_time >= decay:
                self._bw = bw = self.bw_floor
            else:
                x = conf_time / decay
                self._bw = bw = self.bw_start * (self.bw_floor / self.bw_start) ** x
        # steady gains: Kalata's for the tracking index of σm (opened after a maneuver) and T
        sigma_m = (self.sigma_man_high if tr.since_maneuver <= self.maneuver_hold
                   else self.sigma_man)
        t = self._all_pris[self._pri_idx]  # the current PRI [s]
        key = (sigma_m, t)
        if key != self._gains_key:
            self._gains_key = key
            self._lambda = sigma_m * t * t / self.sigma_meas
            self._gains = kalata_gains(self._lambda)
        # SYSTEM.md: evolutive gains until the manager's steady gains take over. The Tracker
        # (filters.gains.scheduled_gains) uses max(evolutive(n), steady) per gain, so the steady
        # gains are sent throughout confirmed tracking; 0 in acquisition / tentative
        # (evolutive only, seed 000: "Alpha-Beta filters with a short time constant").
        if not confirmed:
            self._alpha = self._beta = 0.0
            return self._step_outputs()
        self._alpha, self._beta = self._gains
        tmpl = self._out_tmpl
        if tmpl is not None and not self._dwell_done and self._gains_key is self._tmpl_gains_key:
            out = tmpl.copy()  # a confirmed PRI without a dwell end (StepOutputsMixin)
            out["gate.command"] = self._gate - _GATE0_M
            out["bandwidth"] = bw
            return out
        return self._step_outputs()

    def _dwell_length(self) -> int:
        if self.mode == ACQUISITION:
            return self.dwell_acq
        if self.mode == TENTATIVE:
            return self.dwell_tent
        return self.dwell_conf

    def _end_dwell(self) -> None:
        # a NaN or ±inf sample (or an overflowing sum) among those accumulated: a bad dwell
        ok = not self._dwell.bad and _isfinite(_add_reduce(self._dwell.acc, None))
        self._dwell_done = True
        mode = self.mode
        if mode == ACQUISITION:
            self._end_acquisition_dwell(ok)
        elif mode == TENTATIVE:
            self._end_tentative_dwell(ok)
        else:
            self._end_confirmed_dwell(ok)
        if self._dwell.n_seen:  # the handler did not restart the dwell
            self._restart_dwell(settle=False)
