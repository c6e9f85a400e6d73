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
