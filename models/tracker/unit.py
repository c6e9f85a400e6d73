"""AXIR_B digital tracker unit (seed 000), with the seed-001 DDRE and the seed-002 filters.

One :meth:`Tracker.step` per communication step. Inputs and outputs: :mod:`.ports` (SYSTEM.md
public names; the FMU variables are derived from them). The unit declares the parameters and
dispatches on ``input_mode``:

- ``"beams"`` (default): the seed-000 tracker on the monopulse beams, pedestal angles, radar
  mode and the manager's gains and gate — deviations, Cartesian filtering, pedestal rate
  commands, range gate, maneuver test, optional DDRE (:mod:`.beams`);
- ``"measurement"``: the chosen filters on ``meas.range/az/el`` of the TargetGenerator's
  measurement fidelity (seed-002 experiments, :mod:`.measurement`).

Filters (docs/filters.md): one per-axis filter (:mod:`axir.models.filters`) chosen by
``filter_x/y/z`` (Cartesian axes, beams mode) or ``filter_range/az/el`` (spherical axes,
measurement mode): "alphabeta" (default, seed 000), "kalman", "svd", "svd_reduced", "vd" (seed
002), "imm" (comparison). With α-β on the three Cartesian axes in beams mode (the default) the
tracker is exactly the seed-000 tracker, maneuver test included (3-D NIS, :mod:`.maneuver`);
otherwise ``maneuver`` is true when any axis's fading-memory detector (seed 002 eqs. 11-15)
declares a maneuver, and ``maneuver.statistic``/``maneuver.threshold`` are L(k) and I1 of the
axis with the largest L/I1.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

import numpy as np

from ..filters.base import FilterConfig
from ..filters.registry import EXTRA_PACKAGES, FILTER_KINDS
from ..radar.conventions import (
    DEFAULT_DESIGNATION_RANGE,
    DEFAULT_MAX_RANGE,
    DEFAULT_MAX_SPEED,
    N_BINS,
    N_DOPPLER,
)
from ..radar.params import Param
from ..radar.unit import Unit
from .beams import BeamTracker
from .measurement import MeasurementTracker
from .outputs import TrackerOutputs
from .ports import INPUTS, OUTPUTS


class Tracker(Unit):
    """AXIR_B digital tracker (seed 000). See the module docstring for inputs/outputs."""

    INPUTS = INPUTS
    OUTPUTS = OUTPUTS

    PARAMS = (
        Param("rate_per_volt", 0.1, "rad/(s.V)",
              "pedestal rate per command volt (same value as the Pedestal)", low=0.0,
              high=10.0, low_open=True),  # the Pedestal's range
        Param("pointing_gain", 2.0, "1/s",
              "position-loop gain K of the pointing correction ω = K·(angle error)", low=0.0,
              high=1e4),
        Param("cmd_limit", 10.0, "V", "saturation of the rate-command voltages", low=0.0,
              high=1.0e3, low_open=True),
        Param("designation_az", 0.0, "rad", "designated azimuth (acquisition pointing)",
              low=-2 * math.pi, high=2 * math.pi),
        Param("designation_el", 0.1, "rad", "designated elevation (acquisition pointing)",
              low=-math.pi / 2, high=math.pi / 2),
        Param("designation_range", DEFAULT_DESIGNATION_RANGE, "m",
              "designated range (reported in mode 0)",
              low=0.0, high=1.0e6),  # as RadarManager.designation_range
        # as RadarManager.max_range: the gate never leaves [0, max_range] (issue 11)
        Param("max_range", DEFAULT_MAX_RANGE, "m",
              "instrumented range: the confirmed gate's true range is kept in [0, max_range]",
              low=0.0, high=1.0e6, low_open=True),
        # as RadarManager.max_speed (issue 11: no track faster than a physical bound)
        Param("max_speed", DEFAULT_MAX_SPEED, "m/s",
              "bound on the track speed while coasting: a faster filter velocity is scaled "
              "back onto it (α-β and Kalman CV filters)", low=0.0, high=1.0e5, low_open=True),
        # session 19 (issue 11; designer's choice, docs/filters.md "The manager's Doppler and
        # a young track's range rate"): seed 000's confirmed mode has "the Doppler frequency
        # computed by the manager"; a young track's evolutive gains read correlated range noise
        # as 10³-10⁴ m/s. The defaults (with velocity_prior_sigma): the range rate set once,
        # at the hand-over, to within 1 m/s of the resolved Doppler's; the prior keeps it
        # while the track is young. Held at every step (10 m/s) an alias of the resolution
        # biased the track (measured: docs/filters.md)
        Param("doppler_rate_tol", 1.0, "m/s",
              "confirmed mode, while the manager resolves the Doppler (input doppler.resolved): "
              "the track's range rate is brought within this of the manager's "
              "doppler.range_rate (the velocity's line-of-sight component projected onto the "
              "interval, before a coast and after a measured update; α-β and Kalman CV "
              "filters); 0: never", low=0.0, high=1.0e5),
        Param("doppler_rate_n", 10**9, "1",
              "doppler_rate_tol applies while the track holds fewer measurements than this "
              "(a young track, whose own range rate is worse than the manager's Doppler)",
              low=1, high=10**9),
        Param("doppler_rate_once", True, "",
              "doppler_rate_tol applies at the first step it can of each track only: the "
              "hand-over of a track that goes on from tentative, the first confirmed reading "
              "of one that starts in confirmed mode (then the filter's gains, with "
              "velocity_prior_sigma, keep it); False: at every such step"),
        # session 11 (issue 11; designer's choice, the seed is silent on a lost track)
        Param("reacquire_time", 1.0, "s",
              "after a confirmed, established track is lost (the manager returns to "
              "acquisition around its last range), the pedestal looks where that track, "
              "extrapolated at constant velocity, would be — for this long, then at the "
              "designation again; 0: at the designation at once",
              low=0.0, high=3600.0),
        # session 25 (issue 11; models/tracker/search.py velocity_known)
        Param("reacquire_velocity_check", True, "",
              "the lost track's velocity is used only when its fit carries the direction "
              "over reacquire_time within init_angle_sigma (span × √(J/J_req) ≥ "
              "√12 × reacquire_time); otherwise the pedestal holds the track's last "
              "direction; False: the velocity however young the track"),
        # session 15 (issue 11; designer's choice, the seeds acquire at the designation only:
        # models/tracker/search.py, docs/filters.md "Acquisition search"): an option, OFF by
        # default — it raises the acquisition false-alarm rate in clutter and across the MTI
        # canceller's elevation
        Param("search_radius", 0.0, "rad",
              "acquisition search: while the manager finds nothing, the radar alternates a "
              "dwell of search_dwell on the designation with one lap, of search_period, of a "
              "circle of this angular radius around it (2.5° = one beamwidth: every direction "
              "1.25-3.75° off the designation passes through the 3 dB beam); 0: no search "
              "(the default)", low=0.0, high=0.5),
        Param("search_dwell", 0.5, "s",
              "acquisition search: time on the designation before each lap", low=0.0,
              high=3600.0),
        Param("search_period", 1.5, "s",
              "acquisition search: duration of one lap of the circle (the pedestal follows "
              "at 2π·search_radius/search_period)", low=0.05, high=3600.0),
        Param("search_accel", 1.0, "rad/s2",
              "acquisition search: the lap lasts at least 2π·√(search_radius/(search_accel·"
              "cos el)) (el: the designation's), so that the azimuth acceleration of the look "
              "direction stays within this (half the Pedestal's default 2 rad/s²); at 80° "
              "elevation 3.15 s", low=1e-3, high=1e3),
        Param("search_min_el", math.radians(0.5), "rad",
              "acquisition search: the lap never looks below min(designation elevation, "
              "this) (the main beam out of the ground clutter)",
              low=-math.pi / 2, high=math.pi / 2),
        Param("monopulse_law", "linear", "",
              "angle from DIF/SUM ratio: 'linear' θ = ε/k_m (SYSTEM.md) or 'exact' "
              "θ = atanh(ε)/k_m (inverse of the Gaussian pattern)", choices=("linear", "exact")),
        # session 13 (issue 11): the exact law's reading is clipped to the main lobe (a noisy
        # ratio near ±1 would read up to 13°)
        Param("exact_max_angle", math.radians(2.5), "rad",
              "monopulse_law 'exact': largest angle a reading gives, |θ| ≤ this (the ratio "
              "clipped to ±tanh(k_m·this)); the linear law reads at most 1/k_m ≈ 1.8°",
              low=1e-4, high=0.5),
        # session 12 (issue 11; an option, OFF by default: docs/filters.md "A tentative track
        # coasts in range"): a young track's cross-range velocity is angle noise × range /
        # span; on it fixed the traced walk but moved marginal envelope cells both ways
        # (measured again in session 16, with the speed bound before a coast: still both ways)
        Param("tentative_radial_coast", False, "",
              "tentative: a coasting track (no usable reading) keeps only the line-of-sight "
              "component of its velocity, so the antenna does not walk on the cross-range "
              "velocity of a few weak readings; False: the full velocity"),
        Param("beamwidth", math.radians(2.5), "rad", "3 dB beamwidth of each squinted beam",
              low=1e-4, high=0.5),
        Param("squint", math.radians(1.25), "rad", "squint of each beam from boresight",
              low=0.0, high=0.5, low_open=True),
        Param("min_snr", 2.0, "1",
              "weak-signal check: coast unless gate-centre SUM > min_snr × mean side-bin SUM",
              low=0.0, high=1.0e6),
        # issue 11 (designer's choice, docs/filters.md "No-track report and track initiation")
        Param("track_init_n", 10, "1",
              "track initiation: a confirmed track is reported (track.range/az/el/"
              "range_rate, track.valid) once its filter holds this many measurements; before, "
              "and in tentative, the report is where the radar looks (gate centre of the "
              "manager's hypothesis, antenna boresight)", low=1, high=1000),
        Param("handover_range_tolerance", 75.0, "m",
              "hand-over to confirmed: a tentative track whose range is farther than this "
              "from the centre of the manager's confirmed gate, but within 2 bins of it, is "
              "moved along its line of sight onto that centre (beyond 2 bins it is reset: "
              "another range hypothesis)", low=0.0, high=1.0e6),
        Param("confirm_reinit_nis", 16.27, "1",
              "hand-over to confirmed: the tentative track's position is re-centred on the "
              "first confirmed measurement when that measurement's normalised innovation "
              "squared exceeds this (default: χ²₃ quantile at 1e-3; 0: always); velocity and "
              "gain schedule are kept. The confirmed cells (central Doppler filter) read the "
              "target; the tentative Σ over the 3 filters reads clutter-biased angles at low "
              "SNR", low=0.0, high=1.0e12),
        # issue 11 (session 9, docs/filters.md "Angle accuracy of a weak reading"): the
        # monopulse thermal-noise accuracy of each reading, from its gate-cell SNR
        Param("init_angle_sigma", math.radians(0.25), "rad",
              "track initiation by angle accuracy: a confirmed track is reported only once "
              "the angle information of its readings, J = Σ c/σθ,k² (σθ,k the monopulse "
              "accuracy of reading k from its gate-cell SNR, c the independent fraction of a "
              "PRI, see reading_pole), reaches 1/init_angle_sigma²; before, the report is "
              "where the radar looks (0: no accuracy test, only track_init_n)",
              low=0.0, high=math.pi),
        # session 12 (issue 11; an option, OFF by default: docs/filters.md "The direction of
        # a young confirmed track"): a target confirmed off boresight (a designation 2-3° off)
        # is reported at the boresight, beyond the angle gate, until J is reached; the
        # posterior mean fixes half of those but reports weak 60 km tracks off the target
        Param("init_prior_sigma", 0.0, "rad",
              "a confirmed track whose angle information is below init_angle_sigma, and a "
              "tentative track, report the posterior mean of the direction with the boresight "
              "as a prior of this "
              "standard deviation (the target is in the beam): boresight + w·(track − "
              "boresight), w = J/(J + 1/σ²); 0: the boresight (session 9)",
              low=0.0, high=math.pi),
        # session 13 (issue 11; docs/filters.md "A tentative track whose direction is known"):
        # the first confirmed sample carries the tentative report (the Tracker steps before
        # the manager); a target confirmed 2-3° off boresight was reported at the boresight,
        # outside the angle gate, though its direction was known
        Param("tentative_known_direction", True, "",
              "a tentative track of track_init_n readings whose angle information has "
              "reached 1/init_angle_sigma² reports its filtered direction at a PRI with a "
              "reading (as a confirmed, established track would), and a hand-over re-centre "
              "keeps a known direction known; False: where the radar looks (session 9)"),
        # session 22 (issue 11; docs/filters.md "A re-centre keeps a known direction on a
        # weaker reading"): session 13's 4 forgot a known direction on hand-over readings of
        # 2-3 % of J_req and reported the boresight, 2-2.9° off, for 12-76 PRIs
        Param("recentre_keep_factor", 8.0, "1",
              "tentative_known_direction: a hand-over re-centre keeps a known direction known "
              "when the first confirmed reading's monopulse accuracy is within this factor of "
              "init_angle_sigma (its angle information ≥ 1/(factor·init_angle_sigma)²); a "
              "less accurate reading restarts J from its own information (the report: where "
              "the radar looks until J is reached again)", low=1.0, high=1.0e6),
        # session 14 (issue 11; docs/filters.md "The reported direction inverts the
        # pattern"): the filter averages the linear law's readings, which saturate at 1/k_m
        # ≈ 1.8°: a target confirmed 3.4° off the boresight was reported 1.7° off it
        Param("report_inverts_pattern", True, "",
              "monopulse_law 'linear': a track that reports its filtered direction reports "
              "boresight + atanh(k_m·d)/k_m per axis (d: the filtered direction's lateral and "
              "elevation offsets from the boresight, |result| ≤ max(exact_max_angle, |d|)), "
              "the Gaussian pattern inverted on the averaged readings; the filter, the "
              "pointing and every other output are unchanged; False: boresight + d"),
        # session 15 (issue 11; docs/filters.md "Acquisition search"): the tentative readings
        # are Σ over the 3 Doppler filters, two of which hold only noise: it adds to both
        # beams of a pair and pulls the averaged ratio toward 0
        Param("tentative_dilution", True, "",
              "a tentative track that reports its known direction (tentative_known_direction) "
              "scales its filtered offsets from the boresight by Σ(u + d)/Σ(u + d − noise/3) "
              "(elevation; r, l lateral) over its readings, the noise of the two filters "
              "without the target removed from the sums (noise: the mean background SUM); the "
              "filter and the pointing are unchanged; False: no scaling"),
        # session 24 (issue 11; docs/filters.md "The tentative Σ without a clutter filter"):
        # the third filter on the clutter line biased every tentative elevation reading
        Param("tentative_clutter_ratio", 2.0, "1",
              "tentative readings: a side Doppler filter whose mean background SUM (bins 1-4, "
              "10-16) exceeds this × the quietest filter's holds clutter and is left out of "
              "the angle readings' Σ over the filters (the range profile and the noise level "
              "keep the 3); 0: the Σ over the 3 filters (SYSTEM.md)", low=0.0, high=1.0e6),
        # session 23 (issue 11; docs/filters.md "A beam at the noise: the reading across the
        # other pair"): a target 3.5° off the boresight read 1.45° in every confirmed reading
        Param("edge_reading_angle", math.radians(1.25), "rad",
              "monopulse_law 'linear', confirmed readings: an axis whose linear reading is "
              "beyond tanh(k_m·this)/k_m (the pair's weaker beam then holds mostly noise), "
              "while both beams of the other pair hold more signal than noise, is read as the "
              "stronger beam against the other pair's geometric mean (exact for the Gaussian "
              "beams), as the linear law's noise-free value of that angle; 0: off",
              low=0.0, high=0.5),
        Param("edge_reading_snr", 100.0, "1",
              "edge_reading_angle: the pair's stronger beam must hold this × the noise power "
              "per beam (signal power b² − σ² over σ², σ² from the background bins; 100: "
              "20 dB), so that the reading's own noise does not decide the edge",
              low=0.0, high=1.0e9),
        # session 24 (issue 11; docs/filters.md "… tentative readings at the beam's edge"):
        # a target 2.8° off the boresight read 1.0-1.4° in the Σ over the filters
        Param("tentative_edge_fraction", 0.5, "1",
              "edge_reading_angle in tentative: a reading (Σ over the filters) beyond this × "
              "the edge deviation tanh(k_m·edge_reading_angle)/k_m on an axis is read on the "
              "centre filter's cell of the strongest gate bin, and an axis beyond the edge "
              "there takes the edge reading (the Σ holds two filters' noise in both beams and "
              "reads short); 0: off", low=0.0, high=1.0e6),
        # session 17 (issue 11; an option, OFF by default: docs/filters.md "a coasting PRI
        # holds the tentative report"): removes a false first confirmed sample in the
        # designation sweep but makes one in the design (the held report was the worse one)
        Param("tentative_report_hold", 0.0, "s",
              "a tentative track that reported its known direction (tentative_known_direction) "
              "at a PRI with a reading reports that same direction at the coasting PRIs up to "
              "this long after it (0: only at PRIs with a reading, else where the radar "
              "looks; measured: 0.01)",
              low=0.0, high=1.0),
        Param("reading_pole", 0.9, "1",
              "pole ρ of the one-pole Doppler filters that form the beams (the "
              "TargetGenerator's pole): consecutive readings share their noise, each PRI "
              "counts as c = (1 − ρ)/(1 + ρ) independent readings (noise-equivalent "
              "bandwidth of the filter; 0: independent readings)",
              low=0.0, high=1.0, high_open=True),
        # issue 11 (designer's choices, docs/filters.md "Confirmed tracking at low SNR")
        Param("range_noise_correction", True, "",
              "range deviation: remove the background noise power from the gate cells "
              "before the early/late ratio (keeps the range discriminator's slope ≈ 1 at "
              "low SNR); False: the plain ratio"),
        Param("gate_latency", 1, "1",
              "steps between a gate.start output and the beams formed with it", low=1, high=4),
        # 0: SYSTEM.md's schedule (evolutive until the manager's steady gains take over); the
        # shorter memory the far tracks need (issue 11) comes from the manager's tracking index
        # (RadarManager.sigma_meas / sigma_man), not from a cap here (docs/filters.md)
        Param("n_max", 0, "1",
              "cap of the evolutive gain index (0 = none: growing memory until the manager's "
              "steady gains take over)", low=0, high=10**9),
        # session 17 (issue 11; docs/filters.md "A velocity prior on the evolutive gains"):
        # the evolutive gains fit a line to readings a PRI apart that share their noise over
        # ≈ 1/c PRIs; a young track's velocity gain (β/T ≈ 500 /s at n = 10) turned a 36 m
        # correlated range error into 10⁴ m/s. Off in session 17 (its mean 0 pulled two weak
        # maneuvering targets' range rate toward 0); on since session 19, with the mean set
        # from the manager's Doppler at the hand-over (doppler_rate_once). 0: seed 000's law
        Param("velocity_prior_sigma", 600.0, "m/s",
              "α-β evolutive phase: the velocity gain is that of the line fit with a prior of "
              "this standard deviation on each axis's velocity (readings of variance "
              "sigma_range²/c, c as in reading_pole, a PRI apart; filters/gains.py "
              "prior_gains), the position gain seed 000's α(n): the velocity moves only as the "
              "readings' span outweighs the prior; 0: seed 000's β(n)", low=0.0, high=1.0e6),
        # session 20 (issue 11; docs/filters.md "Targets at the beam's edge and weak young
        # tracks"): measured, off by default; measured again in session 28 (docs/filters.md
        # "The velocity prior per axis, measured again"): still off
        Param("velocity_prior_axes", False, "",
              "the velocity prior (velocity_prior_sigma) with each axis's own reading "
              "variance: q scales with r_axis/sigma_range² (at long range the cross-range "
              "axes read R·sigma_angle, ≫ sigma_range: the prior then weighs as much there as "
              "along the line of sight); False: every axis with sigma_range"),
        # session 30 (issue 11; docs/clutter.md "Through the clutter notch"; designer's choice):
        # a target whose radial speed passes through 0 at low elevation leaves only the
        # clutter's residue in the confirmed cell; its readings walked the track to the ground
        Param("notch_coast_speed", 5.0, "m/s",
              "a confirmed track coasts (its readings, the clutter's, are not used) while the "
              "manager's Doppler (doppler.range_rate, doppler.resolved) is within this speed "
              "of 0 (the default: RadarManager.clutter_notch_speed's) and the antenna below "
              "notch_coast_max_el (models/tracker/notch.py; filters with a velocity state); "
              "0: off", low=0.0, high=1.0e3),
        Param("notch_coast_max_el", math.radians(4.5), "rad",
              "notch_coast_speed applies below this antenna elevation (the clutter regime: "
              "TargetGenerator's mti_max_el)", low=-math.pi / 2, high=math.pi / 2),
        Param("notch_cross_time", 6.0, "s",
              "notch_coast_speed: the coast starts only when a target flying straight at the "
              "velocity of a line fitted to the track's positions (1 s fading memory) crosses "
              "the notch (range rate from ≤ 0 to +notch_coast_speed) within this time; a "
              "coast lasts at most twice this", low=0.0, high=100.0, low_open=True),
        # session 29 (issue 11; docs/filters.md "Each elevation beam's own background"): on
        Param("beam_background", 0.3, "1",
              "confirmed readings: this fraction of each elevation beam's background power "
              "(the mean power of its background bins 1-4, 10-16 in the central filter) "
              "removed from the gate cell's power before the elevation ratio (cells."
              "bg_removed): ground clutter filling the lower beam pulls the reading less "
              "toward it; 0: off", low=0.0, high=1.0),
        Param("beam_background_pole", 0.9, "1",
              "beam_background: the gate cell's power less the background averaged over the "
              "PRIs of a confirmed track with this pole (0: each PRI alone)", low=0.0,
              high=1.0, high_open=True),
        Param("sigma_range", 7.5, "m",
              "range measurement accuracy σr: maneuver detector and the filters' measurement "
              "variance (measurement mode: σ of meas.range; seed 002 scenarios: 100 m)",
              low=0.0, high=1.0e5, low_open=True),  # σ² must stay far from overflow
        Param("sigma_angle", 1e-3, "rad",
              "angle measurement accuracy: maneuver detector and the filters' measurement "
              "variance (measurement mode: σ of meas.az and meas.el)", low=0.0, high=math.pi,
              low_open=True),
        Param("maneuver_fading", 0.8, "1",
              "fading factor ρ of the NIS average (memory ≈ 1/(1 − ρ) updates)", low=0.0,
              high=1.0, high_open=True),
        Param("maneuver_pfa", 1e-3, "1", "false-alarm probability of the maneuver test",
              low=0.0, high=1.0, low_open=True, high_open=True),
        Param("ddre_window", 0, "1",
              "DDRE window s in 75 m bins on the SUM profile (0 = DDRE disabled)", low=0,
              high=5),
        Param("ddre_background", "none", "", "DDRE background subtraction (seed 001)",
              choices=("none", "local", "global")),
        Param("ddre_threshold", 0.0, "1", "DDRE threshold on S0(r_max) [SUM magnitude²]",
              low=0.0, high=1.0e60),  # (4·1e30 beam magnitude bound)²
        Param("ddre_memory", 0.5, "s", "DDRE memory τ (seed 001 eq. 10)", low=0.0,
              high=3600.0, low_open=True),
        Param("ddre_velocity_cut", 200.0, "m/s", "DDRE velocity cut (0 = none)", low=0.0,
              high=1.0e5),
        Param("ddre_t_pred", 0.1, "s", "DDRE prediction shift t_pred (seed 001 eq. 11)",
              low=0.0, high=3600.0),
        Param("input_mode", "beams", "",
              "'beams': monopulse beams + pedestal (seed 000 tracker); 'measurement': filter "
              "meas.range/az/el (TargetGenerator measurement fidelity, seed 002 experiments)",
              choices=("beams", "measurement")),
        *(Param(f"filter_{axis}", "alphabeta", "",
                f"filter of the {label} axis ({mode} input mode; docs/filters.md)",
                choices=FILTER_KINDS)
          for axis, label, mode in (("x", "East (X)", "beams"), ("y", "North (Y)", "beams"),
                                    ("z", "Up (Z)", "beams"), ("range", "range", "measurement"),
                                    ("az", "azimuth", "measurement"),
                                    ("el", "elevation", "measurement"))),
        Param("filter_sigma_m", 5.0, "m/s2",
              "process noise σm of the two-state models (seed 002 eq. 4; svd-1: 5, svd-2: 20); "
              "angle axes use σm/ρ", low=0.0, high=1e4),
        Param("filter_sigma_a", 5.0, "m/s2",
              "acceleration noise σa per 1 s of the SVD acceleration filter: Q_u = σa²·T "
              "(seed 002 eqs. 22, 36; no value in the seed: 5 → Q_u = 25 fits the Table 3 "
              "P_u and K_u ranges, docs/filters.md)", low=0.0, high=1e4),
        Param("filter_sigma_j", 2.0, "m/s2",
              "jerk noise σj per 1 s of the three-state models (VD, IMM CA): white-jerk "
              "density σj²/s (assumption, not in seed 002)", low=0.0, high=1e4),
        Param("fmd_i1", 0.0, "1",
              "FMD detection threshold I1 on L(k) (seed 002 eqs. 11-15); 0 = chi2 quantile at "
              "maneuver_pfa (fading factor a_f = maneuver_fading)", low=0.0, high=1e6),
        Param("fmd_i2", 0.0, "1",
              "FMD end-of-maneuver threshold I2 on the acceleration significance summed over "
              "M = 1/(1 − a_f) updates; 0 = chi2 quantile at fmd_level", low=0.0, high=1e6),
        Param("fmd_end", "hysteresis", "",
              "reading of I2 (docs/filters.md): 'acceleration' = flag held while the sum of "
              "û²/P_u over M updates ≥ I2; 'hysteresis' = held while L ≥ I2 (enter above I1, "
              "leave below I2); the VD filter keeps its own end test",
              choices=("acceleration", "hysteresis")),
        Param("fmd_level", 0.05, "1", "significance level of the acceleration test (I2)",
              low=0.0, high=1.0, low_open=True, high_open=True),
        Param("svd_pu0", 0.1, "m2/s4", "SVD P_u(0/0) (seed 002 §2.3: 0.1)", low=0.0,
              high=1.0e8, low_open=True),  # (1e4 m/s²)²
        Param("svd_c", "paper", "",
              "full SVD form: C of eqs. 20, 25, 27: 'paper' C = T²/2, 'zero' C = 0 (then equal "
              "to the reduced form)", choices=("paper", "zero")),
        Param("imm_sojourn_cv", 20.0, "s", "IMM mean sojourn time of the CV mode",
              low=0.0, high=1.0e6, low_open=True),
        Param("imm_sojourn_ca", 5.0, "s", "IMM mean sojourn time of the CA mode",
              low=0.0, high=1.0e6, low_open=True),
        Param("imm_mu_ca", 0.1, "1", "IMM initial probability of the CA mode", low=0.0,
              high=1.0, low_open=True, high_open=True),
        Param("imm_sigma_acc0", 20.0, "m/s2", "IMM initial acceleration σ", low=0.0,
              high=1.0e4),
        Param("fixed_point", False, "",
              "emulate the seed-002 FPGA word lengths (Table 3: 8/12/16-bit buses, rounding, "
              "saturation) in the range filter; needs input_mode = measurement and "
              "filter_range = svd_reduced (docs/fixed_point.md)"),
    )
    #: the parameter values that give seed 000's tracker where the defaults depart from it
    #: (session 19: the velocity prior on the evolutive velocity gain, the range rate set from
    #: the manager's Doppler; docs/filters.md "The manager's Doppler and a young track's range
    #: rate"; session 24: the tentative readings Σ over the 3 filters whatever they hold, as
    #: SYSTEM.md; session 29: the DIF/SUM ratios of the raw beams; session 30: no notch
    #: coast): the seed reproduction runs with them
    SEED000: ClassVar[dict[str, float]] = {"velocity_prior_sigma": 0.0, "doppler_rate_tol": 0.0,
                                           "tentative_clutter_ratio": 0.0,
                                           "tentative_edge_fraction": 0.0,
                                           "beam_background": 0.0, "notch_coast_speed": 0.0}
    PACKAGES_BY_PARAM: ClassVar = {p.name: EXTRA_PACKAGES for p in PARAMS
                         if p.name.startswith("filter_") and p.choices == FILTER_KINDS}

    def _check(self) -> None:
        if self.fixed_point and (self.input_mode != "measurement"
                                 or self.filter_range != "svd_reduced"):
            raise ValueError(
                f"Tracker: fixed_point = True needs input_mode = 'measurement' and "
                f"filter_range = 'svd_reduced' (got {self.input_mode!r}, "
                f"{self.filter_range!r}): the Table 3 word lengths are those of the seed-002 "
                "range filter"
            )
        if self.squint > self.beamwidth:
            raise ValueError(
                f"Tracker: squint = {self.squint!r} rad must not exceed beamwidth = "
                f"{self.beamwidth!r} rad"
            )

    # ---------------------------------------------------------------------------- state
    def reset(self) -> None:
        cfg = FilterConfig(
            sigma_m=self.filter_sigma_m, sigma_meas=self.sigma_range, sigma_a=self.filter_sigma_a,
            sigma_j=self.filter_sigma_j, a_f=self.maneuver_fading, i1=self.fmd_i1,
            i2=self.fmd_i2, pfa=self.maneuver_pfa, level=self.fmd_level, fmd_end=self.fmd_end,
            pu0=self.svd_pu0, svd_c=self.svd_c,
            imm_sojourn_cv=self.imm_sojourn_cv, imm_sojourn_ca=self.imm_sojourn_ca,
            imm_mu_ca=self.imm_mu_ca, sigma_acc0=self.imm_sigma_acc0, n_max=self.n_max,
            vel_prior_k=self._velocity_prior_k(),
            vel_prior_r=self.sigma_range ** 2 if self.velocity_prior_axes else 0.0,
        )
        #: the input mode's tracker: all the state of the track
        self.core: BeamTracker | MeasurementTracker = (
            MeasurementTracker(self, cfg) if self.input_mode == "measurement"
            else BeamTracker(self, cfg))

    def _velocity_prior_k(self) -> float:
        """r/σv² [s²] of velocity_prior_sigma (0: none): r = sigma_range²/c, c = (1 − ρ)/(1 + ρ)
        the independent fraction of a reading (reading_pole ρ)."""
        sv = self.velocity_prior_sigma
        if not sv > 0.0:
            return 0.0
        rho = self.reading_pole
        return self.sigma_range ** 2 * (1.0 + rho) / ((1.0 - rho) * sv * sv)

    def outputs(self) -> dict[str, Any]:
        """Outputs before the first step: nothing measured or commanded yet — no track
        (``track.valid`` false, estimates 0), SUM 0, commands 0 V, ``gate.start`` 0 (the first
        step sets the gate from ``gate.command``), as :class:`~.outputs.TrackerOutputs`
        defaults. Between steps the outputs are those ``step`` returned."""
        return TrackerOutputs(np.zeros((N_BINS, N_DOPPLER))).as_dict()

    def step(self, dt: float, inputs: Mapping[str, Any]) -> dict[str, Any]:
        """Advance one step of ``dt`` [s] (one PRI in beams mode); keys and units:
        :data:`INPUTS`, :data:`OUTPUTS`."""
        return self.core.step(float(dt), inputs)

    def run_step(self) -> Callable[[float, Mapping[str, Any]], dict[str, Any]]:
        """:meth:`Unit.run_step`: the input mode's ``core.step`` (what :meth:`step` calls with
        ``float(dt)``, which is ``dt`` for a float), unless ``step`` was replaced on this
        instance or overridden by a subclass (then ``step`` itself)."""
        if "step" in self.__dict__ or type(self).step is not Tracker.step:
            return self.step
        return self.core.step

    def run_step_args(self) -> tuple[Callable[..., dict[str, Any]], tuple[str, ...]] | None:
        """:meth:`Unit.run_step_args`: the beams mode's ``core.step`` with its positional
        inputs (:attr:`BeamTracker.STEP_ARGS`), under :meth:`run_step`'s conditions (and the
        core's ``step`` its class's own); None otherwise (the measurement mode too)."""
        core = self.core
        if (type(core) is not BeamTracker or "step" in core.__dict__ or "step" in self.__dict__
                or type(self).step is not Tracker.step):
            return None
        return core.step, BeamTracker.STEP_ARGS
