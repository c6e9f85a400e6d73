"""The radar system's facts (models/system.py): connections, order, step source, Jacobi
parameters, per-unit seeds, initial PRI."""

from axir.models.manager import RadarManager
from axir.models.radar.conventions import BIN_S
from axir.models.system import (
    CONNECTIONS,
    GAUSS_SEIDEL_ORDER,
    JACOBI_PARAMETERS,
    STEP_SOURCE,
    UNITS,
    initial_pri,
    unit_seed,
)
from axir.models.tracker import Tracker


def test_connections_follow_system_md():
    pairs = {(c.src_unit, c.src_var, c.dst_unit, c.dst_var) for c in CONNECTIONS}
    for b in ("up", "right", "down", "left"):
        assert ("TargetGenerator", f"beam.{b}", "Tracker", f"beam.{b}") in pairs
    for expected in [("Pedestal", "az", "Tracker", "ped.az"),
                     ("Tracker", "cmd.el", "Pedestal", "cmd.el"),
                     ("Tracker", "sum", "RadarManager", "sum"),
                     ("RadarManager", "pri", "TargetGenerator", "pri"),
                     ("RadarManager", "bandwidth", "Pedestal", "bandwidth"),
                     ("Tracker", "gate.start", "TargetGenerator", "gate.start")]:
        assert expected in pairs
    dsts = [(c.dst_unit, c.dst_var) for c in CONNECTIONS]
    assert len(dsts) == len(set(dsts))  # every input driven once


def test_units_and_order_name_the_four_units_once():
    assert sorted(UNITS) == sorted(GAUSS_SEIDEL_ORDER)
    assert UNITS == ("TargetGenerator", "Tracker", "Pedestal", "RadarManager")  # SYSTEM.md
    assert GAUSS_SEIDEL_ORDER[0] == "Pedestal" and GAUSS_SEIDEL_ORDER[-1] == "RadarManager"
    for c in CONNECTIONS:
        assert c.src_unit in UNITS and c.dst_unit in UNITS


def test_step_source_is_the_managers_pri_output():
    unit, var = STEP_SOURCE
    assert unit == "RadarManager"
    assert var in {p.name for p in RadarManager.OUTPUTS}


def test_jacobi_parameters_are_declared_parameters():
    assert JACOBI_PARAMETERS == {"Tracker": {"gate_latency": 2}}
    names = {p.name for p in Tracker.PARAMS}
    assert set(JACOBI_PARAMETERS["Tracker"]) <= names


def test_initial_pri_is_pri_1_of_the_manager():
    # 200 range-bin durations of 2·75 m / c (SYSTEM.md: PRIs are integer numbers of bins)
    assert initial_pri() == 200 * (150.0 / 299_792_458.0)
    assert abs(initial_pri() - 1.0007e-4) < 1e-9
    assert initial_pri() == RadarManager().outputs()["pri"]
    assert initial_pri() / BIN_S == 200


def test_unit_seeds_are_stable_and_distinct():
    assert unit_seed(1, "Tracker") == unit_seed(1, "Tracker")
    seeds = {unit_seed(1, u) for u in ("Tracker", "Pedestal", "TargetGenerator")}
    assert len(seeds) == 3
    assert unit_seed(1, "Tracker") != unit_seed(2, "Tracker")
    assert all(0 <= s < 2**31 for s in seeds)
