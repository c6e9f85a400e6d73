"""Scenario files: validation names the key; parsing builds the system."""

from pathlib import Path

import pytest

from axir.orchestrator.errors import ScenarioError
from axir.orchestrator.scenario import (
    load_scenario,
    parse_scenario,
    scenario_problems,
)

GOOD = {
    "scenario": {"name": "t", "duration": 1.0, "seed": 3, "order": ["A", "B"],
                 "step_from": "A.y"},
    "units": {"A": {"fmu": "A.fmu", "parameters": {"k": 1.0}}, "B": {}},
    "connections": [{"from": "A.y", "to": "B.u"}],
    "record": {"decimation": 2, "variables": ["A.y"]},
}


def test_good_scenario_has_no_problems_and_parses(tmp_path):
    assert scenario_problems(GOOD) == []
    sc = parse_scenario(GOOD, "mem")
    assert sc.step is None and sc.decimation == 2 and sc.order == ["A", "B"]
    system = sc.system(tmp_path)
    assert system.units["A"].fmu == tmp_path / "A.fmu"
    assert system.units["B"].fmu == tmp_path / "B.fmu"
    assert str(system.connections[0]) == "A.y -> B.u"


@pytest.mark.parametrize(
    ("patch", "fragment"),
    [
        ({"scenario": {"duration": 1.0}}, "scenario.name"),
        ({"scenario": {"name": "t", "duration": -1}}, "scenario.duration"),
        ({"scenario": {"name": "t", "seed": -2}}, "scenario.seed"),
        ({"scenario": {"name": "t", "algorithm": "euler"}}, "scenario.algorithm"),
        ({"scenario": {"name": "t", "step": "fast"}}, "scenario.step"),
        ({"scenario": {"name": "t"}}, "reads 'RadarManager.pri', a unit this scenario"),
        ({"scenario": {"name": "t", "duration": float("inf")}}, "scenario.duration"),
        ({"scenario": {"name": "t", "step_from": "A.y", "initial_step": float("nan")}},
         "scenario.initial_step"),
        ({"scenario": {"name": "t", "order": ["A"]}}, "scenario.order"),
        ({"scenario": {"name": "t", "bogus": 1}}, "scenario.bogus: unknown key"),
        ({"extra": {}}, "unknown top-level key 'extra'"),
        ({"units": {}}, "units: at least one"),
        ({"units": {"A": {"fmu": 3}, "B": {}}}, "units.A.fmu"),
        ({"units": {"A": {"params": {}}, "B": {}}}, "units.A.params: unknown key"),
        ({"units": {"A": {"parameters": {"k": [1]}}, "B": {}}}, "units.A.parameters.k"),
        ({"connections": [{"from": "C.y", "to": "B.u"}]}, "connections[0].from"),
        ({"connections": [{"to": "B.u"}]}, "connections[0]: must be a table"),
        ({"record": {"decimation": 0}}, "record.decimation"),
        ({"record": {"variables": ["Z.q"]}}, "record.variables"),
    ],
)
def test_problems_name_the_key(patch, fragment):
    data = {**GOOD, **patch}
    problems = scenario_problems(data)
    assert any(fragment in p for p in problems), problems
    with pytest.raises(ScenarioError, match="mem"):
        parse_scenario(data, "mem")


def test_load_errors_name_the_file(tmp_path: Path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[scenario\nname = 1")
    with pytest.raises(ScenarioError, match=r"bad\.toml: malformed TOML"):
        load_scenario(bad)
    with pytest.raises(ScenarioError, match="not found"):
        load_scenario(tmp_path / "missing.toml")
    with pytest.raises(ScenarioError, match="no built-in scenario"):
        load_scenario("no-such-scenario")


