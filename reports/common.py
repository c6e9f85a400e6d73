"""Shared helpers of the seed reproduction reports (reports/seed000.py, reports/seed001.py).

- :func:`fmu_directory`: the four FMUs, built from the working tree into a temporary
  directory (``fmus.build.build_all``, ~2 s) unless a directory is given;
- :func:`run_recorded`: one scenario through the FMUs with :func:`orchestrator.run.run_scenario`,
  optionally shortened and with another record list / decimation, returning the recorded
  columns by name;
- :func:`rcs_to_s0`: the radar-equation conversion of a cross-section threshold [m²] into the
  Tracker's DDRE threshold on S0 [SUM magnitude²] (seed 001 "cross section threshold");
- :func:`rms`.
"""

from __future__ import annotations

import contextlib
import math
import subprocess
import tempfile
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from axir.models.radar.antenna import MonopulseAntenna
from axir.models.target_generator import TargetGenerator
from axir.orchestrator.run import run_scenario
from axir.orchestrator.scenario import Scenario, load_scenario

REPORTS = Path(__file__).resolve().parent
OUT = REPORTS / "out"


@contextlib.contextmanager
def fmu_directory(fmu_dir: str | Path | None = None) -> Iterator[Path]:
    """A directory holding the four FMUs: ``fmu_dir`` if given, else freshly built from the
    working tree into a temporary directory (removed afterwards)."""
    if fmu_dir is not None:
        yield Path(fmu_dir)
        return
    from axir.fmus.build import build_all

    with tempfile.TemporaryDirectory(prefix="axir_fmus_") as d:
        build_all(d)
        yield Path(d)


@dataclass
class Recorded:
    """Columns of one run: ``t`` [s] and every recorded ``Unit.variable``; the run summary."""

    scenario: Scenario
    summary: dict[str, Any]
    columns: dict[str, np.ndarray]

    @property
    def t(self) -> np.ndarray:
        return self.columns["time"]

    def __getitem__(self, ref: str) -> np.ndarray:
        try:
            return self.columns[ref]
        except KeyError:
            raise KeyError(f"{ref!r} was not recorded in scenario {self.scenario.name!r} "
                           f"(recorded: {', '.join(self.columns)})") from None


def run_recorded(
    scenario: str | Scenario,
    fmu_dir: Path,
    *,
    duration: float | None = None,
    record: Sequence[str] | None = None,
    decimation: int | None = None,
    out_dir: Path | None = None,
) -> Recorded:
    """Run a scenario (built-in name, file or :class:`Scenario`) through the FMUs in
    ``fmu_dir``; ``duration`` [s], ``record`` and ``decimation`` override the scenario's."""
    sc = load_scenario(scenario) if isinstance(scenario, (str, Path)) else scenario
    if record is not None:
        sc = replace(sc, record=list(record))
    if decimation is not None:
        sc = replace(sc, decimation=int(decimation))
    summary, rec = run_scenario(sc, fmu_dir, out_dir, duration=duration, progress=False)
    cols = {"time": rec.data[:, 0].copy()}
    for i, ref in enumerate(rec.variables, start=1):
        cols[ref] = rec.data[:, i].copy()
    return Recorded(replace(sc, duration=summary["duration"]), summary, cols)


def boresight_sum_gain(beamwidth: float | None = None, squint: float | None = None) -> float:
    """Σ_b g_b: sum of the four beams' voltage gains for a target on boresight [1]."""
    kw = {k: v for k, v in (("beamwidth", beamwidth), ("squint", squint)) if v is not None}
    return float(np.sum(MonopulseAntenna(**kw).gains(0.0, 0.0)))


def rcs_to_s0(rcs: float, range_m: float, **generator_params: Any) -> float:
    """DDRE threshold on S0 [SUM magnitude²] equivalent to a cross section ``rcs`` [m²] at
    ``range_m`` [m].

    Noise-free SUM of a point target on boresight, centred on a range bin (straddle weight 1)
    and at the centre of the Doppler filter (unit gain): |SUM| = a(R)·Σ_b g_b with the
    TargetGenerator's radar-equation amplitude a(R)² = SNR_ref·(σ/σ_ref)·(R_ref/R)⁴
    (models/target_generator.py), so S0 = |SUM|² = (Σ_b g_b)²·SNR_ref·(σ/σ_ref)·(R_ref/R)⁴.
    ``generator_params`` are TargetGenerator parameters (snr_ref_db, rcs_ref, snr_ref_range,
    beamwidth, squint); absent ones take the generator's defaults.
    """
    if not (rcs >= 0.0 and range_m > 0.0):
        raise ValueError(f"rcs_to_s0: need rcs >= 0 and range > 0, got {rcs!r}, {range_m!r}")
    tg = TargetGenerator(**generator_params)
    snr_ref = 10.0 ** (tg.snr_ref_db / 10.0)
    g = boresight_sum_gain(tg.beamwidth, tg.squint)
    return g * g * snr_ref * (rcs / tg.rcs_ref) * (tg.snr_ref_range / range_m) ** 4


def provenance(summary: dict[str, Any] | None = None) -> str:
    """One line for a report: git commit of the working tree (``+dirty`` when models/, fmus/,
    orchestrator/ or reports/ have uncommitted changes) and the FMUs' sha256 prefixes."""
    root = REPORTS.parent
    try:
        sha = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--",
                                "models", "fmus", "orchestrator", "reports"],
                               capture_output=True, text=True, check=True).stdout.strip()
        text = f"repository at {sha}{'+dirty' if dirty else ''}"
    except (OSError, subprocess.CalledProcessError):
        text = "repository commit unknown"
    fmus = (summary or {}).get("fmus", {})
    if fmus:
        text += "; FMUs sha256 " + ", ".join(f"{n} {v['sha256'][:12]}"
                                             for n, v in sorted(fmus.items()))
    return text


def rms(x: np.ndarray) -> float:
    """Root mean square of the finite values of ``x`` (NaN when there are none)."""
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(x * x))) if x.size else math.nan


def fmt(x: float, digits: int = 2) -> str:
    """A number for a markdown table ("—" for NaN/None)."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.{digits}f}"
