"""SSP 1.0 export and import: one archive drives libcosim, other SSP tools and our master.

``axir export-ssp [SCENARIO] -o radar.ssp`` writes an SSP 1.0 archive (Modelica Association
"System Structure and Parameterization" 1.0, schemas shipped in ``fmpy/ssp/schema``)::

    SystemStructure.ssd          the system: components, connectors, connections, units,
                                 DefaultExperiment (start, stop, fixed step)
    resources/<Unit>.fmu         the FMUs, byte for byte
    resources/<Unit>.ssv         one SSP parameter set per component (the scenario's values)

Decisions (documented in docs/other_tools.md):

- **Fixed step, Jacobi.** SSP has no variable step driven by an output, and libcosim's
  ``fixed_step_algorithm`` steps every FMU from the outputs at t, then transfers (Jacobi). The
  archive therefore describes a fixed-step Jacobi run: the step is the scenario's fixed step,
  else ``--step`` (default :data:`DEFAULT_STEP`); it is written as the OSP annotation
  ``osp:FixedStepAlgorithm baseStepSize`` in the DefaultExperiment (libcosim reads it).
- **Jacobi parameters.** Parameters that depend on the master's order get their Jacobi value
  (:data:`JACOBI_PARAMETERS`: the Tracker's ``gate_latency`` is 2 with a Jacobi master).
- **Seeds are explicit.** Every unit with a ``seed`` parameter gets the per-unit seed our
  master derives (:func:`~.scenario.unit_seed`), written into its ``.ssv``, so a third-party
  master draws the same random numbers.
- **One ``.ssv`` per component.** libcosim applies component-level parameter bindings only
  (names = the FMU's variable names); a system-level set with prefixed names would be ignored.
- **Scalar connections.** Array connections are expanded element-wise (FMI 2.0 structured
  names, ``beam.up[3,2]``); every component declares a connector for each of its inputs,
  outputs and set parameters, with its SSP type and unit.
- **Namespace prefixes** are the conventional ``ssd``/``ssc``/``ssv``/``osp``: libcosim's
  parser (boost property_tree) matches element names with their prefixes literally.
- An ``org.axir.run`` annotation keeps what SSP cannot say (scenario name, base seed, recorded
  variables, decimation, the master algorithm); other tools ignore it.

:func:`load_ssp` reads such an archive (or any SSP 1.0 ``.ssp``/``.ssd`` within the
supported subset: FMU components, component-level parameter sets, connections without
transformations) into the same :class:`~.scenario.Scenario` a TOML file gives, so
``axir run radar.ssp`` runs the file our master and libcosim both read.
"""

from __future__ import annotations

import hashlib
import shutil
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import click

from .errors import AxirError, ScenarioError
from .fmi import load_model_description
from .scenario import DEFAULT_RECORD, Scenario, load_scenario, unit_seed
from .system import Connection, expand_connections

NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
    "axir": "urn:axir:ssp-annotation:1",
}
OSP_ANNOTATION = "com.opensimulationplatform"
AXIR_ANNOTATION = "org.axir.run"
SSD_NAME = "SystemStructure.ssd"
#: [s] communication step of the archive when the scenario's step is variable (the manager's
#: PRI): 1e-4 s, the order of the PRIs (100-112 µs) and the FMUs' DefaultExperiment stepSize.
DEFAULT_STEP = 1e-4
#: parameter values a Jacobi master needs (the archive always describes a Jacobi run): the
#: Tracker's beams were formed with the gate it output two steps earlier (models/tracker.py).
JACOBI_PARAMETERS = {"gate_latency": 2}
_FMI_TYPES = ("Real", "Integer", "Boolean", "String")
_EPOCH = (1980, 1, 1, 0, 0, 0)  # fixed zip timestamps: same inputs -> same archive bytes
_EXTRACTED: dict[str, Path] = {}


# ----------------------------------------------------------------------------- export
def _fmt(kind: str, value: Any) -> str:
    """An SSP attribute value of FMI type ``kind`` (Reals round-trip exactly)."""
    if kind == "Real":
        return repr(float(value))
    if kind == "Integer":
        return str(int(value))
    if kind == "Boolean":
        return "true" if value else "false"
    return str(value)


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
        out.append(f"    <ssv:Parameter name={quoteattr(pname)}>"
                   f"<ssv:{kind} value={quoteattr(_fmt(kind, value))}/></ssv:Parameter>\n")
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
    and the Jacobi values of :data:`JACOBI_PARAMETERS`; checked against the FMUs' types."""
    out: dict[str, dict[str, Any]] = {}
    for unit, spec in scenario.units.items():
        md = mds[unit]
        variables = {v.name: v for v in md.modelVariables}
        params = dict(spec.get("parameters", {}))
        seed_var = variables.get("seed")
        if seed_var is not None and seed_var.causality == "parameter" and "seed" not in params:
            params["seed"] = unit_seed(scenario.seed, unit)
        for pname, value in JACOBI_PARAMETERS.items():
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


def _write(z: zipfile.ZipFile, name: str, data: bytes, compress: bool = True) -> None:
    info = zipfile.ZipInfo(name, date_time=_EPOCH)
    info.compress_type = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
    info.external_attr = 0o644 << 16
    z.writestr(info, data)


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
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".part")
    with zipfile.ZipFile(tmp, "w") as z:
        _write(z, SSD_NAME, ssd.encode())
        for unit in scenario.order:
            _write(z, f"resources/{unit}.fmu", system.units[unit].fmu.read_bytes(),
                   compress=False)
            if params[unit]:
                typed = {p: (kinds[unit][p], v) for p, v in params[unit].items()}
                _write(z, f"resources/{unit}.ssv", _ssv(f"{scenario.name}.{unit}", typed).encode())
    tmp.replace(out)
    return out


# ----------------------------------------------------------------------------- validation
def validate_ssp(path: Path) -> list[str]:
    """Schema problems of an archive's SystemStructure.ssd and .ssv files (empty: valid),
    checked against the SSP 1.0 XML schemas fmpy ships (``fmpy/ssp/schema``)."""
    from fmpy.ssp import ssd as fmpy_ssd
    from lxml import etree

    schema_dir = Path(fmpy_ssd.__file__).parent / "schema"
    problems = []
    with zipfile.ZipFile(path) as z:
        names = z.namelist()
        if SSD_NAME not in names:
            return [f"{path}: no {SSD_NAME} at the archive root"]
        for name in names:
            if name == SSD_NAME:
                xsd = "SystemStructureDescription.xsd"
            elif name.endswith(".ssv"):
                xsd = "SystemStructureParameterValues.xsd"
            else:
                continue
            schema = etree.XMLSchema(file=str(schema_dir / xsd))
            root = etree.fromstring(z.read(name))
            if not schema.validate(root):
                problems += [f"{name}:{e.line}: {e.message}" for e in schema.error_log]
    return problems


# ----------------------------------------------------------------------------- import
def _q(prefix: str, tag: str) -> str:
    return f"{{{NS[prefix]}}}{tag}"


def _extract(path: Path) -> Path:
    """Extract an ``.ssp`` once per content (cached per process) and return the directory."""
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    cached = _EXTRACTED.get(digest)
    if cached is not None and cached.is_dir():
        return cached
    target = Path(tempfile.mkdtemp(prefix=f"axir_ssp_{path.stem}_"))
    try:
        with zipfile.ZipFile(path) as z:
            for name in z.namelist():
                if name.startswith("/") or ".." in Path(name).parts:
                    raise ScenarioError(f"{path}: unsafe member name {name!r}")
            z.extractall(target)
    except zipfile.BadZipFile as e:
        shutil.rmtree(target, ignore_errors=True)
        raise ScenarioError(f"{path} is not an SSP archive (not a zip file): {e}") from None
    _EXTRACTED[digest] = target
    return target


def _parse_value(kind: str, text: str | None, where: str) -> Any:
    if text is None:
        raise ScenarioError(f"{where}: missing value")
    try:
        if kind == "Real":
            return float(text)
        if kind in ("Integer", "Enumeration"):
            return int(text)
        if kind == "Boolean":
            if text.strip() in ("true", "1"):
                return True
            if text.strip() in ("false", "0"):
                return False
            raise ValueError(text)
    except ValueError:
        raise ScenarioError(f"{where}: not a valid {kind} value: {text!r}") from None
    return text


def _parameter_set(root: ET.Element, where: str) -> dict[str, Any]:
    params: dict[str, Any] = {}
    for p in root.iterfind("ssv:Parameters/ssv:Parameter", {"ssv": NS["ssv"]}):
        name = p.get("name")
        if not name:
            raise ScenarioError(f"{where}: a Parameter has no name")
        for kind in ("Real", "Integer", "Boolean", "String", "Enumeration"):
            e = p.find(_q("ssv", kind))
            if e is not None:
                params[name] = _parse_value(kind, e.get("value"), f"{where}: {name}")
                break
        else:
            raise ScenarioError(f"{where}: parameter {name!r} has an unsupported type")
    return params


def _read_xml(path: Path, what: str) -> ET.Element:
    if not path.is_file():
        raise ScenarioError(f"{what} not found: {path}")
    try:
        return ET.parse(path).getroot()
    except ET.ParseError as e:
        raise ScenarioError(f"{path}: malformed XML: {e}") from None


def load_ssp(ref: str | Path) -> Scenario:
    """An SSP archive (``.ssp``), a system description (``.ssd``) or the directory of an
    extracted archive as a :class:`Scenario`.

    Supported subset: one system of FMU components (sources relative to the SSD), their
    parameter bindings (``.ssv`` files or inline parameter sets), scalar connections between
    components without transformations, a DefaultExperiment starting at 0 with an
    ``osp:FixedStepAlgorithm`` step. Anything else is a :class:`ScenarioError` naming it.
    """
    path = Path(ref)
    if not path.exists():
        raise ScenarioError(f"SSP file not found: {path}")
    if path.suffix == ".ssp" or path.is_dir():
        ssd_path = (_extract(path) if path.is_file() else path) / SSD_NAME
        if not ssd_path.is_file():
            raise ScenarioError(f"{path}: no {SSD_NAME} at the archive root")
    else:
        ssd_path = path
    where = str(path)
    root = _read_xml(ssd_path, "system structure description")
    if root.tag != _q("ssd", "SystemStructureDescription"):
        raise ScenarioError(f"{where}: not an SSP 1.0 SystemStructureDescription "
                            f"(root element {root.tag})")
    base = ssd_path.parent
    system = root.find(_q("ssd", "System"))
    if system is None:
        raise ScenarioError(f"{where}: no ssd:System")
    units: dict[str, dict[str, Any]] = {}
    order: list[str] = []
    connectors: dict[str, set[str]] = {}
    elements = system.find(_q("ssd", "Elements"))
    for el in list(elements) if elements is not None else []:
        name = el.get("name")
        if el.tag != _q("ssd", "Component"):
            raise ScenarioError(f"{where}: element {name!r}: only FMU components are supported "
                                f"(got {el.tag.rpartition('}')[2]})")
        src = el.get("source") or ""
        if "://" in src or not src.endswith(".fmu"):
            raise ScenarioError(f"{where}: component {name}: source {src!r} is not a relative "
                                ".fmu path")
        fmu = (base / src).resolve()
        if not fmu.is_file():
            raise ScenarioError(f"{where}: component {name}: FMU not found: {src}")
        params: dict[str, Any] = {}
        for b in el.iterfind("ssd:ParameterBindings/ssd:ParameterBinding", NS):
            if b.get("prefix"):
                raise ScenarioError(f"{where}: component {name}: parameter binding prefixes "
                                    "are not supported")
            if b.find(_q("ssd", "ParameterMapping")) is not None:
                raise ScenarioError(f"{where}: component {name}: parameter mappings are not "
                                    "supported")
            bsrc = b.get("source")
            if bsrc:
                if b.get("sourceBase", "SSD") != "SSD":
                    raise ScenarioError(f"{where}: component {name}: sourceBase "
                                        f"{b.get('sourceBase')!r} is not supported")
                ssv = _read_xml(base / bsrc, f"parameter set of {name}")
                params.update(_parameter_set(ssv, f"{where}: {bsrc}"))
            else:
                inline = b.find("ssd:ParameterValues/ssv:ParameterSet", NS)
                if inline is not None:
                    params.update(_parameter_set(inline, f"{where}: {name} parameters"))
        units[name] = {"fmu": str(fmu), "parameters": params}
        order.append(name)
        connectors[name] = {c.get("name") for c in el.iterfind("ssd:Connectors/ssd:Connector",
                                                                 NS)}
    if not units:
        raise ScenarioError(f"{where}: the system has no components")
    conns: list[Connection] = []
    for c in system.iterfind("ssd:Connections/ssd:Connection", NS):
        se, sc_, ee, ec = (c.get(k) for k in ("startElement", "startConnector", "endElement",
                                               "endConnector"))
        label = f"connection {se}.{sc_} -> {ee}.{ec}"
        if se is None or ee is None:
            raise ScenarioError(f"{where}: {label}: connections to the system boundary are not "
                                "supported")
        for unit, conn in ((se, sc_), (ee, ec)):
            if unit not in units:
                raise ScenarioError(f"{where}: {label}: no component {unit!r}")
            if connectors[unit] and conn not in connectors[unit]:
                raise ScenarioError(f"{where}: {label}: component {unit} declares no connector "
                                    f"{conn!r}")
        transform = [e.tag.rpartition("}")[2] for e in c if e.tag.endswith("Transformation")]
        if transform:
            raise ScenarioError(f"{where}: {label}: transformations are not supported "
                                f"({', '.join(transform)})")
        conns.append(Connection(se, sc_, ee, ec))
    step, stop = None, 10.0
    de = root.find(_q("ssd", "DefaultExperiment"))
    if de is not None:
        if float(de.get("startTime", 0.0)) != 0.0:
            raise ScenarioError(f"{where}: DefaultExperiment startTime "
                                f"{de.get('startTime')} (only 0 is supported)")
        stop = float(de.get("stopTime", stop))
        for a in de.iterfind("ssd:Annotations/ssc:Annotation", NS):
            if a.get("type") == OSP_ANNOTATION:
                fs = a.find("osp:Algorithm/osp:FixedStepAlgorithm", NS)
                if fs is not None:
                    step = float(fs.get("baseStepSize"))
    if step is None or not step > 0:
        raise ScenarioError(f"{where}: no fixed step: add <osp:FixedStepAlgorithm "
                            "baseStepSize=...> to the DefaultExperiment annotations")
    run = root.find(f"ssd:Annotations/ssc:Annotation[@type='{AXIR_ANNOTATION}']/axir:Run", NS)
    seed, decimation, algorithm = 1, 1, "jacobi"
    name = root.get("name") or path.stem
    record = [r for r in DEFAULT_RECORD if r.partition(".")[0] in units]
    if run is not None:
        seed = int(run.get("seed", seed))
        decimation = int(run.get("decimation", decimation))
        algorithm = run.get("algorithm", algorithm)
        if algorithm not in ("jacobi", "gauss-seidel"):
            raise ScenarioError(f"{where}: {AXIR_ANNOTATION}: unknown algorithm {algorithm!r}")
        rec = [r.get("variable") for r in run.iterfind("axir:Record", NS)]
        if rec:
            record = rec
        name = run.get("scenario", name)
    for unit, spec in units.items():
        # a seed equal to the one our master derives from the base seed is dropped, so that
        # `axir run radar.ssp --seed N` derives new per-unit seeds (same results otherwise)
        if spec["parameters"].get("seed") == unit_seed(seed, unit):
            del spec["parameters"]["seed"]
    return Scenario(
        name=name,
        source=str(path),
        description=system.get("description", ""),
        duration=stop,
        seed=seed,
        algorithm=algorithm,
        order=order,
        step=step,
        decimation=decimation,
        record=record,
        units=units,
        connections=conns,
    )


# ----------------------------------------------------------------------------- libcosim
def run_libcosim(path: Path, variables: list[str], duration: float | None = None,
                 ) -> tuple[Any, Any]:
    """Run an SSP archive in libcosim (PyPI ``libcosimpy``, a test dependency) and record
    ``variables`` (``"Unit.variable"``) after every step.

    libcosim reads the archive itself (its SSP loader: components, ``.ssv`` parameter sets,
    connections, the ``osp:FixedStepAlgorithm`` step) and runs its fixed-step algorithm:
    every FMU steps from the outputs at t, then outputs are transferred (Jacobi).

    Returns ``(t, data)``: the times [s] after each step (numpy array, n) and the recorded
    values (n × len(variables)). The execution (instances and FMU libraries) is destroyed
    before returning.
    """
    import numpy as np

    try:
        from libcosimpy.CosimEnums import CosimVariableType
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
    except ImportError:  # pragma: no cover - libcosimpy is a test dependency
        raise AxirError("libcosim is not installed: pip install libcosimpy") from None
    sc = load_ssp(path)
    stop = sc.duration if duration is None else duration
    step_ns = round(sc.step * 1e9)
    n = round(stop * 1e9) // step_ns
    log_output_level(CosimLogLevel.WARNING)
    ex = CosimExecution.from_ssp_file(str(Path(path).resolve()))
    try:
        obs = CosimObserver.create_last_value()
        ex.add_observer(obs)
        reads: dict[tuple[int, Any], tuple[list[int], list[int]]] = {}
        for col, ref in enumerate(variables):
            unit, _, var = ref.partition(".")
            idx = ex.slave_index_from_instance_name(unit)
            if idx is None:
                raise AxirError(f"libcosim: no instance {unit!r} in {path}")
            found = {v.name.decode(): v for v in ex.slave_variables(idx)}.get(var)
            if found is None:
                raise AxirError(f"libcosim: {unit} has no variable {var!r}")
            vrs, cols = reads.setdefault((idx, found.type), ([], []))
            vrs.append(found.reference)
            cols.append(col)
        getters = {CosimVariableType.REAL.value: obs.last_real_values,
                   CosimVariableType.INTEGER.value: obs.last_integer_values,
                   CosimVariableType.BOOLEAN.value: obs.last_boolean_values}
        plan = [(getters[kind], idx, vrs, cols) for (idx, kind), (vrs, cols) in reads.items()]
        data = np.empty((n, len(variables)))
        t = np.empty(n)
        for k in range(n):
            if not ex.step(1):
                raise AxirError(f"libcosim: step {k + 1} failed: {ex.status()}")
            for get, idx, vrs, cols in plan:
                data[k, cols] = get(idx, vrs)
            t[k] = ex.status().current_time / 1e9
    finally:
        del ex  # cosim_execution_destroy: frees the instances and unloads the FMUs
    return t, data


# ----------------------------------------------------------------------------- CLI
@click.command("export-ssp")
@click.argument("scenario", required=False)
@click.option("-o", "--out", "out", type=click.Path(dir_okay=False, path_type=Path),
              help="The .ssp file to write (default: <scenario name>.ssp).")
@click.option("--fmu-dir", default=None, type=click.Path(file_okay=False, path_type=Path),
              help="Where the FMUs are (default: dist, or $AXIR_FMU_DIR).")
@click.option("--step", type=click.FloatRange(min=0, min_open=True),
              help=f"Fixed communication step [s] (default: the scenario's fixed step, else "
                   f"{DEFAULT_STEP}).")
@click.option("--duration", type=click.FloatRange(min=0, min_open=True),
              help="Stop time [s] (default: the scenario's duration).")
@click.option("--seed", type=click.IntRange(min=0), help="Base seed (overrides the scenario).")
def export_ssp(scenario: str | None, out: Path | None, fmu_dir: Path | None,
               step: float | None, duration: float | None, seed: int | None) -> None:
    """Write SCENARIO (default: the closed loop) as an SSP 1.0 archive: SystemStructure.ssd,
    the FMUs and one .ssv parameter set per unit under resources/, a fixed-step Jacobi
    DefaultExperiment. Runs in libcosim and with `axir run OUT.ssp`."""
    from .cli import DEFAULT_FMU_DIR

    sc = load_scenario(scenario)
    out = out or Path(f"{sc.name}.ssp")
    path = export_ssp_archive(sc, fmu_dir or Path(DEFAULT_FMU_DIR), out, step=step,
                              duration=duration, seed=seed)
    problems = validate_ssp(path)
    if problems:
        raise AxirError(f"{path}: written archive fails the SSP 1.0 schemas: "
                        + "; ".join(problems[:5]))
    click.echo(f"wrote {path} (SSP 1.0, validated against the SSP 1.0 schemas)")


__all__ = ["DEFAULT_STEP", "export_ssp", "export_ssp_archive", "load_ssp", "validate_ssp"]
