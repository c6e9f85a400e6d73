"""Parameters of the radar manager, declared once (:class:`~axir.models.radar.params.Param`:
name, default, unit, doc, valid range; the FMU parameter variables and the validation derive
from them). Cross-parameter checks: :func:`check_params`.
"""

from __future__ import annotations

from typing import Any

from ..radar.conventions import (
    BIN_M,
    DEFAULT_DESIGNATION_RANGE,
    DEFAULT_MAX_RANGE,
    DEFAULT_MAX_SPEED,
    DEFAULT_WAVELENGTH,
)
from ..radar.params import Param
from .ambiguity import DEFAULT_PRI_BINS, ghost_free_span_bins, range_to_bin
from .pri_choice import DEFAULT_TRACK_PRI_BINS, parse_track_pri_bins

#: Parameters of :class:`~axir.models.manager.machine.RadarManager`.
PARAMS: tuple[Param, ...] = (
    Param("pri1_bins", DEFAULT_PRI_BINS[0], "1",
          "PRI 1 in 0.5 µs range-bin durations (PRI = k·BIN_S, Ru = k·75 m)", 20, 20000),
    Param("pri2_bins", DEFAULT_PRI_BINS[1], "1", "PRI 2 in range-bin durations", 20, 20000),
    Param("pri3_bins", DEFAULT_PRI_BINS[2], "1", "PRI 3 in range-bin durations", 20, 20000),
    Param("acq_pri_index", 1, "", "PRI (1..3) used in acquisition", choices=(1, 2, 3)),
    # designer's choice (issue 11): PRI staggering over acquisition passes, so a target
    # folded into the clutter filter at one PRF is clear at the next
    Param("acq_pri_cycle", True, "",
          "acquisition cycles the three PRIs, one per pass over the search windows "
          "(acq_pri_index first); false: acq_pri_index only"),
    # designer's choice (issue 11, docs/clutter.md): a radial speed folded into the MTI notch
    # at the pass' PRI (> 6 dB loss for 24 % of the speeds at PRI 1, 3.7 % at all three)
    # would wait a whole pass (≈ 0.5 s) for the next PRI; the window on the designation is
    # searched at the three PRIs in a row (1: the pass grows from 9 to 11 windows)
    Param("acq_all_pri_windows", 1, "1",
          "acquisition: the innermost search windows (centre first) also searched at the two "
          "other PRIs right after the pass' PRI; 0: one PRI per pass", 0, 1000),
    Param("confirm_pri_index", 0, "",
          "PRI kept in confirmed tracking (0: largest eclipse margin, or the least predicted "
          "loss: confirm_max_loss_db)", choices=(0, 1, 2, 3)),
    # designer's choice (issue 11, low11, docs/clutter.md; seed 000: "waveform (DCP, PRI) are
    # continuously optimized"): the automatic PRI of M of N / confirmed tracking avoids a PRI
    # where the resolved Doppler predicts a canceller loss above 3 dB (half power) when another
    # PRI predicts less (models/manager/pri_choice.py)
    Param("confirm_max_loss_db", 3.0, "dB",
          "M of N / confirmed tracking: when the largest-eclipse-margin PRI's predicted "
          "canceller loss at the resolved Doppler exceeds this, the PRI of least predicted loss "
          "is kept instead; 0: eclipse margin only", 0.0, 100.0),
    Param("confirm_loss_mti_order", 1, "1",
          "order of the MTI canceller assumed by the predicted loss and by the thermal levels "
          "of residue_share_looks (the generator's mti; 0: no prediction, eclipse margin only, "
          "and no canceller-shaped thermal levels)", 0, 4),
    # designer's choice (issue 11, branch env14, models/manager/pri_choice.py "In confirmed
    # tracking"; seed 000: "waveform (DCP, PRI) are continuously optimized"): a target in a
    # 5-7 g turn ramps its Doppler by 2-3.4 kHz/s and walked into the clutter line of the kept
    # PRI within 1-1.5 s (three random engagements dropped); 3 dB: half the power, and no
    # switching back and forth between two PRIs of nearly equal loss
    Param("confirm_switch_db", 3.0, "dB",
          "confirmed: when the kept PRI's predicted canceller loss at the tracked Doppler "
          "exceeds confirm_max_loss_db, tracking moves to the PRI of least predicted loss if "
          "it is at least this many dB smaller (eclipse margin ≥ N_BINS/2); 0: one PRI "
          "throughout", 0.0, 100.0),
    # designer's choice (session 10): the switch trusts the tracked unfolded Doppler only
    # while it agrees with the track's range rate (−2ṙ/λ); a target in the clutter band (the
    # seed-001 ship, 157 Hz) otherwise switched 41 times in 20 s on a wandering unfolded
    # Doppler and lost half of its DDRE detections. 3 kHz ≈ 48 m/s at X band: above the
    # α-β range-rate lag of a 7 g turn (20-30 m/s, docs/envelope.md), below one PRF (≈ 10 kHz)
    Param("confirm_switch_rate_tol", 3000.0, "Hz",
          "confirmed PRI switch only while |tracked unfolded Doppler − (−2·track.range_rate/λ)| "
          "≤ this (an unfolded Doppler an ambiguity off the range rate does not move the PRI); "
          "0: no check", 0.0, 1e6),
    # designer's choice (session 19): the Tracker sets a young confirmed track's range rate
    # from doppler.range_rate (Tracker.doppler_rate_tol); the check above then compares the
    # unfolded Doppler with itself, and an alias resolved at the confirmation moved the PRI
    # 7 ms after it and lost the target (10 km, +140 m/s, 2°, designation 1.5°/1.5° off).
    # 0.1 s: ≈ 1 000 readings, where the velocity prior's gain is the seed's (docs/filters.md)
    Param("confirm_switch_delay", 0.1, "s",
          "no confirmed PRI switch before the track has been confirmed this long (the "
          "Tracker's range rate of a young track is the manager's own Doppler, not a check "
          "of it); 0: from the first confirmed dwell", 0.0, 3600.0),
    # designer's choice (issue 11, branch env14, models/manager/doppler_track.py
    # _blind_coast): the default PRIs share blind bands (every PRI > 3 dB of canceller loss,
    # e.g. 8.3-10.5 kHz); a 5-7 g turn crosses that one in 0.6-1.1 s with the Doppler ramp.
    # OFF by default: 1 s held the 11.1 km / 2.1° / 6.2 g random cell, but at 2.5° the
    # coasting tracks' elevation walked onto the clutter (3 false confirmations in 6 runs of
    # 16 km / 1 m² / 5 g, none with 0; docs/clutter.md "A turning target's Doppler")
    # designer's choice (issue 11, session 30; docs/clutter.md "Through the clutter notch"):
    # a target whose radial speed passes through 0 (every crossing target at its closest
    # point, a turn through the beam) is suppressed by the canceller at every PRI for
    # 10 m/s / a_r (1.6 s at 10 km / 250 m/s across); it was dropped and re-acquired
    Param("notch_coast_time", 2.0, "s",
          "confirmed: a track at miss_limit is kept while the Tracker's range rate is within "
          "1.5 × clutter_notch_speed of 0, once confirmed for 0.5 s and for at most this long "
          "after its last detection; the Doppler is searched around the range rate's (made "
          "for the Tracker's notch coast, notch_coast_speed, but independent of it: the "
          "manager sees neither the elevation nor the Tracker's state); 0: no coast",
          0.0, 100.0),
    Param("blind_coast_time", 0.0, "s",
          "confirmed: a track at miss_limit is kept while its Doppler, predicted along the "
          "ramp, is in a band blind at every PRI (predicted loss > confirm_max_loss_db) and "
          "leaves it within this time of the last detection; 0: no coast", 0.0, 100.0),
    # designer's choice (issue 11, session 11, branch env15; models/manager/pri_choice.py
    # "Confirmed-tracking PRIs"; seed 000: "waveform (DCP, PRI) are continuously optimized"
    # while the track is maintained): the three acquisition PRIs share blind bands (8.3-10.5
    # kHz, 18.3-19.4 kHz, …) where a turning target was dropped; with 157 or 128 bins added no
    # band over ±1500 m/s predicts more than 3 dB at every PRI (outside the clutter band)
    Param("track_pri_bins", DEFAULT_TRACK_PRI_BINS, "",
          "confirmed tracking only: further PRIs [range-bin durations, comma-separated] the "
          "confirmed PRI switch (confirm_switch_db) may move to; never used in acquisition, "
          "tentative or M of N; empty: the three PRIs only"),
    # designer's choice (session 11, pri_choice.py "Return to the acquisition PRIs"): the step
    # is the PRI, a tracking PRI costs 1.34-1.65× the steps; the default scenario's turn moved
    # to 128 bins at 21.4 s and stayed there (+34 % steps over 40 s) without it
    Param("track_pri_return", True, "",
          "confirmed: a track on a track_pri_bins PRI returns to the acquisition PRI of least "
          "predicted loss once that loss is ≤ confirm_max_loss_db − confirm_switch_db, and a "
          "switch goes to such an acquisition PRI rather than a tracking PRI"),
    Param("max_range", DEFAULT_MAX_RANGE, "m", "largest true range resolved", 0.0, 1.0e6,
          low_open=True),  # 1000 km: beyond the radar horizon of any X-band target
    Param("tol_bins", 1, "1", "accepted apparent-range error per PRI [bins]", 0, 5),
    Param("designation_range", DEFAULT_DESIGNATION_RANGE, "m",
          "operator-designated true range", 0.0, 1.0e6),
    Param("search_extent", 3_000.0, "m",
          "half-width of the acquisition range search (≥ Ru/2: whole Ru)", 0.0, 1.0e6),
    # designer's choice (issue 11, the seed is silent): a resolved range farther than this
    # from the designated (or last track) range is not the designated target; ≥ search_extent
    # plus a 2 km margin for the target's motion during the search
    Param("designation_window", 5_000.0, "m",
          "half-width of the true-range window around the designated / last track range in "
          "which range hypotheses are visited and a resolved range is accepted", 0.0, 1.0e6,
          low_open=True),
    Param("max_speed", DEFAULT_MAX_SPEED, "m/s",
          "physical speed bound of a confirmed track (its range change from an anchor and, "
          "once doppler_track_delay old, |track.range_rate|): beyond it the track is dropped "
          "(re-acquisition around the last plausible range); also bounds the unfolded "
          "Doppler candidates", 0.0, 1.0e5,
          low_open=True),
    Param("search_step_bins", 12, "1", "gate step between search windows [bins]", 1, 16),
    Param("dwell_acq", 16, "1", "PRIs accumulated per acquisition dwell", 1, 4096),
    Param("dwell_tent", 16, "1", "PRIs accumulated per tentative dwell", 1, 4096),
    Param("dwell_conf", 16, "1", "PRIs accumulated per confirmed dwell", 1, 4096),
    Param("latency_pris", 3, "1",
          "loop latency manager → tracker → generator → tracker → manager [PRIs]", 0, 1000),
    Param("settle_db", 40.0, "dB",
          "Doppler-filter transient decay waited for after a command change", 0.0, 200.0),
    Param("stall_pris", 64, "1",
          "PRIs a dwell waits for a matching gate.start before it counts as a miss", 1,
          10**6),  # 100 s at 100 µs
    Param("looks_per_pri", 4, "1",
          "independent Rayleigh looks per SUM cell per PRI (4 beams)", 1, 64),
    Param("doppler_pole", 0.9, "1",
          "pole radius of the generator's IIR Doppler filters (TargetGenerator.pole)",
          0.0, 1.0, high_open=True),
    Param("pfa_acq", 1e-5, "1", "design false-alarm probability per cell per dwell (Th1)",
          1e-9, 0.1),
    Param("pfa_track", 1e-4, "1", "design false-alarm probability per cell per dwell (Th2)",
          1e-9, 0.1),
    Param("adaptive_looks", True, "",
          "estimate each Doppler filter's effective looks from the range-cell spread "
          "(clutter-aware thresholds); false: doppler_pole model only"),
    # designer's choice (issue 11, docs/clutter.md): the MTI canceller's clutter residue is
    # white but common to the beams; a filter whose acquisition level is far above the thermal
    # one gets the one-look-per-PRI law. 1.6: above √2, the canceller's largest thermal
    # amplitude gain (2 sin² πν ≤ 2 in power), with a margin for the level's estimation noise
    Param("residue_level_ratio", 1.6, "1",
          "a Doppler filter whose acquisition noise level exceeds this multiple of the "
          "thermal level is clutter-residue-dominated (threshold: one look per PRI)",
          1.0, 1.0e6, low_open=True),
    # designer's choice (issue 11, session 21, models/manager/residue.py): a filter whose
    # level exceeds its own thermal level (shaped by the canceller when the levels say it is
    # on) holds a beam-common residue share f; its threshold is at least the exact law at the
    # effective looks L/(1 + (L − 1)·κ(f)) (the switch above covers level > 1.6 × thermal only)
    Param("residue_share_looks", True, "",
          "thresholds of a Doppler filter whose acquisition level exceeds its thermal level "
          "use the effective looks of its beam-common clutter share (with adaptive_looks)"),
    Param("noise_power", 1.0, "1",
          "receiver thermal noise power per beam and pulse in SUM units squared "
          "(TargetGenerator: 1; the calibrated thermal level of residue_level_ratio)",
          0.0, 1.0e12, low_open=True),
    Param("noise_avg_dwells", 8.0, "1",
          "averaging length of the acquisition noise level [dwells]", 1.0, 1.0e6),
    # designer's choice (session 21, docs/clutter.md "A level that follows the front end"): a
    # fast attack. 1.25 is ≈ 5 σ of a 16-cell median of the thermal acquisition cells (≈ 5 %)
    Param("noise_attack_ratio", 1.25, "1",
          "a Doppler position class whose acquisition dwell median exceeds this multiple of "
          "its noise level restarts the level from that median (0: averaging only)",
          0.0, 1.0e6),
    Param("tent_window_cycles", 2, "1",
          "passes over a PRI's hypothesis windows before tentative fails", 1, 100),
    Param("tent_eclipse_last", True, "",
          "tentative: a PRI at which a range candidate of the attempt folds within "
          "N_BINS/2 bins of 0 or Ru (the gate straddles the transmit pulse) is measured "
          "last; False: the notch rule's order only"),
    Param("tent_timeout_pris", 4000, "1", "tentative-mode time limit [PRIs]", 1, 10**8),
    Param("confirm_m", 3, "1", "detections needed (M of N) to confirm", 1, 100),
    Param("confirm_n", 4, "1", "dwells (N) of the M-of-N confirmation", 1, 100),
    # designer's choice (issue 11, session 26; the seed is silent): the confirmed gate is
    # centred on the range bin that held the M-of-N hits, as the Doppler centre is moved to
    # the filter that held them (a strong target 1-1.5 bins from the resolved bin's centre
    # was confirmed in bin 6 or 8; the Tracker's hand-over test, handover_range_tolerance,
    # compares its track with this centre)
    Param("confirm_range_recentre", True, "",
          "at confirmation the gate centre moves one bin to the side bin (6 or 8) that held "
          "more of the M-of-N hits than the centre bin and than the other side bin"),
    # designer's choice (issue 11, session 25; the seed is silent): a track is dropped after
    # N missed dwells in a row, which noise alone makes with (1 − Pd)^N per dwell; over the
    # ≈ 1 100 confirmed dwells of a 3 s engagement N = 5 holds a target at Pd 0.9 per dwell,
    # N = 10 one at Pd 0.75 (a target at the detectability criterion with the confirmed
    # dwell's dither, Doppler lag and straddle losses: random draws 3 and 8, 2.3-3.3 g turns
    # at 13-72°, each dropped by 5 misses while its range, angles and Doppler were right);
    # 10 dwells ≈ 26 ms
    Param("miss_limit", 10, "1", "consecutive missed dwells that drop a confirmed track", 1,
          10**6),
    # servo bandwidths: the Pedestal accepts [0.01, 100] Hz (models/pedestal.py BW_MIN/BW_MAX)
    Param("bw_start", 5.0, "Hz", "servo bandwidth in acquisition / tentative", 0.01, 100.0),
    Param("bw_floor", 1.0, "Hz", "servo bandwidth limit in confirmed", 0.01, 100.0),
    Param("bw_decay_time", 2.0, "s", "time to reduce the bandwidth to its floor", 0.0, 3600.0),
    # assumptions (issue 11, session 6; docs/filters.md): σ_n = the range noise measured in
    # the closed loop (0.8-0.92 m, reports/out/seed000.md), σ_m = a 3 g-class target (30 m/s²).
    # Before: 15 m and 5 m/s², a tracking index 90× smaller whose steady gains (α ≈ 1e-4, a
    # memory of seconds) kept the hand-over transient of far tracks and lagged the 3 g turn
    Param("sigma_meas", 1.0, "m", "measurement noise σ_n of the tracking index", 0.0, 1.0e5,
          low_open=True),
    Param("sigma_man", 30.0, "m/s2", "maneuver noise σ_m (non-maneuvering)", 0.0, 1.0e4,
          low_open=True),  # 1000 g
    # assumption: ≈ 3× the 30 m/s² of a 3 g turn; measured: holds the default 3 g turn
    # in the closed loop (range lag ≤ 25 m) where 20 m/s² lost the gate
    Param("sigma_man_high", 100.0, "m/s2", "maneuver noise σ_m while maneuvering", 0.0, 1.0e4,
          low_open=True),
    Param("maneuver_hold", 1.0, "s", "time the gains stay open after a maneuver", 0.0, 3600.0),
    Param("wavelength", DEFAULT_WAVELENGTH, "m", "carrier wavelength λ", 1e-3, 10.0),
    Param("doppler_search_centre", 0.0, "Hz",
          "Doppler centre in acquisition / tentative (filters tile the folded band)",
          -1.0e7, 1.0e7),  # 2·v/λ for v ≤ 10 km/s, λ ≥ 2 mm
    Param("doppler_spacing_fraction", 1.0 / 3.0, "1",
          "Doppler filter spacing as a fraction of the PRF (generator setting)",
          0.0, 1.0, low_open=True),
    # designer's choice (issue 11, docs/doppler_coverage.md): Doppler steps per dwell
    Param("doppler_max_loss_db", 4.0, "dB",
          "worst-case Doppler loss against a filter-centred target: the filter bank is "
          "stepped over dwells by PRF/(3·n), n the smallest count meeting it (9 at pole 0.9)",
          0.0, 40.0, low_open=True),
    # designer's choice: ≥ the half grid step of the Doppler steps (0.0185) plus the
    # discriminator's error; larger lets aliases one PRF apart pass (the PRFs differ by 5 %):
    # 0.05 would reject ±150 m/s as clutter ghosts (2.1 % of the band instead of 1.2 %)
    Param("doppler_tol_fraction", 0.03, "1",
          "Doppler coherence tolerance of tentative tracking, fraction of the PRF (folded "
          "Doppler measured at each PRI vs the unfolded candidates)", 0.0, 0.5, low_open=True),
    # designer's choice (issue 11, docs/clutter.md; seed 000: "at least 3 different PRIs"):
    # a target near a blind speed of one PRI (folded into the MTI notch / clutter filter there)
    # cannot be detected at that PRI; resolved on the two others only if their Doppler
    # predicts it blind there (10 %: ≥ 7 dB of two-pulse MTI loss)
    Param("tent_blind_fraction", 0.1, "1",
          "tentative: a PRI where no coherent detection was found is given up when the "
          "Doppler resolved on the two others folds within this fraction of its PRF of 0 Hz "
          "(blind there); 0: all three PRIs required", 0.0, 0.5),
    # option (issue 11, docs/clutter.md), off by default: a weak target between two filter
    # positions can be detected in acquisition in the wrong filter; 1/6 (a filter's
    # half-spacing) searches the first PRI's steps within it, but each acquisition false
    # alarm then costs up to 18 tentative dwells (time in acquisition 0.57 instead of > 0.8 at
    # Pfa 1e-3, tests/test_closed_loop_models.py) and it did not rescue the 42 km case
    Param("acq_doppler_tol_fraction", 0.0, "1",
          "tentative: Doppler tolerance of the acquisition detection, fraction of the PRF "
          "(the first PRI's Doppler steps within it are searched, nearest first); 0: the "
          "coherence tolerance doppler_tol_fraction", 0.0, 0.5),
    # option (issue 11, session 18; docs/clutter.md "The Doppler reading's two amplitude
    # models"), 'excess' by default: one of the three filters always holds the clutter,
    # beside the target's. The excess of mean |target + clutter| over a filter's level
    # under-reads a share comparable to the level (a 44 dB target at 4.9 km, −914 m/s read
    # −3712 Hz for −2641: every tentative attempt looked for it at the wrong Doppler, lock
    # 1.43 s); inverted for the Rice bias (doppler.rician_amplitude) the share is unbiased,
    # but a side filter holding noise a little above its level then reads as a share of the
    # target (30 km, 1°, −642.86 m/s: 2028 Hz for 2425, the excess 2292). 'both' fixed the
    # first and every verdict of the design stayed, but the default scenario locks at
    # 0.078 s instead of 0.037 s (a wider Doppler hypothesis searched in another order).
    Param("doppler_read", "excess", "",
          "acquisition and tentative: the three-filter Doppler reading fits the filters' "
          "target amplitudes as 'excess' (mean amplitude less the filter's level; the "
          "default), 'rician' (inverted for the Rice bias of the level) or 'both' (the "
          "midpoint of the two readings, the tolerance widened by half their difference)",
          choices=("excess", "rician", "both")),
    Param("clutter_notch_speed", 5.0, "m/s",
          "tentative: a resolution is rejected as ground clutter (or a blind speed) when its "
          "Doppler is within this radial speed of 0, as notch_reject says: the resolved "
          "Doppler or a candidate fitting nearly as well (notch_fit_ratio), or any candidate",
          0.0, 1.0e3),
    # designer's choice (issue 11, session 27, docs/clutter.md "The notch test on the resolved
    # Doppler"; the seed is silent): session 4 rejected a resolution when ANY unfolded
    # candidate kept by the ±doppler_tol_fraction·PRF tolerances reached the notch, which made
    # the notch ≈ ±9.8 m/s wide instead of ±5 m/s (traced: 22 km / −7.5 m/s / 20° / 1.5 m²,
    # readings 368-389 Hz at the three PRIs, candidates 120-650 Hz, never confirmed). No
    # target-free clutter attempt of the design reaches the resolution at all.
    Param("notch_reject", "resolved", "",
          "tentative: the clutter notch test is made on the resolved (least-squares) Doppler "
          "and notch_fit_ratio ('resolved') or on every Doppler candidate the tolerances keep "
          "('any', session 4)", choices=("resolved", "any")),
    # designer's choice (session 27, the same section): readings biased by the MTI canceller
    # (a slow target at 3°) resolved a wrong alias in the band blind at all three PRIs
    # (9.7 kHz) that fitted them hardly better than a candidate in the notch (RMS residual
    # 244 against 266 Hz); the right resolutions of the sweep fitted ≥ 1.9× better
    Param("notch_fit_ratio", 1.5, "1",
          "tentative, notch_reject 'resolved': a candidate in the clutter notch whose RMS "
          "residual over the readings is within this factor of the resolved Doppler's rejects "
          "the resolution as well (1: only an equally good one)", 1.0, 1.0e3),
    # designer's choice (issue 11, docs/clutter.md "Tentative in the notch"; the seed is
    # silent): a detection folded into the MTI notch has ≥ 7 dB of canceller loss, its
    # discriminator reading is unreliable (traced: a −0.042·PRF target read outside the
    # 0.03·PRF tolerance, the wrong alias resolved); it constrains the Doppler only to the
    # notch (tent_blind_fraction + doppler_tol_fraction) and counts as the one blind PRI
    Param("tent_notch_interval", True, "",
          "tentative: a weak detection whose folded Doppler is within tent_blind_fraction of 0 Hz "
          "keeps the Doppler candidates folding into the notch (not its reading), as the one "
          "blind PRI; a PRI where most candidates are blind is measured last; false: the "
          "measured Doppler at every PRI, PRIs in index order after the acquisition PRI"),
    # designer's choice (issue 11, docs/clutter.md "Tentative in the notch"; the seed is
    # silent): the notch rules apply to weak detections only. Excess (A − N)/N of the detected
    # cell over its filter's noise level N, traced: false alarms and the target in the MTI
    # notch 0.8-1.8 (readings 0.11-0.29·PRF off), the target clear of the notch 2.8-6.8 at
    # 25 km, in the notch at 14 km 2.6-4.5 (≤ 0.04·PRF off), the default scenario 4.1-13.7
    # (MTI off, precise readings). 2 ≈ 8.5 dB of amplitude SNR per look
    Param("tent_weak_excess", 2.0, "1",
          "tentative: a detection whose excess over its filter's noise level, (A − N)/N, is "
          "below this is weak: only a weak reading in the notch is an interval, only a weak "
          "second PRI is retro-skipped, only a weak or unmeasured PRI is blind for M of N; "
          "0: no reading is weak", 0.0, 1.0e6),
    # designer's choice (issue 11, models/manager/doppler_peak.py, docs/clutter.md "Late locks
    # at 30-42 km"): seed 000's "cell providing the largest number" over the Doppler steps; a
    # weak detection found on its filter's skirt was read 0.04-0.09·PRF off (tolerance 0.03).
    # 4: the fit brackets a peak up to ≈ 3 positions away; excess 4: below the default
    # scenario's detections (4.1-13.7, their path unchanged)
    Param("doppler_peak_dwells", 4, "1",
          "acquisition / tentative: extra dwells of the Doppler peak search after a weak "
          "detection (grid positions of the Doppler steps around the detecting filter, the "
          "reading fitted to the resonator profile of their responses); 0: the detecting "
          "dwell's reading",
          0, 100),
    Param("doppler_peak_excess", 4.0, "1",
          "acquisition / tentative: a detection whose excess over its filter's noise level, "
          "(A − N)/N, is below this gets the Doppler peak search (doppler_peak_dwells)",
          0.0, 1.0e6),
    # designer's choice (session 9, docs/clutter.md "Strong detection on a skirt"): random
    # engagement 11.5 km / +347 m/s / 2.6 m² (34 dB): its 2nd tentative PRI was detected
    # 0.07·PRF off its filter (excess 5.1, sides 0.3-0.7 × noise), read 950 Hz off, and
    # tentative failed 4 times (lock 1.49 s). At 1 the full design kept 0 false
    # confirmations but plane 20 km +322.71 m/s s1 locked at 1.016 s (0.70 s without;
    # tests/test_tracker_far.py: a side at 1.03 × its noise read 316 Hz off), at 2 the default
    # scenario locked at 0.058 s (0.037 s). Session 11: 1.5, on by default — a second random
    # cell of the class (draw 4: 8.5 km, +335 m/s, 1.13 → 0.10 s), the design cell 0.73 s,
    # the default scenario 0.0369 s (docs/clutter.md, docs/envelope.md "Session 11")
    Param("doppler_peak_side", 1.5, "1",
          "tentative, 2nd and 3rd PRI (and, with acq_peak_side, an acquisition detection in "
          "the clutter filter): a detection above doppler_peak_excess still gets the "
          "Doppler peak search when neither side filter's excess (A − N)/N reaches this: the "
          "three-filter discriminator reads the offset from the side filters (PRF/3 away, "
          "≈ −24 dB for a centred target) and reads nothing when they hold only noise; 0: "
          "never (docs/clutter.md)", 0.0, 1.0e6),
    # designer's choice (issue 11, session 28, docs/clutter.md "The side test at the acquisition
    # detection"): at 3° a slow strong target was detected at the 0 Hz step 408 Hz off the
    # centre filter, its side filters (±PRF/3) holding only noise; the acquisition and the first
    # tentative PRI both read the centre (65 and 2 Hz), a wrong alias was resolved
    Param("acq_peak_side", True, "",
          "acquisition: doppler_peak_side's test is made at a detection in the clutter filter "
          "(the filter centred on 0 Hz) too: a strong one whose side filters hold only noise "
          "gets the Doppler peak search; false: only at the 2nd and 3rd tentative PRI "
          "(sessions 11-27)"),
    # designer's choice (issue 11, models/manager/range_walk.py, docs/clutter.md "Range walk
    # in tentative"): a 0.25 s attempt on an 800 m/s target walked it 2.6 bins out of the
    # hypothesis window (Th2 on bins 6-8)
    Param("tent_range_walk", True, "",
          "tentative: each hypothesis window moves by the range walk of its Doppler step's "
          "candidates (ṙ = −λ·f/2) since the attempt began, and a detection keeps only the "
          "Doppler candidates of its window's walk; false: fixed windows"),
    Param("doppler_track_delay", 0.5, "s",
          "confirmed time before the Doppler centre follows the track range rate", 0.0,
          3600.0),
    # designer's choice (issue 11, docs/clutter.md "Confirmed tracking at 20-42 km"): a pair's
    # offset at a filtered SNR of 17-24 dB scatters by ≈ ±100 Hz (amplitude noise and target
    # fluctuation between the two dwells); gain 1 random-walked the centre 100-250 Hz off
    # the target (−5 dB) and faded dwells dropped the track; 0.5 halves that scatter's
    # variance (σ²·g/(2 − g)) for a time constant of ≈ 2 pairs (≈ 10 ms)
    Param("doppler_loop_gain", 0.5, "1",
          "confirmed: fraction of the discriminator's Doppler offset corrected per dwell "
          "(0: centre from the track range rate only)", 0.0, 1.0),
    # designer's choice (issue 11, confirmed Doppler divergence −66 → −1776 Hz in clutter):
    # the bias exists for the α-β range-rate lag (≈ 30 m/s in the default 3 g turn)
    Param("doppler_bias_max_speed", 40.0, "m/s",
          "confirmed, three-filter comparison: bound of the discriminator's Doppler bias, "
          "as a radial speed (|bias| ≤ 2·v/λ; the dither loop is not bounded by the track "
          "range rate)", 0.0, 1.0e3),
    Param("doppler_bias_reset_misses", 2, "1",
          "confirmed: consecutive missed dwells after which the bias is dropped and the "
          "centre returns to the track range rate's Doppler (with the dither: to the last "
          "detecting dwell's Doppler, then searched around it)", 1, 10**6),
    # designer's choice (issue 11, models/manager/doppler_track.py): the three-filter
    # comparison is blind within ±0.05·PRF of the centre; 0.006·PRF costs 0.5 dB
    Param("doppler_dither_fraction", 0.006, "1",
          "confirmed: the centre filter is displaced by ±this fraction of the PRF on "
          "alternate dwells, the amplitude ratio measures the Doppler offset; 0: three-filter "
          "amplitude comparison", 0.0, 0.1),
    Param("doppler_dither_settle", 10, "1",
          "confirmed, with the dither: PRIs ignored after each displacement (the Doppler "
          "filter's transient, time constant 1/(1 − doppler_pole) PRIs)", 0, 1000),
    Param("doppler_disc_snr", 3.0, "1",
          "confirmed: discriminator used only when the target's excess amplitude in its "
          "best filter exceeds this multiple of that filter's noise level", 0.0, 1.0e6),
    # designer's choice (issue 11, session 25, models/manager/doppler_track.py
    # "Weak targets"): a 3.35 g turn at 52.7 km / 73° (random draw 10) read 1-3 × the noise
    # per dwell, no pair passed doppler_disc_snr, the centre stayed at the tentative Doppler
    # while the turn moved the target 900 Hz, and the track was dropped
    Param("doppler_disc_pairs", 8, "1",
          "confirmed, with the dither: the dither dwells of up to this many pairs are summed "
          "until both signs' excess passes doppler_disc_snr/√(pairs) × their noise level "
          "(1: each pair alone)", 1, 1000),
    Param("doppler_disc_together", True, "",
          "confirmed, with the dither: the pair sums pass when both signs' excess together "
          "passes the threshold (a target far off the centre leaves one sign at the noise; "
          "the ratio then reads the end of the table, toward the other sign); False: each "
          "sign must pass"),
    # designer's choice (issue 11, models/manager/doppler.py: rician_amplitude): the dither
    # pair's amplitudes are freed of the Rice bias, which made the MTI's coloured noise
    # read as a Doppler offset toward the notch (30 km, 1°, +428.57 m/s drifted and dropped)
    Param("doppler_disc_rician", True, "",
          "confirmed, with the dither: the amplitude ratio uses each central bin's mean "
          "amplitude inverted for the Rice bias of the noise (False: excess over the side-bin "
          "level)"),
    # designer's choice (issue 11, branch env14, models/manager/doppler_ramp.py): a 5-7 g
    # turn ramps the Doppler by 2-3.4 kHz/s; the type-1 dither loop lagged it by 100-450 Hz
    # (up to 3 filter half-widths) and stopped when the pairs lost their clear target.
    # τ = 0.15 s: ≈ 25 pairs, slope noise ≈ 60-150 Hz/s; 100 m/s²: ≈ 10 g. OFF by default:
    # at 0.15 s it cut the 37 km / 5.1 g random cell's RMS range 6.95 → 4.79 m, but on weak
    # non-turning 42 km / 5° plane cells spurious slopes passed the 3σ test (seed 1:
    # −571.43 m/s RMS 6.15 → 11.61 m, +71.43 6.05 → 10.00 m, +214.29 m/s one drop)
    Param("doppler_ramp_time", 0.0, "s",
          "confirmed, with the dither: time constant of the weighted least-squares slope of "
          "the pairs' measured Doppler (the Doppler ramp −2·a_r/λ); the centre is predicted "
          "along it at every dwell; 0: no prediction", 0.0, 100.0),
    Param("doppler_ramp_max_acc", 100.0, "m/s2",
          "confirmed: bound of the Doppler ramp as a radial acceleration (|ramp| ≤ "
          "2·this/λ)", 0.0, 1.0e4),
    Param("doppler_disc_clutter", 2.0, "1",
          "confirmed: the discriminator is not used while a Doppler filter's side-bin "
          "level exceeds this multiple of the quietest filter's (clutter)", 1.0, 1.0e6),
    # designer's choice (issue 11, session 25): a weak track misses two dwells in a row on
    # noise alone; the search then left its centre (random draw 8, 17.4 km / 72° / 2.3 g:
    # 66 Hz off, 0.4 half-width, then −s, +s, −2s and the drop)
    Param("doppler_search_from_centre", True, "",
          "confirmed, with the dither: the search after doppler_bias_reset_misses missed "
          "dwells begins with one dwell at the last detecting dwell's undisplaced centre "
          "(0, −s, +s, −2s, +2s, …; False: −s, +s, −2s, +2s, …)"),
    # designer's choice (issue 11, round 4, models/manager/doppler_track.py): a tentative
    # Doppler 168 Hz (one half-width) off missed 4 dwells in a row at 30 km, +1000 m/s and
    # the track was dropped with its range right to 10 m; one half-width per step keeps a
    # target within 1.5 half-widths of the last detecting centre inside −1 dB of a position
    Param("doppler_search_halfwidths", 1.0, "1",
          "confirmed, with the dither: after doppler_bias_reset_misses missed dwells the "
          "centre is searched at (0 with doppler_search_from_centre,) −s, +s, −2s, +2s … "
          "(one position per missed dwell) around "
          "the Doppler of the last detecting dwell, s = this many 3 dB half-widths of the "
          "Doppler filter; 0: held there", 0.0, 100.0),
)


def check_params(m: Any) -> None:
    """Cross-parameter checks of a RadarManager ``m`` (ValueError naming the parameters):
    three different PRIs, valid ``track_pri_bins``, bw_floor ≤ bw_start, confirm_m ≤
    confirm_n, sigma_man_high ≥ sigma_man, designation_range ≤ max_range, and a PRI set
    unambiguous up to max_range."""
    ks = (m.pri1_bins, m.pri2_bins, m.pri3_bins)
    if len(set(ks)) != 3:
        raise ValueError(f"RadarManager: pri1_bins, pri2_bins, pri3_bins must differ: {ks}")
    parse_track_pri_bins(m.track_pri_bins, ks)
    if m.bw_floor > m.bw_start:
        raise ValueError(
            f"RadarManager: bw_floor = {m.bw_floor} Hz exceeds bw_start = {m.bw_start} Hz"
        )
    if m.confirm_m > m.confirm_n:
        raise ValueError(
            f"RadarManager: confirm_m = {m.confirm_m} exceeds confirm_n = {m.confirm_n}"
        )
    if m.sigma_man_high < m.sigma_man:
        raise ValueError("RadarManager: sigma_man_high must be ≥ sigma_man")
    if m.designation_range > m.max_range:
        raise ValueError(
            f"RadarManager: designation_range = {m.designation_range} m exceeds "
            f"max_range = {m.max_range} m"
        )
    max_bin = range_to_bin(m.max_range)
    span = ghost_free_span_bins(ks, m.tol_bins, limit=max_bin + 2 * m.tol_bins + 2)
    if span <= max_bin + 2 * m.tol_bins:
        raise ValueError(
            f"RadarManager: the PRI set {ks} with tol_bins = {m.tol_bins} is ambiguous "
            f"beyond {span * BIN_M:.0f} m < max_range = {m.max_range} m"
        )
