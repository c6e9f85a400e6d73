"""SSP 1.0 names shared by the exporter and the importer (namespaces, annotations, files)."""

from __future__ import annotations

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
