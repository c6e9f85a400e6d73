"""Scenario files (TOML): a human-readable run definition turned into a system description.

Schema (all keys optional except where noted; units SI)::

    [scenario]
    name = "closed-loop"          # required
    description = "..."
    duration = 40.0               # [s] simulated time
    seed = 1                      # base seed; each unit with a `seed` parameter gets a
                                  # stable per-unit seed derived from it
                                  # (axir.models.system.unit_seed)
    algorithm = "gauss-seidel"    # or "jacobi"
    order = ["Pedestal", "TargetGenerator", "Tracker", "RadarManager"]
    step = "variable"             # or a fixed step [s], e.g. 1e-4
    step_from = "RadarManager.pri"  # with step = "variable": output giving the next step [s]
    initial_step = 1e-4           # [s] first step while step_from has no valid value yet
                                  # (default: the manager's initial PRI)

    [record]
    decimation = 10               # record every Nth step
    variables = ["Tracker.track.range", ...]   # default: truth, track, deviations, mode, pedestal

    [units.Tracker]
    fmu = "Tracker.fmu"           # relative to the FMU directory (default ./dist)
    parameters = { gate_latency = 1 }

    connections = "radar"         # the SYSTEM.md loop (default), or a list of tables:
    [[connections]]
    from = "Tracker.cmd.az"
    to = "Pedestal.cmd.az"

:func:`scenario_problems` is pure (returns a list of problems); :func:`load_scenario` raises
:class:`ScenarioError` naming the file and the key.
"""

from __future__ import annotations

import math
import sys
from importlib import resources
from pathlib import Path
from typing import Any

from axir.models.system import CONNECTIONS, Connection

from .config import DEFAULT_INITIAL_STEP, DEFAULT_STEP_FROM
from .errors import ScenarioError
from .scenario_spec import DEFAULT_RECORD, Scenario
from .ssp.importer import load_ssp

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

DEFAULT_SCENARIO = "closed-loop"
_TOP_KEYS = {"scenario", "record", "units", "connections"}
_SCEN_KEYS = {"name", "description", "duration", "seed", "algorithm", "order", "step",
              "step_from", "initial_step"}


def _is_num(x: Any) -> bool:
    """A finite number (TOML reads ``inf`` and ``nan`` as floats)."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def scenario_problems(data: dict[str, Any]) -> list[str]:
    """Problems of a parsed scenario dict, each naming its key (pure function)."""
    p: list[str] = []
    for k in sorted(set(data) - _TOP_KEYS):
        p.append(f"unknown top-level key {k!r} (known: {', '.join(sorted(_TOP_KEYS))})")
    sc = data.get("scenario")
    if not isinstance(sc, dict):
        return [*p, "missing table [scenario]"]
    for k in sorted(set(sc) - _SCEN_KEYS):
        p.append(f"scenario.{k}: unknown key (known: {', '.join(sorted(_SCEN_KEYS))})")
    if not isinstance(sc.get("name"), str) or not sc.get("name"):
        p.append("scenario.name: required, a non-empty string")
    if "duration" in sc and not (_is_num(sc["duration"]) and sc["duration"] > 0):
        p.append("scenario.duration: must be a positive, finite number of seconds, "
                 f"got {sc['duration']!r}")
    if "seed" in sc and not (isinstance(sc["seed"], int) and not isinstance(sc["seed"], bool)
                             and sc["seed"] >= 0):
        p.append(f"scenario.seed: must be a non-negative integer, got {sc['seed']!r}")
    if sc.get("algorithm", "gauss-seidel") not in ("gauss-seidel", "jacobi"):
        p.append(f"scenario.algorithm: 'gauss-seidel' or 'jacobi', got {sc['algorithm']!r}")
    step = sc.get("step", "variable")
    if step != "variable" and not (_is_num(step) and step > 0):
        p.append(f"scenario.step: 'variable' or a positive, finite step in seconds, got {step!r}")
    for k in ("initial_step",):
        if k in sc and not (_is_num(sc[k]) and sc[k] > 0):
            p.append(f"scenario.{k}: must be a positive, finite number of seconds, "
                     f"got {sc[k]!r}")
    units = data.get("units", {})
    if not isinstance(units, dict) or not units:
        p.append("units: at least one [units.NAME] table is required")
        units = {}
    for name, spec in units.items():
        if not isinstance(spec, dict):
            p.append(f"units.{name}: must be a table")
            continue
        for k in sorted(set(spec) - {"fmu", "parameters"}):
            p.append(f"units.{name}.{k}: unknown key (known: fmu, parameters)")
        if "fmu" in spec and not isinstance(spec["fmu"], str):
            p.append(f"units.{name}.fmu: must be a file name string")
        params = spec.get("parameters", {})
        if not isinstance(params, dict):
            p.append(f"units.{name}.parameters: must be a table")
            continue
        for k, v in params.items():
            if not isinstance(v, (bool, int, float, str)):
                p.append(f"units.{name}.parameters.{k}: must be a number, boolean or string")
    order = sc.get("order", list(units))
    if not isinstance(order, list) or sorted(order) != sorted(units):
        p.append(f"scenario.order: must list exactly the units {sorted(units)}, got {order!r}")
    if "step_from" in sc:
        ref = sc["step_from"]
        if not isinstance(ref, str) or ref.partition(".")[0] not in units:
            p.append(f"scenario.step_from: 'Unit.variable' of a declared unit, got {ref!r}")
    elif step == "variable" and units and DEFAULT_STEP_FROM.partition(".")[0] not in units:
        p.append(f"scenario.step: a variable step reads {DEFAULT_STEP_FROM!r}, a unit this "
                 "scenario does not declare: give step = <seconds> or step_from")
    rec = data.get("record", {})
    if not isinstance(rec, dict):
        p.append("record: must be a table")
        rec = {}
    dec = rec.get("decimation", 1)
    if not (isinstance(dec, int) and not isinstance(dec, bool) and dec >= 1):
        p.append(f"record.decimation: must be an integer >= 1, got {dec!r}")
    for v in rec.get("variables", []):
        if not isinstance(v, str) or v.partition(".")[0] not in units:
            p.append(f"record.variables: {v!r} is not 'Unit.variable' of a declared unit")
    conns = data.get("connections", "radar")
    if isinstance(conns, str):
        if conns != "radar":
            p.append(f"connections: 'radar' or a list of {{from, to}} tables, got {conns!r}")
    elif isinstance(conns, list):
        for i, c in enumerate(conns):
            if not isinstance(c, dict) or set(c) != {"from", "to"}:
                p.append(f"connections[{i}]: must be a table with exactly 'from' and 'to'")
                continue
            for end in ("from", "to"):
                ref = c[end]
                if not isinstance(ref, str) or ref.partition(".")[0] not in units:
                    p.append(f"connections[{i}].{end}: {ref!r} is not 'Unit.variable' "
                             "of a declared unit")
    else:
        p.append("connections: 'radar' or a list of {from, to} tables")
    return p


def parse_scenario(data: dict[str, Any], source: str) -> Scenario:
    """Validate a parsed scenario dict and build a :class:`Scenario`."""
    problems = scenario_problems(data)
    if problems:
        raise ScenarioError(f"{source}: " + "; ".join(problems))
    sc = data["scenario"]
    units = {n: dict(s) for n, s in data["units"].items()}
    conns_raw = data.get("connections", "radar")
    if conns_raw == "radar":
        conns = [c for c in CONNECTIONS if c.src_unit in units and c.dst_unit in units]
    else:
        conns = []
        for c in conns_raw:
            su, _, sv = c["from"].partition(".")
            du, _, dv = c["to"].partition(".")
            conns.append(Connection(su, sv, du, dv))
    rec = data.get("record", {})
    record = rec.get("variables")
    if record is None:
        record = [r for r in DEFAULT_RECORD if r.partition(".")[0] in units]
    step = sc.get("step", "variable")
    return Scenario(
        name=sc["name"],
        source=source,
        description=sc.get("description", ""),
        duration=float(sc.get("duration", 10.0)),
        seed=int(sc.get("seed", 1)),
        algorithm=sc.get("algorithm", "gauss-seidel"),
        order=list(sc.get("order", list(units))),
        step=None if step == "variable" else float(step),
        step_from=sc.get("step_from", DEFAULT_STEP_FROM),
        initial_step=float(sc.get("initial_step", DEFAULT_INITIAL_STEP)),
        decimation=int(rec.get("decimation", 1)),
        record=list(record),
        units=units,
        connections=conns,
    )


def builtin_scenarios() -> list[str]:
    """Names of the scenarios shipped inside the package."""
    d = resources.files("axir.orchestrator") / "scenarios"
    return sorted(p.name[:-5] for p in d.iterdir() if p.name.endswith(".toml"))


def load_scenario(ref: str | Path | None = None) -> Scenario:
    """Load a scenario by file path or by built-in name (default: the closed loop); an SSP
    archive (``.ssp``) or system description (``.ssd``) is read by
    :func:`.ssp.importer.load_ssp`."""
    ref = DEFAULT_SCENARIO if ref is None else ref
    path = Path(ref)
    if path.suffix in (".ssp", ".ssd"):
        return load_ssp(path)
    if path.suffix != ".toml" and not path.exists():
        res = resources.files("axir.orchestrator") / "scenarios" / f"{ref}.toml"
        if not res.is_file():
            raise ScenarioError(
                f"no scenario file {ref!r} and no built-in scenario of that name "
                f"(built-in: {', '.join(builtin_scenarios())})"
            )
        text, source = res.read_text(encoding="utf-8"), f"<built-in {ref}>"
    else:
        if not path.is_file():
            raise ScenarioError(f"scenario file not found: {path}")
        try:
            text, source = path.read_text(encoding="utf-8"), str(path)
        except UnicodeDecodeError as e:
            raise ScenarioError(f"{path}: not UTF-8 text (byte {e.start}: "
                                f"{e.object[e.start:e.start + 1]!r}); TOML files are UTF-8"
                                ) from None
        except OSError as e:
            raise ScenarioError(f"scenario file {path}: {e.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ScenarioError(f"{source}: malformed TOML: {e}") from None
    return parse_scenario(data, source)


__all__ = ["DEFAULT_SCENARIO", "builtin_scenarios", "load_scenario", "parse_scenario",
           "scenario_problems"]
