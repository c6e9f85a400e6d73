"""Every Real variable of the four FMUs declares a unit, and every declared unit except the
dimensionless ones carries its SI base-unit exponents (modelDescription UnitDefinitions)."""

from __future__ import annotations

import pytest
from fmpy import read_model_description

from axir.fmus.build import DECLARATIONS

DIMENSIONLESS = {"1", "dB"}


@pytest.mark.parametrize("name", sorted(DECLARATIONS))
def test_every_real_has_a_unit_with_base_units(fmu_dir, name):
    md = read_model_description(str(fmu_dir / f"{name}.fmu"))
    defs = {u.name: u for u in md.unitDefinitions}
    for v in md.modelVariables:
        if v.type != "Real":
            continue
        unit = v.unit or (v.declaredType.unit if v.declaredType is not None else None)
        assert unit, f"{name}.{v.name} has no unit"
        assert unit in defs, f"{name}.{v.name}: unit {unit!r} not in UnitDefinitions"
        if unit not in DIMENSIONLESS:
            assert defs[unit].baseUnit is not None, f"{name}: unit {unit!r} has no BaseUnit"
