"""FMU declaration and FMI variable layout (fmus/spec.py)."""

from __future__ import annotations

from fmu_standin import SPEC

from axir.fmus.spec import layout


def test_layout_structured_names() -> None:
    rows = layout(SPEC)
    names = [r.name for r in rows]
    assert names[:3] == ["gain", "n_max", "flag"]
    assert names[3] == "beam.up[1,1]" and names[4] == "beam.up[1,2]"
    assert names[3 + 48] == "beam.right[1,1]" and names[3 + 191] == "beam.left[16,3]"
    assert names.index("sum[3,2]") == 3 + 192 + 1 + 2 * 3 + 1
    assert len(rows) == 3 + 193 + 48 + 3
    assert {r.kind for r in rows if r.name in ("count", "n_max")} == {"Integer"}
