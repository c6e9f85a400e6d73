"""Hold-last-valid input rule of a unit's scalar inputs (per step).

Assumption (SYSTEM.md: a unit degrades, it does not stop): an input that is not a finite
number, or is below its floor, keeps its last valid value and the step is flagged invalid.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any


def hold_inputs(inputs: Mapping[str, Any], last: Mapping[str, float],
                defaults: tuple[tuple[str, float], ...], floors: Mapping[str, float]
                ) -> tuple[dict[str, float], bool]:
    """(inputs as floats with the rule applied, whether any input was held).

    ``defaults``: (name, start value) of every input, taken when the input is absent;
    ``floors``: smallest valid value per name (others: any finite number); ``last``: the last
    valid value per name. The first try converts all at once (the usual case: every input a
    finite float above its floor); otherwise the item-by-item rule decides each input.
    """
    get = inputs.get
    u = {}
    try:  # a plain loop, not a dict comprehension: no comprehension frame per step (issue 14)
        for name, default in defaults:
            u[name] = float(get(name, default))
        if math.isfinite(sum(u.values())):
            for n, lo in floors.items():  # a plain loop: no generator per step (issue 14)
                if not u[n] >= lo:
                    break
            else:
                return u, False
    except (TypeError, ValueError):
        pass
    u = {}
    bad = False
    for name, default in defaults:
        try:
            x = float(inputs.get(name, default))
        except (TypeError, ValueError):
            x = math.nan
        if not math.isfinite(x) or x < floors.get(name, -math.inf):
            x, bad = last[name], True
        u[name] = x
    return u, bad
