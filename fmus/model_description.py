"""The modelDescription.xml of an axir FMU, written from its :class:`~.spec.FmuSpec`
(build time only, used by :mod:`axir.fmus.build`; not bundled into the FMUs).

Deterministic (no timestamp): units with their SI base units (:mod:`.units`), descriptions,
value references in :func:`~.spec.layout` order, ModelStructure without direct feedthrough
(outputs change only in ``fmi2DoStep``), the FMU-state capabilities.
"""

from __future__ import annotations

from typing import Any
from xml.sax.saxutils import quoteattr

from .spec import LOG_CATEGORIES, FmuSpec, layout
from .units import BASE_UNITS


def _unit_xml(name: str) -> str:
    base = BASE_UNITS.get(name)
    if not base:
        return f"    <Unit name={quoteattr(name)}/>\n"
    attrs = " ".join(f'{k}="{v}"' for k, v in base.items())
    return f"    <Unit name={quoteattr(name)}>\n      <BaseUnit {attrs}/>\n    </Unit>\n"


def fmi_value_text(kind: str, value: Any) -> str:
    """The XML attribute text of an FMI value of type ``kind`` (Reals round-trip exactly)."""
    if kind == "Real":
        return repr(float(value))
    if kind == "Integer":
        return str(int(value))
    if kind == "Boolean":
        return "true" if value else "false"
    return str(value)


def model_description_xml(spec: FmuSpec, guid: str, version: str, tool: str) -> str:
    """The complete, deterministic modelDescription.xml of ``spec`` (no timestamp)."""
    rows = layout(spec)
    units = sorted({r.unit for r in rows if r.unit})
    out = ['<?xml version="1.0" encoding="UTF-8"?>\n']
    attrs = {
        "fmiVersion": "2.0",
        "modelName": spec.name,
        "guid": guid,
        "description": spec.description or spec.name,
        "version": version,
        "generationTool": tool,
        "variableNamingConvention": "structured",
        "numberOfEventIndicators": "0",
    }
    out.append("<fmiModelDescription\n" + "\n".join(
        f"  {k}={quoteattr(v)}" for k, v in attrs.items()) + ">\n")
    cs = {
        "modelIdentifier": spec.name,
        "needsExecutionTool": "true",
        "canHandleVariableCommunicationStepSize": "true",
        "canInterpolateInputs": "false",
        "maxOutputDerivativeOrder": "0",
        "canRunAsynchronuously": "false",
        "canBeInstantiatedOnlyOncePerProcess": "false",
        "canNotUseMemoryManagementFunctions": "true",
        "canGetAndSetFMUstate": "true",
        "canSerializeFMUstate": "true",
        "providesDirectionalDerivative": "false",
    }
    out.append("  <CoSimulation\n" + "\n".join(
        f"    {k}={quoteattr(v)}" for k, v in cs.items()) + "/>\n")
    out.append("  <UnitDefinitions>\n")
    out += [_unit_xml(u) for u in units]
    out.append("  </UnitDefinitions>\n")
    out.append("  <LogCategories>\n")
    for cat, doc in LOG_CATEGORIES.items():
        out.append(f"    <Category name={quoteattr(cat)} description={quoteattr(doc)}/>\n")
    out.append("  </LogCategories>\n")
    if spec.default_step is not None:
        out.append(f'  <DefaultExperiment startTime="0.0" stepSize="{spec.default_step!r}"/>\n')
    out.append("  <ModelVariables>\n")
    for vr, r in enumerate(rows):
        a = [f"name={quoteattr(r.name)}", f'valueReference="{vr}"',
             f"description={quoteattr(r.description)}", f'causality="{r.causality}"',
             f'variability="{r.variability}"']
        if r.initial:
            a.append(f'initial="{r.initial}"')
        t = []
        if r.unit:
            t.append(f"unit={quoteattr(r.unit)}")
        if r.vmin is not None:
            t.append(f'min="{fmi_value_text(r.kind, r.vmin)}"')
        if r.vmax is not None:
            t.append(f'max="{fmi_value_text(r.kind, r.vmax)}"')
        if r.start is not None:
            t.append(f"start={quoteattr(fmi_value_text(r.kind, r.start))}")
        out.append(f"    <!-- {vr + 1} -->\n    <ScalarVariable {' '.join(a)}>\n"
                   f"      <{r.kind} {' '.join(t)}/>\n    </ScalarVariable>\n")
    out.append("  </ModelVariables>\n  <ModelStructure>\n")
    outs = [i + 1 for i, r in enumerate(rows) if r.causality == "output"]
    if outs:
        # Outputs change only in fmi2DoStep: no direct feedthrough from inputs.
        out.append("    <Outputs>\n")
        out += [f'      <Unknown index="{i}" dependencies=""/>\n' for i in outs]
        out.append("    </Outputs>\n")
    init = [i + 1 for i, r in enumerate(rows)
            if r.causality == "output" and r.initial in ("approx", "calculated")]
    if init:
        pars = " ".join(str(i + 1) for i, r in enumerate(rows) if r.causality == "parameter")
        out.append("    <InitialUnknowns>\n")
        out += [f'      <Unknown index="{i}" dependencies="{pars}"/>\n' for i in init]
        out.append("    </InitialUnknowns>\n")
    out.append("  </ModelStructure>\n</fmiModelDescription>\n")
    return "".join(out)
