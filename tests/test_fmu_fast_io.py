"""The fast step's gather and scatter made by the C shim (issue 14, session 9: shim section
"fast step I/O", ``fmus/step_plan.py: make_fast_io``), on real shimmed FMUs in this process.

The shim builds the input mapping and stores the outputs itself when every output has a plain
value, and hands anything else to the slave's Python scatter. Checked here, against a replica
of the slave's own :class:`~axir.fmus.step_plan.StepPlan` over a copy of its value block
(what the Python path stores or raises):

- the shim's path is the one taken in a plain step (no forwarded ``do_step``; the I/O step
  function ran) and it stores exactly the model's outputs;
- an odd value in a Real, Integer or Boolean output, or an odd array output (another dtype,
  shape, order, a list), is stored exactly as the Python scatter stores it, or the step fails
  as the Python scatter fails (the exception raised by the forwarded ``do_step``: fmi2Error);
- a failed scatter stores nothing of that step and leaves the time where it was.
"""

from __future__ import annotations

import ctypes
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pytest
from test_fmu_shim_shared import (  # noqa: F401 (shimmed: the fixture the ones below use)
    DT,
    ERROR,
    OK,
    _init,
    _slave,
    raw,
    shimmed,
)

from axir.fmus.step_plan import StepPlan

_ODD = [None, "2.5", "", [1.0], [], np.float32(0.1), 3, True, False, -1, 2 ** 63, 2.5,
        float("nan"), float("-inf"), np.array(2.5), np.array([1, 2]), np.array([0]),
        np.int64(7), np.int32(-3), np.True_, np.False_, np.array(True), 1 + 2j, object()]


def _replica(slave: Any) -> tuple[StepPlan, np.ndarray]:
    """The slave's StepPlan over a copy of its block (what the Python scatter would store)."""
    block = slave._shared.block.copy()
    base = slave._shared.block.ctypes.data

    def view(arr: np.ndarray) -> np.ndarray:
        off = arr.ctypes.data - base
        return block[off:off + arr.nbytes].view(arr.dtype)

    buf = {k: view(slave._buf[k]) for k in ("Real", "Integer", "Boolean")}
    return StepPlan(block, buf, slave._inputs, slave._outputs), block


def _step_with(f: Any, slave: Any, t: float, out: dict[str, Any]) -> int:
    """One doStep at ``t`` whose model step returns ``out``."""
    slave.model.step = lambda h, inputs: out
    return f.dll.fmi2DoStep(f.component, t, DT, 1)


def _values_block(slave: Any) -> bytes:
    """The slave's value arrays (Real, Integer, Boolean) as bytes."""
    return b"".join(slave._buf[k].tobytes() for k in ("Real", "Integer", "Boolean"))


@pytest.fixture
def fmus(request: pytest.FixtureRequest) -> Path:
    return request.getfixturevalue("shimmed")


def test_plain_steps_take_the_shims_path_and_store_the_models_outputs(fmus: Path) -> None:
    with raw(fmus / "TargetGenerator.fmu", "io_tg") as f:
        _init(f)
        slave = _slave("io_tg")
        forwarded: list[float] = []
        orig = slave.do_step
        slave.do_step = lambda t, h: (forwarded.append(t), orig(t, h))[1]
        model_step = slave.model.step
        seen: list[dict[str, Any]] = []
        slave.model.step = lambda h, inputs: seen.append(model_step(h, inputs)) or seen[-1]
        for k in range(40):
            assert f.dll.fmi2DoStep(f.component, k * DT, DT, 1) == OK
            plan, block = _replica(slave)
            plan.scatter(seen[-1])  # the Python path on a copy of the block
            assert _values_block(slave) == _block_values(block, slave), k
        assert forwarded == []
        assert slave._time_before == 39 * DT  # set by the I/O step function (make_fast_io)
        assert slave._time == 40 * DT


def _block_values(block: np.ndarray, slave: Any) -> bytes:
    base = slave._shared.block.ctypes.data
    parts = []
    for k in ("Real", "Integer", "Boolean"):
        arr = slave._buf[k]
        off = arr.ctypes.data - base
        parts.append(block[off:off + arr.nbytes].tobytes())
    return b"".join(parts)


def _check_odd(f: Any, slave: Any, key: str, odd: Any, t: float) -> None:
    out = dict(slave.model.outputs())
    out[key] = odd
    plan, block = _replica(slave)
    try:
        plan.scatter(out)
        want: Any = _block_values(block, slave)
    except Exception as e:
        want = type(e)
    before, time_before = _values_block(slave), slave._time
    status = _step_with(f, slave, t, out)
    if isinstance(want, type):
        assert status == ERROR, (key, odd)
        assert _values_block(slave) == before  # nothing of the failed step stored
        assert slave._time == time_before
        assert any(want.__name__ in m for _, m in f.logs), f.logs[-3:]
    else:
        assert status == OK, (key, odd, f.logs[-3:])
        assert _values_block(slave) == want, (key, odd)


@pytest.mark.parametrize("key", ["az", "input.invalid.count", "input.invalid"])
@pytest.mark.parametrize("odd", _ODD, ids=[repr(v)[:14] for v in _ODD])
def test_an_odd_scalar_output_is_stored_as_the_python_scatter_stores_it(
        fmus: Path, key: str, odd: Any) -> None:
    with raw(fmus / "Pedestal.fmu", "io_odd") as f:
        _init(f)
        slave = _slave("io_odd")
        assert f.dll.fmi2DoStep(f.component, 0.0, DT, 1) == OK
        _check_odd(f, slave, key, odd, DT)


_ODD_ARRAYS = {
    "float32": lambda a: a.astype(np.float32),
    "int64": lambda a: np.rint(a).astype(np.int64),
    "fortran": lambda a: np.asfortranarray(a),
    "strided": lambda a: np.repeat(a, 2, axis=2)[:, :, ::2],
    "flat": lambda a: a.ravel(),
    "list": lambda a: a.tolist(),
    "wrong shape": lambda a: a[:, :8, :],
    "big-endian": lambda a: a.astype(">f8"),
    "0-d": lambda a: np.float64(1.5),
    "complex": lambda a: a.astype(complex),
    "plain": lambda a: a.copy(),
}


@pytest.mark.filterwarnings("ignore::numpy.exceptions.ComplexWarning")
@pytest.mark.parametrize("case", list(_ODD_ARRAYS))
def test_an_odd_array_output_is_stored_as_the_python_scatter_stores_it(
        fmus: Path, case: str) -> None:
    with raw(fmus / "TargetGenerator.fmu", "io_arr") as f:
        _init(f)
        slave = _slave("io_arr")
        for k in range(3):
            assert f.dll.fmi2DoStep(f.component, k * DT, DT, 1) == OK
        beam = np.asarray(slave.model.outputs()["beam"]) + 0.25  # differs from the block
        _check_odd(f, slave, "beam", _ODD_ARRAYS[case](beam), 3 * DT)


def test_a_missing_output_fails_the_step_as_the_python_scatter_does(fmus: Path) -> None:
    with raw(fmus / "Pedestal.fmu", "io_miss") as f:
        _init(f)
        slave = _slave("io_miss")
        out = dict(slave.model.outputs())
        del out["el"]
        before = _values_block(slave)
        assert _step_with(f, slave, 0.0, out) == ERROR
        assert _values_block(slave) == before and slave._time == 0.0
        assert any("KeyError" in m and "'el'" in m for _, m in f.logs)


def test_a_mapping_that_is_not_a_dict_goes_through_the_python_scatter(fmus: Path) -> None:
    class Outputs(dict):
        reads: ClassVar[list[str]] = []

        def __getitem__(self, key: str) -> Any:
            self.reads.append(key)
            return super().__getitem__(key)

    with raw(fmus / "Pedestal.fmu", "io_map") as f:
        _init(f)
        slave = _slave("io_map")
        out = Outputs(slave.model.outputs())
        out["az"] = 0.125
        assert _step_with(f, slave, 0.0, out) == OK
        assert out.reads  # the Python scatter read it
        vr = (ctypes.c_uint * 1)(f.vr["az"])
        val = (ctypes.c_double * 1)()
        assert f.dll.fmi2GetReal(f.component, vr, 1, val) == OK and val[0] == 0.125
