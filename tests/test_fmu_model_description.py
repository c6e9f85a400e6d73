"""modelDescription.xml writer (fmus/model_description.py): valid for fmpy, units everywhere."""

from __future__ import annotations

from pathlib import Path

from fmpy import read_model_description
from fmpy.validation import validate_fmu
from fmu_standin import SPEC

from axir.fmus.model_description import model_description_xml


def test_standin_model_description_validates(tmp_path: Path) -> None:
    (tmp_path / "modelDescription.xml").write_text(
        model_description_xml(SPEC, "{00000000-0000-0000-0000-000000000000}", "0", "test"))
    assert validate_fmu(str(tmp_path)) == []
    md = read_model_description(str(tmp_path))
    reals = [v for v in md.modelVariables if v.type == "Real"]
    assert all(v.unit for v in reals)
    assert all(v.variability == "discrete" for v in md.modelVariables
               if v.type != "Real" and v.causality != "parameter")
