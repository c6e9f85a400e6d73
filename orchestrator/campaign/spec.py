"""What a campaign is: the :class:`CampaignSpec` a worker needs, the recorded variables,
parameter overrides (``--set``) and :func:`prepare`, which validates the inputs and reads the
FMU bytes once."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..errors import AxirError
from ..fmi import load_model_description
from ..preflight import check_fmu_file, check_values
from ..scenario import load_scenario
from ..scenario_spec import Scenario

DEFAULT_ERRORS: dict[str, tuple[str, str]] = {
    "range": ("Tracker.track.range", "TargetGenerator.truth.range"),
    "velocity": ("Tracker.track.range_rate", "TargetGenerator.truth.range_rate"),
    "acceleration": ("Tracker.track.range_acc", "TargetGenerator.truth.range_acc"),
}
ERROR_UNITS = {"range": "m", "velocity": "m/s", "acceleration": "m/s2"}
#: range-axis covariance of the track (P_rr [m²], P_rv [m²/s], P_vv [m²/s²])
DEFAULT_COVARIANCE: tuple[str, str, str] = (
    "Tracker.track.P_rr", "Tracker.track.P_rv", "Tracker.track.P_vv")
#: samples where this is recorded and 0 are excluded (no track yet)
DEFAULT_VALID = "Tracker.track.valid"
DEFAULT_MANEUVER = "Tracker.maneuver"
#: also recorded when present (per-run data for reports)
DEFAULT_EXTRA = ("Tracker.maneuver.statistic", "TargetGenerator.meas.range")


@dataclass(frozen=True)
class CampaignSpec:
    """Everything a worker needs to run any run of the campaign (small and picklable).

    ``units_fmu`` maps unit → (FMU file name, sha256 of its bytes); the bytes travel
    separately (scattered once per worker). ``record`` lists the variables recorded per run.
    ``per_run`` (run index → unit → {parameter: value}) overrides parameters of single runs
    (API only; e.g. a deliberately broken run in tests).
    """

    scenario: Scenario
    units_fmu: tuple[tuple[str, str, str], ...]
    runs: int
    base_seed: int
    record: tuple[str, ...]
    per_run: Mapping[int, Mapping[str, Mapping[str, Any]]] = field(default_factory=dict)

    @property
    def key(self) -> str:
        """Identity of the loaded system a worker may reuse: FMUs, units, order, connections,
        step settings (parameters and seeds change per run and are not part of it)."""
        sc = self.scenario
        ident = (self.units_fmu, tuple(sc.order), tuple(map(str, sc.connections)),
                 sc.algorithm, sc.step, sc.step_from, sc.initial_step)
        return hashlib.sha256(repr(ident).encode()).hexdigest()[:20]


def parse_assignment(text: str) -> tuple[str, str, Any]:
    """``"Unit.param=value"`` → (unit, param, value); the value is read as a boolean
    (``true``/``false``), an integer, a float, or else kept as a string."""
    ref, eq, raw = text.partition("=")
    unit, dot, name = ref.strip().partition(".")
    if not eq or not dot or not unit or not name:
        raise AxirError(f"--set {text!r}: expected UNIT.PARAMETER=VALUE")
    raw = raw.strip()
    value: Any
    if raw.lower() in ("true", "false"):
        value = raw.lower() == "true"
    else:
        try:
            value = int(raw)
        except ValueError:
            try:
                value = float(raw)
            except ValueError:
                value = raw
    return unit, name, value


def with_parameters(scenario: Scenario, assignments: Mapping[str, Mapping[str, Any]]
                    ) -> Scenario:
    """A copy of ``scenario`` with unit parameters overridden (unit → {name: value});
    unknown units raise :class:`AxirError` (unknown parameters are reported by the FMU)."""
    units = {n: {**s, "parameters": dict(s.get("parameters", {}))}
             for n, s in scenario.units.items()}
    for unit, params in assignments.items():
        if unit not in units:
            raise AxirError(f"parameter override for unknown unit {unit!r} "
                            f"(scenario {scenario.name} has {', '.join(units)})")
        units[unit]["parameters"].update(params)
    return replace(scenario, units=units)


def _fmu_files(scenario: Scenario, fmu_dir: Path,
               overrides: Mapping[str, Mapping[str, Any]] | None = None,
               ) -> dict[str, Path]:
    """The FMU file of every unit, checked before the campaign (:mod:`..preflight`: the
    files, then the ``--set`` and scenario parameter values; per-run overrides, an API
    for varying runs, are not: a bad one fails its run alone, reported in runs.csv)."""
    out = {}
    mds = {}
    for name, spec in scenario.units.items():
        path = Path(fmu_dir) / spec.get("fmu", f"{name}.fmu")
        mds[name] = check_fmu_file(path, name)
        out[name] = path
    check_values(overrides or {}, mds, "--set")
    check_values({n: s.get("parameters", {}) for n, s in scenario.units.items()}, mds,
                 scenario.source)
    return out


def _available(paths: Mapping[str, Path]) -> set[str]:
    """``Unit.variable`` names of every unit's FMU (read from the modelDescription only)."""
    names = set()
    for unit, path in paths.items():
        md = load_model_description(path)
        names |= {f"{unit}.{v.name}" for v in md.modelVariables}
    return names


def record_list(available: set[str], errors: Mapping[str, tuple[str, str]],
                covariance: Sequence[str] | None) -> tuple[str, ...]:
    """The variables a campaign records: the error pairs, covariance, validity, maneuver and
    extras that exist in the FMUs (in a fixed order)."""
    want: list[str] = []
    for est, truth in errors.values():
        want += [est, truth]
    want += list(covariance or ())
    want += [DEFAULT_VALID, DEFAULT_MANEUVER, *DEFAULT_EXTRA]
    out: list[str] = []
    for v in want:
        if v in available and v not in out:
            out.append(v)
    return tuple(out)


def prepare(scenario: Scenario | str | Path | None, fmu_dir: Path, runs: int, *,
            seed: int | None = None, duration: float | None = None,
            parameters: Mapping[str, Mapping[str, Any]] | None = None,
            per_run: Mapping[int, Mapping[str, Mapping[str, Any]]] | None = None,
            errors: Mapping[str, tuple[str, str]] = DEFAULT_ERRORS,
            covariance: Sequence[str] | None = DEFAULT_COVARIANCE,
            ) -> tuple[CampaignSpec, dict[str, bytes]]:
    """Validate the inputs and build the :class:`CampaignSpec` and the FMU bytes per unit."""
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    if not (isinstance(runs, int) and runs >= 1):
        raise AxirError(f"--runs must be a positive integer, got {runs!r}")
    sc = sc.with_overrides(duration=duration)
    if parameters:
        sc = with_parameters(sc, parameters)
    base = sc.seed if seed is None else int(seed)
    if base < 0:
        raise AxirError(f"--seed must be >= 0, got {base}")
    paths = _fmu_files(sc, fmu_dir, parameters)
    blobs = {u: p.read_bytes() for u, p in paths.items()}
    units_fmu = tuple((u, p.name, hashlib.sha256(blobs[u]).hexdigest())
                      for u, p in sorted(paths.items()))
    record = record_list(_available(paths), errors, covariance)
    spec = CampaignSpec(sc, units_fmu, runs, base, record, dict(per_run or {}))
    return spec, blobs
