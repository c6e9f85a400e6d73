"""The recorder without FMUs: columns of mixed types in any order land where they belong, and
the CSV text is ``repr(float(v))`` / ``str(int(v))`` per value (the layout of
``fmpy.util.write_csv``), streamed or written at the end alike."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

from axir.orchestrator.record import Recorder, write_csv


class _Unit:
    """A stand-in slave: variables (name, type) whose values ``values`` holds; ``bind`` of an
    ``fmi2Get*`` fills the given ctypes buffer as an FMU would."""

    def __init__(self, name: str, variables: list[tuple[str, str]]) -> None:
        self.name = name
        self.vars = {n: SimpleNamespace(name=n, type=t, valueReference=i)
                     for i, (n, t) in enumerate(variables)}
        self.values: dict[str, Any] = {n: 0 for n, _ in variables}
        self.by_vr = {v.valueReference: v.name for v in self.vars.values()}
        self.gets: list[str] = []

    def variable(self, name: str) -> Any:
        return self.vars[name]

    def bind(self, function: str, vr: Any, n: int, buf: Any) -> Any:
        names = [self.by_vr[vr[i]] for i in range(n)]
        kind = function.removeprefix("fmi2Get")
        assert all(self.vars[m].type == kind for m in names)

        def get() -> int:
            self.gets.append(function)
            for i, m in enumerate(names):
                buf[i] = self.values[m]
            return 0

        return get


def _master(units: list[_Unit]) -> Any:
    return SimpleNamespace(instances={u.name: u for u in units}, t_ns=0, steps=0)


# values the CSV must print exactly as Python prints them
_REALS = [0.1, -0.0, 1e20, 5e-324, 1.7976931348623157e308, math.inf, -math.inf, math.nan,
          123456.789, -2.5e-7, 1.0, 3.0000000000000004]


def test_mixed_types_in_any_order_and_csv_text(tmp_path: Path) -> None:
    a = _Unit("A", [("x", "Real"), ("mode", "Integer"), ("on", "Boolean"), ("y", "Real")])
    b = _Unit("B", [("k", "Integer"), ("z", "Real")])
    refs = ["A.y", "B.k", "A.on", "B.z", "A.mode", "A.x"]  # interleaved units and types
    master = _master([a, b])
    rec = Recorder(refs)
    rec.stream_to(tmp_path / "streamed.csv")
    expected_rows = []
    for step, r in enumerate(_REALS):
        a.values.update(x=r, y=-r if not math.isnan(r) else 2.0, mode=step - 3, on=step % 2)
        b.values.update(k=-(2 ** 31) + step, z=step * 0.3)
        master.t_ns = step * 111_111
        if step == 0:
            rec.start(master)
        else:
            master.steps = step
            rec.step(master, master.t_ns)
        vals = {"A.y": a.values["y"], "B.k": b.values["k"], "A.on": a.values["on"],
                "B.z": b.values["z"], "A.mode": a.values["mode"], "A.x": a.values["x"]}
        expected_rows.append([master.t_ns / 1e9] + [vals[r] for r in refs])
    rec.finish(master, True)
    data = rec.data
    assert data.shape == (len(_REALS), 1 + len(refs))
    np.testing.assert_array_equal(data, np.array(expected_rows, dtype=float))
    # one fmi2Get* per (unit, type) per sample
    assert sorted(set(a.gets)) == ["fmi2GetBoolean", "fmi2GetInteger", "fmi2GetReal"]
    assert len(a.gets) == 3 * len(_REALS) and len(b.gets) == 2 * len(_REALS)
    kinds = ["Real", "Integer", "Boolean", "Real", "Integer", "Real"]
    lines = ['"time","A.y","B.k","A.on","B.z","A.mode","A.x"']
    for row in expected_rows:
        lines.append(",".join([repr(float(row[0]))] + [
            str(int(v)) if k != "Real" else repr(float(v)) for k, v in zip(kinds, row[1:],
                                                                             strict=True)]))
    text = "\n".join(lines) + "\n"
    write_csv(tmp_path / "end.csv", rec)
    assert (tmp_path / "end.csv").read_text() == text
    assert (tmp_path / "streamed.csv").read_text() == text


def test_stream_flushes_whole_rows_while_recording(tmp_path: Path) -> None:
    a = _Unit("A", [("x", "Real")])
    master = _master([a])
    rec = Recorder(["A.x"])
    rec.stream_to(tmp_path / "r.csv", flush_s=0.0)  # flush at every look at the clock
    rec.start(master)
    for step in range(1, 300):
        a.values["x"] = step / 7
        master.t_ns, master.steps = step * 1000, step
        rec.step(master, master.t_ns)
    # before finish: the rows up to the last look at the clock are in the file, whole
    lines = (tmp_path / "r.csv").read_text().splitlines()
    assert 200 < len(lines) - 1 <= 300
    assert all(ln.count(",") == 1 for ln in lines[1:])
    rec.finish(master, True)
    assert len((tmp_path / "r.csv").read_text().splitlines()) == 1 + 300

