"""System validation against model descriptions (pure functions, fmpy data classes)."""

from pathlib import Path

from fmpy.model_description import ModelDescription, ScalarVariable

from axir.orchestrator.system import (
    Connection,
    SystemDescription,
    UnitSpec,
    expand_array,
    validate_system,
)


def _md(*vars_):
    md = ModelDescription()
    for i, (name, causality, type_) in enumerate(vars_):
        v = ScalarVariable(name, valueReference=i)
        v.causality, v.type = causality, type_
        md.modelVariables.append(v)
    return md


A = _md(("y", "output", "Real"), ("m", "output", "Integer"), ("k", "parameter", "Real"),
        ("arr[1,1]", "output", "Real"), ("arr[1,2]", "output", "Real"))
B = _md(("u", "input", "Real"), ("n", "input", "Integer"), ("arr[1,1]", "input", "Real"),
        ("arr[1,2]", "input", "Real"), ("x", "output", "Real"))


def _system(conns, params=None):
    units = {"A": UnitSpec("A", Path("A.fmu"), params or {}), "B": UnitSpec("B", Path("B.fmu"))}
    return SystemDescription(units, conns)


def test_valid_system_and_array_expansion():
    conns, problems = validate_system(
        _system([Connection("A", "y", "B", "u"), Connection("A", "arr", "B", "arr")]),
        {"A": A, "B": B})
    assert problems == []
    assert [c.dst_var for c in conns] == ["u", "arr[1,1]", "arr[1,2]"]
    assert expand_array("arr", A) == ["arr[1,1]", "arr[1,2]"]


def test_problems_name_unit_and_variable():
    cases = [
        (Connection("A", "nope", "B", "u"), "A has no variable 'nope'"),
        (Connection("A", "y", "B", "nope"), "B has no variable 'nope'"),
        (Connection("A", "y", "C", "u"), "unknown unit 'C'"),
        (Connection("A", "m", "B", "u"), "type mismatch Integer -> Real"),
        (Connection("B", "x", "A", "k"), "target is a parameter, not an input"),
        (Connection("A", "k", "B", "u"), "source is a parameter, not an output"),
    ]
    for conn, fragment in cases:
        _, problems = validate_system(_system([conn]), {"A": A, "B": B})
        assert any(fragment in p for p in problems), (conn, problems)


def test_input_driven_twice_and_unknown_parameter():
    _, problems = validate_system(
        _system([Connection("A", "y", "B", "u"), Connection("B", "x", "B", "u")], {"zz": 1}),
        {"A": A, "B": B})
    assert any("already driven" in p for p in problems)
    assert any("unknown parameter 'zz'" in p for p in problems)
