"""Outputs after fmi2ExitInitializationMode are the units' outputs at their initial state
(issue 10 point 4: the TargetGenerator's truth used to read 0, the target at the radar, until
the first fmi2DoStep)."""

from __future__ import annotations

import importlib
import math
from pathlib import Path

import pytest
from test_fmu_all import FMUS, PARAMS, TARGET_AZ, TARGET_EL, TARGET_R, Driver, opened

from axir.fmus.build import DECLARATIONS


def test_target_generator_truth_at_t0(fmu_dir: Path) -> None:
    """Truth = the default trajectory's start (-6000, 12000, 1500) m (written out here from
    models/radar/trajectory.py's documented default, not computed by the code under test);
    beams 0: no pulse has been received, the Doppler filters are empty."""
    with opened(fmu_dir, "TargetGenerator") as inst:
        out = Driver(inst, "TargetGenerator").output_values()
    assert (out["truth.x"], out["truth.y"], out["truth.z"]) == (-6000.0, 12000.0, 1500.0)
    assert out["truth.range"] == pytest.approx(TARGET_R, rel=1e-12)
    assert out["truth.az"] == pytest.approx(TARGET_AZ, rel=1e-12)
    assert out["truth.el"] == pytest.approx(TARGET_EL, rel=1e-12)
    speed = math.hypot(out["truth.vx"], out["truth.vy"], out["truth.vz"])
    assert speed > 50.0, "an aircraft, not a target at rest"
    assert out["truth.range_rate"] != 0.0 and out["truth.snr_db"] > 0.0
    assert all(v == 0.0 for k, v in out.items() if k.startswith("beam."))


@pytest.mark.parametrize("name", FMUS)
def test_initial_outputs_equal_a_model_built_alike(fmu_dir: Path, name: str) -> None:
    """Every output after initialization is finite-or-declared and equals ``model.outputs()``
    of the same model built in process with the same parameters (the FMU does not read start
    values any more)."""
    spec = importlib.import_module(f"axir.fmus.{DECLARATIONS[name]}").SPEC
    model = spec.model(**PARAMS.get(name, {}))
    ref = model.outputs()
    with opened(fmu_dir, name) as inst:
        got = Driver(inst, name).output_values()
    for port in spec.model.OUTPUTS:
        names = port.scalar_names()
        vals = [got[n] for n in names]
        want = ref[port.name].ravel().tolist() if port.shape else [ref[port.name]]
        assert [float(v) for v in vals] == pytest.approx([float(w) for w in want], nan_ok=True), \
            port.name
