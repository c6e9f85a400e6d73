"""Write a scenario as an SSP 1.0 archive (see the package docstring for the decisions)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

from axir.fmus.bundle import write_reproducible_zip
from axir.fmus.model_description import fmi_value_text
from axir.models.system import JACOBI_PARAMETERS, unit_seed

from ..errors import AxirError
from ..fmi import load_model_description
from ..scenario_spec import Scenario
from ..system import expand_connections
from .format import AXIR_ANNOTATION, NS, OSP_ANNOTATION, SSD_NAME

#: [s] communication step of the archive when the scenario's step is variable (the manager's
#: PRI): 1e-4 s, the order of the PRIs (100-112 µs) and the FMUs' DefaultExperiment stepSize.
DEFAULT_STEP = 1e-4


def _typed(var: Any, value: Any, where: str) -> Any:
    """``value`` checked against the FMI type of ``var`` (error names ``where``)."""
    kind = var.type
    if kind == "Boolean":
        if not isinstance(value, (bool, int)):
            raise AxirError(f"{where}: Boolean parameter, got {value!r}")
        return bool(value)
    if kind in ("Integer", "Enumeration"):
        if isinstance(value, bool) or not float(value).is_integer():
            raise AxirError(f"{where}: Integer parameter, got {value!r}")
        return int(value)
    if kind == "Real":
        if isinstance(value, (bool, str)):
            raise AxirError(f"{where}: Real parameter, got {value!r}")
        return float(value)
    return str(value)


def _unit_of(var: Any) -> str | None:
    return var.unit or (var.declaredType.unit if var.declaredType is not None else None)


def _connector(var: Any, kind: str, units: set[str]) -> str:
    t = "Integer" if var.type == "Enumeration" else var.type
    unit = _unit_of(var) if t == "Real" else None
    attr = ""
    if unit:
        units.add(unit)
        attr = f" unit={quoteattr(unit)}"
    return (f"          <ssd:Connector name={quoteattr(var.name)} kind=\"{kind}\">"
            f"<ssc:{t}{attr}/></ssd:Connector>\n")


def _ssv(name: str, params: dict[str, tuple[str, Any]]) -> str:
    out = ['<?xml version="1.0" encoding="UTF-8"?>\n',
           f'<ssv:ParameterSet xmlns:ssv="{NS["ssv"]}" xmlns:ssc="{NS["ssc"]}" '
           f'version="1.0" name={quoteattr(name)} generationTool="axir">\n',
           "  <ssv:Parameters>\n"]
    for pname, (kind, value) in params.items():
        text = quoteattr(fmi_value_text(kind, value))
        out.append(f"    <ssv:Parameter name={quoteattr(pname)}>"
                   f"<ssv:{kind} value={text}/></ssv:Parameter>\n")
    out.append("  </ssv:Parameters>\n</ssv:ParameterSet>\n")
    return "".join(out)


def _units_xml(units: Iterable[str], mds: dict[str, Any]) -> str:
    base: dict[str, Any] = {}
    for md in mds.values():
        for u in md.unitDefinitions:
            base.setdefault(u.name, u.baseUnit)
    out = ["  <ssd:Units>\n"]
    for name in sorted(units):
        b = base.get(name)
        attrs = ""
        if b is not None:
            keys = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
            attrs = "".join(f' {k}="{getattr(b, k)}"' for k in keys if getattr(b, k))
            if b.factor != 1.0:
                attrs += f' factor="{b.factor!r}"'
            if b.offset != 0.0:
                attrs += f' offset="{b.offset!r}"'
        out.append(f"    <ssc:Unit name={quoteattr(name)}><ssc:BaseUnit{attrs}/></ssc:Unit>\n")
    out.append("  </ssd:Units>\n")
    return "".join(out)


def ssp_parameters(scenario: Scenario, mds: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Per unit, the parameter values the archive sets: the scenario's, the derived seeds,
    and the Jacobi values of :data:`~axir.models.system.JACOBI_PARAMETERS`; checked against
    the FMUs' types."""
    out: dict[str, dict[str, Any]] = {}
    for unit, spec in scenario.units.items():
        md = mds[unit]
        variables = {v.name: v for v in md.modelVariables}
        params = dict(spec.get("parameters", {}))
        seed_var = variables.get("seed")
        if seed_var is not None and seed_var.causality == "parameter" and "seed" not in params:
            params["seed"] = unit_seed(scenario.seed, unit)
        for pname, value in JACOBI_PARAMETERS.get(unit, {}).items():
            v = variables.get(pname)
            if v is not None and v.causality == "parameter":
                params[pname] = value
        typed = {}
        for pname, value in params.items():
            v = variables.get(pname)
            if v is None or v.causality not in ("parameter", "input"):
                raise AxirError(f"{unit}: {pname!r} is not a parameter or input of "
                                f"{spec.get('fmu', unit + '.fmu')}")
            typed[pname] = _typed(v, value, f"{unit}.{pname}")
        out[unit] = typed
    return out


def build_ssd(scenario: Scenario, mds: dict[str, Any], params: dict[str, dict[str, Any]],
              step: float, stop: float) -> str:
    """The SystemStructure.ssd text of ``scenario`` (fixed step ``step``, stop ``stop``)."""
    conns, problems = expand_connections(scenario.connections, mds)
    if problems:
        raise AxirError("cannot export: " + "; ".join(problems))
    units: set[str] = set()
    elements = []
    for unit in scenario.order:
        md = mds[unit]
        lines = [f"      <ssd:Component name={quoteattr(unit)} "
                 f'type="application/x-fmu-sharedlibrary" source="resources/{unit}.fmu">\n',
                 "        <ssd:Connectors>\n"]
        for v in md.modelVariables:
            if v.causality in ("input", "output") or (
                    v.causality == "parameter" and v.name in params[unit]):
                lines.append(_connector(v, v.causality, units))
        lines.append("        </ssd:Connectors>\n")
        if params[unit]:
            lines.append("        <ssd:ParameterBindings>\n"
                         "          <ssd:ParameterBinding type=\"application/x-ssp-parameter-set\""
                         f" source=\"resources/{unit}.ssv\"/>\n"
                         "        </ssd:ParameterBindings>\n")
        lines.append("      </ssd:Component>\n")
        elements.append("".join(lines))
    connections = "".join(
        f"      <ssd:Connection startElement={quoteattr(c.src_unit)} "
        f"startConnector={quoteattr(c.src_var)} endElement={quoteattr(c.dst_unit)} "
        f"endConnector={quoteattr(c.dst_var)}/>\n" for c in conns)
    record = "".join(f"        <axir:Record variable={quoteattr(r)}/>\n" for r in scenario.record)
    ns = " ".join(f'xmlns:{p}="{NS[p]}"' for p in ("ssd", "ssc", "ssv", "osp", "axir"))
    desc = f" description={quoteattr(scenario.description)}" if scenario.description else ""
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f"<ssd:SystemStructureDescription {ns} version=\"1.0\" "
        f"name={quoteattr(scenario.name)} generationTool=\"axir\">\n"
        f"  <ssd:System name=\"radar\"{desc}>\n"
        "    <ssd:Elements>\n" + "".join(elements) + "    </ssd:Elements>\n"
        "    <ssd:Connections>\n" + connections + "    </ssd:Connections>\n"
        "  </ssd:System>\n"
        + _units_xml(units, mds) +
        f"  <ssd:DefaultExperiment startTime=\"0.0\" stopTime=\"{float(stop)!r}\">\n"
        "    <ssd:Annotations>\n"
        f"      <ssc:Annotation type=\"{OSP_ANNOTATION}\">\n"
        "        <osp:Algorithm>"
        f"<osp:FixedStepAlgorithm baseStepSize=\"{float(step)!r}\"/></osp:Algorithm>\n"
        "      </ssc:Annotation>\n"
        "    </ssd:Annotations>\n"
        "  </ssd:DefaultExperiment>\n"
        "  <ssd:Annotations>\n"
        f"    <ssc:Annotation type=\"{AXIR_ANNOTATION}\">\n"
        f"      <axir:Run scenario={quoteattr(scenario.name)} seed=\"{scenario.seed}\" "
        f"algorithm=\"jacobi\" decimation=\"{scenario.decimation}\">\n"
        + record +
        "      </axir:Run>\n"
        "    </ssc:Annotation>\n"
        "  </ssd:Annotations>\n"
        "</ssd:SystemStructureDescription>\n"
    )


def export_ssp_archive(scenario: Scenario, fmu_dir: Path, out: Path, *,
                       step: float | None = None, duration: float | None = None,
                       seed: int | None = None) -> Path:
    """Write ``scenario`` as an SSP 1.0 archive ``out`` (see the module docstring).

    Args:
        scenario: the system (units, parameters, connections, record list).
        fmu_dir: where the FMUs named by the scenario are.
        out: the ``.ssp`` file to write.
        step: communication step [s] (default: the scenario's fixed step, else
            :data:`DEFAULT_STEP`).
        duration: stop time [s] (default: the scenario's duration).
        seed: base seed (default: the scenario's).
    """
    scenario = scenario.with_overrides(seed, duration)
    step = step if step is not None else (scenario.step or DEFAULT_STEP)
    if not step > 0:
        raise AxirError(f"--step must be positive, got {step}")
    if round(step * 1e9) < 1:
        raise AxirError(f"--step {step} s is below libcosim's 1 ns time resolution")
    out = Path(out)
    if out.suffix != ".ssp":
        raise AxirError(f"{out}: the output file must end in .ssp")
    system = scenario.system(Path(fmu_dir))
    mds = {}
    for name, spec in system.units.items():
        if not spec.fmu.is_file():
            raise AxirError(f"FMU file not found: {spec.fmu} (unit {name}); "
                            "run `axir build` first or pass --fmu-dir")
        mds[name] = load_model_description(spec.fmu)
    params = ssp_parameters(scenario, mds)
    ssd = build_ssd(scenario, mds, params, step, scenario.duration)
    kinds = {u: {v.name: ("Integer" if v.type == "Enumeration" else v.type)
                 for v in mds[u].modelVariables} for u in mds}
    entries = {SSD_NAME: ssd.encode()}
    for unit in scenario.order:
        entries[f"resources/{unit}.fmu"] = system.units[unit].fmu.read_bytes()
        if params[unit]:
            typed = {p: (kinds[unit][p], v) for p, v in params[unit].items()}
            entries[f"resources/{unit}.ssv"] = _ssv(f"{scenario.name}.{unit}", typed).encode()
    out.parent.mkdir(parents=True, exist_ok=True)
    write_reproducible_zip(out, entries, first=(SSD_NAME,), stored=lambda n: n.endswith(".fmu"))
    return out


__all__ = ["DEFAULT_STEP", "build_ssd", "export_ssp_archive", "ssp_parameters"]
