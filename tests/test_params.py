"""Parameter declaration and validation (models/radar/params.py)."""

import math

import pytest

from axir.models.radar.params import Configurable, Param


class _Demo(Configurable):
    PARAMS = (
        Param("gain", 1.0, "1", "a gain", low=0.0, high=10.0, low_open=True),
        Param("count", 3, "", "a count", low=1),
        Param("flag", False, "", "a flag"),
        Param("law", "linear", "", "a law", choices=("linear", "exact")),
    )


def test_defaults_and_overrides():
    d = _Demo(gain=2, count=5.0, flag="true", law="exact")
    assert (d.gain, d.count, d.flag, d.law) == (2.0, 5, True, "exact")
    assert isinstance(d.gain, float) and isinstance(d.count, int)
    assert _Demo().params() == {"gain": 1.0, "count": 3, "flag": False, "law": "linear"}


@pytest.mark.parametrize(
    ("kw", "fragment"),
    [
        ({"gain": 0.0}, "_Demo.gain = 0.0 is out of range: valid range (0.0, 10.0]"),
        ({"gain": 11.0}, "_Demo.gain = 11.0"),
        ({"gain": math.nan}, "_Demo.gain = nan"),
        ({"gain": math.inf}, "_Demo.gain = inf"),
        ({"gain": "x"}, "wrong type: expected float"),
        ({"count": 0}, "_Demo.count = 0 is out of range: valid range [1, inf)"),
        ({"count": 1.5}, "wrong type: expected int"),
        ({"flag": 2}, "wrong type: expected bool"),
        ({"law": "cubic"}, "valid values one of 'linear', 'exact'"),
        ({"nope": 1}, "unknown parameter(s) nope"),
    ],
)
def test_invalid_values_name_the_parameter(kw, fragment):
    with pytest.raises(ValueError, match=None) as e:
        _Demo(**kw)
    assert fragment in str(e.value)


# ------------------------------------------------------------------ issue 10: ranges
def _units() -> list[type]:
    from axir.models.manager import RadarManager
    from axir.models.pedestal import Pedestal
    from axir.models.target_generator import TargetGenerator
    from axir.models.tracker import Tracker

    return [TargetGenerator, Tracker, Pedestal, RadarManager]


def test_every_numeric_parameter_has_a_finite_range_within_fmi_types() -> None:
    """Every Real/Integer parameter of the four units declares both bounds (FMI min/max);
    Integer ranges fit a 32-bit FMI Integer (a wider one would be wrapped by the host)."""
    for unit in _units():
        for p in unit.PARAMS:
            if p.kind in (int, float) and p.choices is None:
                assert p.low is not None and p.high is not None, f"{unit.__name__}.{p.name}"
                if p.kind is int:
                    assert p.low >= -(2**31) and p.high <= 2**31 - 1, f"{unit.__name__}.{p.name}"


@pytest.mark.parametrize(("unit", "name", "value"), [
    ("TargetGenerator", "snr_ref_range", 1e308), ("Tracker", "sigma_range", 1e308),
    ("TargetGenerator", "rcs", 1e308), ("TargetGenerator", "doppler_spacing", 1e308),
    ("Tracker", "gate_latency", 4294967298), ("TargetGenerator", "seed", 4294967303),
    ("TargetGenerator", "noise", 2), ("TargetGenerator", "clutter", -1),
    ("Tracker", "n_max", 10**400)])
def test_out_of_range_values_are_refused_by_name(unit: str, name: str, value: object) -> None:
    cls = {u.__name__: u for u in _units()}[unit]
    with pytest.raises(ValueError, match=rf"parameter {unit}\.{name} = "):
        cls(**{name: value})


def test_error_names_the_fmi_variable() -> None:
    """Pedestal's parameter `bandwidth` is the FMI variable `bandwidth0` (the input is
    `bandwidth`): the message names what the FMU user sets."""
    from axir.models.pedestal import Pedestal

    with pytest.raises(ValueError, match=r"Pedestal\.bandwidth0 \(argument bandwidth\)"):
        Pedestal(bandwidth=1e308)
