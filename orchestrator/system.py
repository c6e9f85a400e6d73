"""System description: which FMUs, which parameter values, which connections (the radar's
own units and connections are facts of :mod:`axir.models.system`).

Validation follows fmpy's style: :func:`validate_system` is a pure function returning a list of
problems (strings naming unit and variable); nothing is raised until the caller decides.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fmpy.model_description import ModelDescription

from axir.models.system import Connection


@dataclass
class UnitSpec:
    """One FMU instance of the system."""

    name: str
    fmu: Path
    parameters: dict[str, Any] = field(default_factory=dict)


@dataclass
class SystemDescription:
    units: dict[str, UnitSpec]
    connections: list[Connection]


def expand_array(name: str, md: ModelDescription) -> list[str]:
    """``name`` itself if it is a variable, else its structured elements ``name[i,j]`` in
    model-description order (FMI 2.0 structured naming)."""
    names = [v.name for v in md.modelVariables]
    if name in names:
        return [name]
    pat = re.compile(re.escape(name) + r"\[[0-9, ]+\]$")
    return [n for n in names if pat.match(n)]


def expand_connections(
    conns: list[Connection], mds: Mapping[str, ModelDescription]
) -> tuple[list[Connection], list[str]]:
    """Expand array connections element-wise; returns (connections, problems)."""
    out: list[Connection] = []
    problems: list[str] = []
    for c in conns:
        if c.src_unit not in mds or c.dst_unit not in mds:
            missing = c.src_unit if c.src_unit not in mds else c.dst_unit
            problems.append(f"connection {c}: unknown unit {missing!r}")
            continue
        src = expand_array(c.src_var, mds[c.src_unit])
        dst = expand_array(c.dst_var, mds[c.dst_unit])
        if not src:
            problems.append(f"connection {c}: {c.src_unit} has no variable {c.src_var!r}")
            continue
        if not dst:
            problems.append(f"connection {c}: {c.dst_unit} has no variable {c.dst_var!r}")
            continue
        if len(src) != len(dst):
            problems.append(f"connection {c}: {len(src)} source vs {len(dst)} target elements")
            continue
        src_idx = [s[len(c.src_var):] for s in src]
        dst_idx = [d[len(c.dst_var):] for d in dst]
        if src_idx != dst_idx:
            problems.append(f"connection {c}: array indices differ")
            continue
        out += [Connection(c.src_unit, s, c.dst_unit, d) for s, d in zip(src, dst, strict=True)]
    return out, problems


def validate_system(
    system: SystemDescription, mds: Mapping[str, ModelDescription]
) -> tuple[list[Connection], list[str]]:
    """Check units, parameters and connections against the FMUs' model descriptions.

    Returns the element-wise connections and the list of problems (empty when valid).
    """
    conns, problems = expand_connections(system.connections, mds)
    for unit in system.units.values():
        md = mds.get(unit.name)
        if md is None:
            continue
        variables = {v.name: v for v in md.modelVariables}
        for pname in unit.parameters:
            v = variables.get(pname)
            if v is None:
                problems.append(f"{unit.name}: unknown parameter {pname!r} ({unit.fmu.name})")
            elif v.causality not in ("parameter", "input"):
                problems.append(
                    f"{unit.name}.{pname}: is a {v.causality}, not a parameter or input"
                )
    seen: dict[tuple[str, str], Connection] = {}
    for c in conns:
        sv = {v.name: v for v in mds[c.src_unit].modelVariables}[c.src_var]
        dv = {v.name: v for v in mds[c.dst_unit].modelVariables}[c.dst_var]
        if sv.causality != "output":
            problems.append(f"connection {c}: source is a {sv.causality}, not an output")
        if dv.causality != "input":
            problems.append(f"connection {c}: target is a {dv.causality}, not an input")
        if sv.type != dv.type:
            problems.append(f"connection {c}: type mismatch {sv.type} -> {dv.type}")
        key = (c.dst_unit, c.dst_var)
        if key in seen:
            problems.append(f"connection {c}: input already driven by {seen[key]}")
        seen[key] = c
    return conns, problems
