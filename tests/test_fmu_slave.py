"""Runtime slave (fmus/slave.py) in process: vectorised get/set, step, FMU state, errors."""

from __future__ import annotations

import numpy as np
from fmu_standin import BEAMS, SPEC, StandInSlave

from axir.fmus.spec import layout


def test_slave_vectorised_io_in_process() -> None:
    """The slave class alone (no FMU): vectorised get/set, step, state (speed: see
    benchmarks/bench_fmu_slave.py)."""
    s = StandInSlave(instance_name="x", resources=".")
    rows = layout(SPEC)
    vr = {r.name: i for i, r in enumerate(rows)}
    beam_vrs = [vr[f"beam.{b}[{r},{f}]"] for b in BEAMS for r in range(1, 17) for f in (1, 2, 3)]
    sum_vrs = [vr[f"sum[{r},{f}]"] for r in range(1, 17) for f in (1, 2, 3)]
    s.set_real([vr["gain"]], [2.0])
    s.exit_initialization_mode()
    beams = np.arange(192, dtype=float).reshape(4, 16, 3)
    s.set_real(beam_vrs, beams.ravel().tolist())
    s.set_real([vr["ped.az"]], [0.25])
    assert s.do_step(0.0, 0.1)
    assert s.get_real(sum_vrs) == (2.0 * beams.sum(axis=0)).ravel().tolist()
    assert s.get_integer([vr["count"]]) == [1]
    st = s._get_fmu_state()
    blob = StandInSlave._fmu_state_to_bytes(st)
    s.do_step(0.1, 0.1)
    s._set_fmu_state(StandInSlave._fmu_state_from_bytes(blob))
    assert s.get_integer([vr["count"]]) == [1]
    s.set_real([vr["gain"]], [20.0])  # tunable, invalid -> error log, old value kept
    s.do_step(0.1, 0.1)
    assert s.get_real([vr["gain"]]) == [2.0]
    assert any("gain" in m.msg for m in s.log_queue)
    s.get_real([vr["count"]])  # wrong type: logged, no exception
