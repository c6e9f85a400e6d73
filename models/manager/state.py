"""State of the radar manager's state machine, grouped by concern (plain data, no logic; the
transitions are in :mod:`.machine`). Every field starts at its reset value."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..radar.conventions import N_BINS, N_DOPPLER
from .doppler_ramp import Ramp


@dataclass
class Dwell:
    """The dwell being accumulated (every mode)."""

    acc: np.ndarray = field(default_factory=lambda: np.zeros((N_BINS, N_DOPPLER)))  # Σ SUM
    n_seen: int = 0  # PRIs counted in this dwell
    bad: bool = False  # a missing/non-finite sample or a stall: the dwell counts as a miss
    settle: int = 0  # PRIs still ignored after a command change
    stall: int = 0  # PRIs without a matching gate.start


@dataclass
class Search:
    """Acquisition range search (mode 0)."""

    centre_true: float = 0.0  # true range [m] the search is centred on
    windows: list[tuple[int, int, int]] = field(default_factory=list)  # (gate bin, step, PRI)
    pos: int = 0  # index of the current window
    passes: int = 0  # completed passes over the windows (the acquisition PRI cycles)


@dataclass
class Tentative:
    """Tentative tracking (mode 1): PRI order, measurements, hypothesis windows, M of N."""

    steps: int = 0  # PRIs since tentative began (timeout)
    order: list[int] = field(default_factory=list)  # PRI indices, acquisition PRI first
    order_pos: int = 0
    meas: list[tuple[int, int]] = field(default_factory=list)  # (k, apparent bin) per PRI
    cands: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))  # true bins
    #: (centre, hyp. bin, step, range walk [bins]) of the current PRI's pass
    windows: list[tuple[int, int, int, int]] = field(default_factory=list)
    rwins: list[tuple[int, int]] = field(default_factory=list)  # range windows of this PRI
    dsteps: list[int] = field(default_factory=list)  # Doppler steps of this PRI
    walk: int = 0  # range walk of the current window [bins] (tent_range_walk)
    win_pos: int = 0
    cycles: int = 0  # passes over the windows of the current PRI
    fd_acq: float = 0.0  # folded Doppler of the acquisition detection [Hz]
    skipped: int = -1  # PRI index given up (predicted blind, tent_blind_fraction), −1 none
    notch: int = -1  # PRI index measured in the MTI notch (Doppler: interval only), −1 none
    notch_fd: float = math.nan  # its folded Doppler reading [Hz] (a value if a PRI is given up)
    #: (range, Doppler) candidates before the second PRI's measurement (its retro-skip)
    before2: tuple[np.ndarray, np.ndarray] | None = None
    weak: list[int] = field(default_factory=list)  # PRI indices measured by a weak detection
    confirming: bool = False  # range resolved: M-of-N confirmation running
    hits: int = 0
    nmiss: int = 0
    dcands: np.ndarray = field(default_factory=lambda: np.zeros(0))  # unfolded Dopplers [Hz]
    dmeas: list[tuple[float, float]] = field(default_factory=list)  # (PRF, folded Doppler) [Hz]
    doppler: float = math.nan  # resolved unfolded Doppler [Hz]
    filter_energy: np.ndarray = field(default_factory=lambda: np.zeros(N_DOPPLER))  # M-of-N hits
    bin_hits: list[int] = field(default_factory=lambda: [0, 0, 0])  # M-of-N hits, bins 6-8


@dataclass
class Track:
    """Confirmed tracking (mode 2) and the Tracker's inputs it holds."""

    conf_time: float = 0.0  # time in confirmed mode [s]
    misses: int = 0  # consecutive missed dwells
    last_range: float = math.nan  # last finite track.range [m]
    last_rate: float = math.nan  # last finite track.range_rate [m/s]
    good_range: float = math.nan  # last plausible confirmed track range [m]
    anchor_range: float = math.nan  # plausibility anchor: range [m] ...
    anchor_time: float = 0.0  # ... at this confirmed time [s]
    doppler_base: float = 0.0  # track (or tentative filter) Doppler [Hz]
    doppler_bias: float = 0.0  # discriminator correction added to the base [Hz]
    base_from_rate: bool = False  # the base follows the track range rate (after the delay)
    dither_sign: int = 1  # Doppler dither of this dwell: +Δ or −Δ (doppler_track)
    #: the dither dwells summed so far (doppler_disc_pairs): central bins 6-8 of the centre
    #: filter and the side-bin level, [+Δ: 0-2, 3; −Δ: 4-6, 7]
    disc_sum: np.ndarray = field(default_factory=lambda: np.zeros(8))
    disc_pairs: int = 0  # pairs in disc_sum
    good_doppler: float = math.nan  # undisplaced centre of the last detecting dwell [Hz]
    doppler_unf: float = math.nan  # unfolded track Doppler [Hz] (confirmed PRI switch)
    ref_doppler: float = 0.0  # the same, folded: the centre, or good_doppler while searching
    pri_switches: int = 0  # PRI switches of this confirmed track (confirm_switch_db)
    ramp: Ramp = field(default_factory=Ramp)  # Doppler ramp estimate (doppler_ramp_time)
    follow_time: float = 0.0  # conf_time of the last Doppler-centre update [s]
    seen_time: float = 0.0  # conf_time of the last dwell that detected the target [s]
    notch: bool = False  # coasting through the clutter notch (session 30, notch_coast_time)
    maneuver: bool = False
    since_maneuver: float = math.inf  # time since the maneuver flag was last set [s]
