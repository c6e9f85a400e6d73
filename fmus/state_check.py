"""Structure check of a decoded FMU state (:mod:`.state_codec` decodes the data; this checks
that it is a state of this FMU's variable layout before the slave uses it).

Bundled into every FMU: relative imports only.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .spec import FmuSpec, layout
from .state_codec import StateFormatError

_KINDS = ("Real", "Integer", "Boolean", "String")
_NP_DTYPES = {"Real": np.float64, "Integer": np.int64, "Boolean": np.bool_}


def checked_state(spec: FmuSpec, state: Any) -> dict[str, Any]:
    """``state`` if it has the structure ``AxirSlave._get_fmu_state`` (:mod:`.slave`) gives for this
    FMU's variable layout (buffer types and lengths, flag types), else StateFormatError."""
    if type(state) is not dict:
        raise StateFormatError("state is not a mapping")
    if set(state) == {"invalid"} and type(state["invalid"]) is str:
        return state
    if set(state) != {"bundle", "buf", "model", "held", "flags"}:
        raise StateFormatError(f"state fields {sorted(map(str, state))}")
    counts = dict.fromkeys(_KINDS, 0)
    for r in layout(spec):
        counts[r.kind] += 1
    buf = state["buf"]
    if type(buf) is not dict or set(buf) != set(_KINDS):
        raise StateFormatError("bad value buffers")
    for k in _NP_DTYPES:
        a = buf[k]
        if (type(a) is not np.ndarray or a.dtype != np.dtype(_NP_DTYPES[k])
                or a.shape != (counts[k],)):
            raise StateFormatError(f"{k} buffer is not {counts[k]} values of {k}")
    if (type(buf["String"]) is not list or len(buf["String"]) != counts["String"]
            or not all(type(x) is str for x in buf["String"])):
        raise StateFormatError("bad String buffer")
    held = state["held"]
    n_in = {k: 0 for k in ("Real", "Integer")}
    for r in layout(spec):
        if r.causality == "input" and r.kind in n_in:
            n_in[r.kind] += 1
    want = {k for k, n in n_in.items() if n}
    if type(held) is not dict or set(held) != want or not all(
            type(held[k]) is np.ndarray and held[k].dtype == np.dtype(_NP_DTYPES[k])
            and held[k].shape == (n_in[k],) for k in want):
        raise StateFormatError("bad held input values")
    flags = state["flags"]
    if (type(flags) is not tuple or len(flags) != 4
            or not all(type(f) is bool for f in (flags[0], flags[2]))
            or not (flags[1] is None or type(flags[1]) is str) or type(flags[3]) is not float):
        raise StateFormatError("bad flags")
    model = state["model"]
    if model is not None and (type(model) is not dict
                              or not all(type(k) is str for k in model)):
        raise StateFormatError("bad model state")
    return state
