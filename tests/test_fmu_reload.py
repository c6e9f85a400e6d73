"""An FMU instantiated again after the host deleted the folder of its first extraction
(fmus/digest.py: add_bundle_root). fmpy's ``simulate_fmu`` extracts into a temporary folder
and removes it after the run; the bundled package stays imported in the process, so a module
the bundle imports only on demand (the IMM filter) was looked up in the deleted folder:
``fmi2ExitInitializationMode`` failed with "No module named '_axir_….models.filters.imm'"
(found by the seed-002 reproduction, whose Dask workers keep the package between campaigns).
Runs in its own process: FMUs share the interpreter's ``sys.modules``."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytest.importorskip("filterpy")

SCRIPT = textwrap.dedent("""
    import sys
    from fmpy import simulate_fmu
    fmu = sys.argv[1]
    imm = {"filter_x": "imm", "filter_y": "imm", "filter_z": "imm"}
    # 1: default filters, extracted into a temporary folder removed after the run
    simulate_fmu(fmu, stop_time=0.001, output_interval=1e-4)
    # 2: a new extraction; the IMM filter is imported now, for the first time
    r = simulate_fmu(fmu, stop_time=0.001, output_interval=1e-4, start_values=imm)
    print("rows", len(r))
""")


def test_imm_tracker_instantiated_after_the_first_extraction_was_deleted(fmu_dir: Path):
    p = subprocess.run([sys.executable, "-c", SCRIPT, str(fmu_dir / "Tracker.fmu")],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    assert "rows 11" in p.stdout
