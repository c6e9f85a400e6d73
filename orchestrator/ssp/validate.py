"""Schema check of an SSP archive against the SSP 1.0 XML schemas fmpy ships."""

from __future__ import annotations

import zipfile
from pathlib import Path

from .format import SSD_NAME


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
