"""Generate ``docs/interfaces.md`` from the four FMUs' modelDescription.xml.

The modelDescription is the source of truth for the public interface (SYSTEM.md): this module
only renders it. Per FMU: parameters (default, unit, description), inputs and outputs (unit,
description); structured arrays are collapsed to one line (``beam.up[1..16,1..3]``).

Only interface facts are written (no GUID, no build hash, no tool version), so the file changes
only when an interface changes::

    python -m axir.orchestrator.docs --fmu-dir dist --out docs/interfaces.md
    python -m axir.orchestrator.docs --fmu-dir dist --out docs/interfaces.md --check
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from fmpy.model_description import ModelDescription, ScalarVariable

from axir.models.system import UNITS

from .errors import AxirError
from .fmi import load_model_description

REGENERATE = "python -m axir.orchestrator.docs --fmu-dir DIR --out docs/interfaces.md"
_ELEMENT = re.compile(r"^(?P<base>.+)\[(?P<idx>\d+(?:,\d+)*)\]$")


@dataclass
class Row:
    """One documented variable or one collapsed array."""

    name: str
    type: str
    causality: str
    variability: str
    unit: str
    start: str
    description: str
    count: int = 1


def _unit(v: ScalarVariable) -> str:
    if v.type != "Real":
        return ""
    return v.unit or (v.declaredType.unit if v.declaredType is not None else "") or ""


def _start(v: ScalarVariable) -> str:
    if v.start is None:
        return ""
    if v.type == "Boolean":
        return str(v.start).lower()
    return str(v.start)


def _collapse_name(base: str, indices: list[tuple[int, ...]]) -> str:
    """``base[1..16,1..3]`` for a full rectangular block, else ``base[…]`` with the count."""
    dims = len(indices[0])
    if any(len(i) != dims for i in indices):
        return f"{base}[…] ({len(indices)} elements)"
    lo = [min(i[d] for i in indices) for d in range(dims)]
    hi = [max(i[d] for i in indices) for d in range(dims)]
    full = 1
    for a, b in zip(lo, hi, strict=True):
        full *= b - a + 1
    if full != len(set(indices)):
        return f"{base}[…] ({len(indices)} elements)"
    return base + "[" + ",".join(f"{a}..{b}" if a != b else f"{a}" for a, b in
                                 zip(lo, hi, strict=True)) + "]"


def rows(md: ModelDescription) -> list[Row]:
    """The variables of ``md`` in modelDescription order, arrays collapsed to one row
    (placed where their first element is; the description of the first element is used)."""
    out: list[Row] = []
    arrays: dict[tuple[str, str], tuple[Row, list[tuple[int, ...]]]] = {}
    for v in md.modelVariables:
        m = _ELEMENT.match(v.name)
        if m is None:
            out.append(Row(v.name, v.type, v.causality, v.variability or "", _unit(v),
                           _start(v), v.description or ""))
            continue
        key = (m["base"], v.causality)
        idx = tuple(int(x) for x in m["idx"].split(","))
        if key not in arrays:
            row = Row(m["base"], v.type, v.causality, v.variability or "", _unit(v),
                      _start(v), v.description or "")
            arrays[key] = (row, [])
            out.append(row)
        row, idxs = arrays[key]
        idxs.append(idx)
        if _start(v) != row.start:
            row.start = "(varies)"
        if _unit(v) != row.unit:
            row.unit = "(varies)"
    for row, idxs in arrays.values():
        row.name = _collapse_name(row.name, idxs)
        row.count = len(idxs)
    return out


def _cell(text: str) -> str:
    text = " ".join(str(text).split())
    return text.replace("\\", "\\\\").replace("|", "\\|")


def _code(text: str) -> str:
    if not text:
        return ""
    text = " ".join(str(text).split()).replace("|", "\\|")
    return f"`` {text} ``" if "`" in text else f"`{text}`"


def fmu_section(md: ModelDescription, file_name: str) -> str:
    """Markdown section of one FMU."""
    cs = md.coSimulation
    rs = rows(md)
    lines = [f"## {md.modelName} (`{file_name}`)", ""]
    if md.description:
        lines += [_cell(md.description), ""]
    n_scalar = len(md.modelVariables)
    caps = []
    if cs is not None:
        def b(x: object) -> str:
            return str(bool(x)).lower()

        caps = [f"model identifier `{cs.modelIdentifier}`",
                f"variable communication step: {b(cs.canHandleVariableCommunicationStepSize)}",
                f"get/set FMU state: {b(cs.canGetAndSetFMUstate)}",
                f"serialize FMU state: {b(cs.canSerializeFMUstate)}"]
    de = md.defaultExperiment
    if de is not None and de.stepSize is not None:
        caps.append(f"default step {de.stepSize} s")
    lines += [f"FMI {md.fmiVersion} co-simulation; {n_scalar} scalar variables; "
              + "; ".join(caps) + ".", ""]

    params = [r for r in rs if r.causality == "parameter"]
    lines += ["### Parameters", ""]
    if params:
        lines += ["| name | type | variability | default | unit | description |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| `{r.name}` | {r.type} | {r.variability} | {_code(r.start)} | "
                  f"{_cell(r.unit)} | {_cell(r.description)} |" for r in params]
    else:
        lines.append("(none)")
    lines.append("")
    for title, causality in (("Inputs", "input"), ("Outputs", "output")):
        sel = [r for r in rs if r.causality == causality]
        lines += [f"### {title}", ""]
        if sel:
            lines += ["| name | type | unit | start | description |", "|---|---|---|---|---|"]
            lines += [f"| `{r.name}` | {r.type} | {_cell(r.unit)} | {_code(r.start)} | "
                      f"{_cell(r.description)} |" for r in sel]
        else:
            lines.append("(none)")
        lines.append("")
    others = [r for r in rs if r.causality not in ("parameter", "input", "output")]
    if others:
        lines += ["### Other variables", "", "| name | causality | type | unit | description |",
                  "|---|---|---|---|---|"]
        lines += [f"| `{r.name}` | {r.causality} | {r.type} | {_cell(r.unit)} | "
                  f"{_cell(r.description)} |" for r in others]
        lines.append("")
    return "\n".join(lines)


def render(fmu_dir: Path, names: Sequence[str] = UNITS) -> str:
    """The whole ``interfaces.md`` for the FMUs ``<fmu_dir>/<name>.fmu``."""
    fmu_dir = Path(fmu_dir)
    parts = [
        "# axir FMU interfaces",
        "",
        "<!-- Generated from the FMUs' modelDescription.xml by axir.orchestrator.docs; "
        "do not edit. -->",
        f"<!-- Regenerate: {REGENERATE} -->",
        "",
        "Generated from each FMU's `modelDescription.xml` (the source of truth, see "
        "SYSTEM.md). Arrays use FMI 2.0 structured names, 1-based, and are shown collapsed: "
        "`beam.up[1..16,1..3]` stands for `beam.up[1,1]` … `beam.up[16,3]` (range bin r, "
        "Doppler filter f). Units are SI; Integer and Boolean variables carry no unit in "
        "FMI 2.0 (their range is in the description). Value references are not part of the "
        "interface: connect by name.",
        "",
        "| FMU | parameters | inputs | outputs | scalar variables |",
        "|---|---|---|---|---|",
    ]
    sections = []
    for name in names:
        path = fmu_dir / f"{name}.fmu"
        if not path.is_file():
            raise AxirError(f"FMU file not found: {path} (build with `axir build --out "
                            f"{fmu_dir}`)")
        md = load_model_description(path)
        count = {c: sum(1 for v in md.modelVariables if v.causality == c)
                 for c in ("parameter", "input", "output")}
        parts.append(f"| [{md.modelName}](#{md.modelName.lower()}-{name.lower()}fmu) | "
                     f"{count['parameter']} | {count['input']} | {count['output']} | "
                     f"{len(md.modelVariables)} |")
        sections.append(fmu_section(md, path.name))
    parts.append("")
    return "\n".join(parts + sections).rstrip("\n") + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m axir.orchestrator.docs",
                                 description="Generate docs/interfaces.md from the FMUs.")
    ap.add_argument("--fmu-dir", default="dist", type=Path, help="where the four FMUs are")
    ap.add_argument("--out", default=Path("docs/interfaces.md"), type=Path,
                    help="output Markdown file ('-' for stdout)")
    ap.add_argument("--check", action="store_true",
                    help="do not write; exit 1 if --out differs from the generated text")
    args = ap.parse_args(argv)
    try:
        text = render(args.fmu_dir)
    except AxirError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if str(args.out) == "-":
        sys.stdout.write(text)
        return 0
    if args.check:
        current = args.out.read_text(encoding="utf-8") if args.out.is_file() else None
        if current != text:
            print(f"{args.out} is out of date; regenerate with: {REGENERATE}", file=sys.stderr)
            return 1
        print(f"{args.out} is up to date")
        return 0
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text, encoding="utf-8", newline="\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
