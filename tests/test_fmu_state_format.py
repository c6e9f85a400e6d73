"""Serialised FMU states are data (fmus/state_codec.py): no pickle, nothing of the data runs.

A crafted state that would create a file when unpickled (format 1, and the same idea smuggled
into the new format: a foreign class, an object dtype, a pickle in a buffer) is refused — the
file is never created, ``fmi2SetFMUstate`` answers fmi2Error (through the C shim) with a
message, and the instance keeps working. States of another FMU or format version are refused
with a message naming the reason. Round trips stay bit-identical (also tests/test_fmu_all.py).
"""

from __future__ import annotations

import json
import os
import pickle
import struct
from pathlib import Path

import numpy as np
import pytest
from fmu_standin import StandInSlave
from test_fmu_all import Driver, deserialize, free_state, get_state, opened, serialize

from axir.fmus.state_codec import MAGIC, VERSION, StateFormatError, decode_state, encode_state
from axir.orchestrator.errors import FmiError


class _Touch:
    """Unpickling this runs ``os.system('touch <path>')`` (the attack of issue 10)."""

    def __init__(self, path: Path) -> None:
        self.path = str(path)

    def __reduce__(self) -> tuple:
        return (os.system, (f"touch {self.path}",))


def _new_format(header: dict, buffers: bytes = b"", version: int = VERSION) -> bytes:
    h = json.dumps(header).encode()
    return MAGIC + struct.pack("<II", version, len(h)) + h + buffers


def _payloads(marker: Path, model: str, bundle: str | None) -> dict[str, bytes]:
    """Byte strings an attacker could hand to fmi2DeSerializeFMUstate."""
    evil = pickle.dumps(_Touch(marker), protocol=4)
    head = {"model": model, "bundle": bundle}
    return {
        "format 1 (pickle)": b"AXIRFMUSTATE1\n" + evil,
        "new magic + pickle": MAGIC + evil,
        "class outside the model package": _new_format(
            {**head, "buffers": [], "tree": {"$": "obj", "id": 0, "cls": "os:system",
                                            "d": {"$": "dict", "id": 1, "k": [], "v": []}}}),
        "object dtype": _new_format(
            {**head, "buffers": [len(evil)],
             "tree": {"$": "nd", "id": 0, "dtype": "|O", "shape": [1], "buf": 0}}, evil),
        "other format version": _new_format({**head, "buffers": [], "tree": None}, version=1),
        "truncated": MAGIC + struct.pack("<II", VERSION, 1000) + b"{",
    }


def test_crafted_states_run_nothing_in_process(tmp_path: Path) -> None:
    """The slave's decoder (the function pythonfmu calls for fmi2DeSerializeFMUstate)."""
    marker = tmp_path / "pwned"
    for what, data in _payloads(marker, StandInSlave.SPEC.name, None).items():
        state = StandInSlave._fmu_state_from_bytes(data)
        assert not marker.exists(), f"{what}: the payload ran"
        assert set(state) == {"invalid"}, what
        s = StandInSlave(instance_name="x", resources=".")
        s.exit_initialization_mode()
        s._set_fmu_state(state)
        assert any(m.status.name.lower() == "error" and "not a state of this FMU" in m.msg
                   for m in s.log_queue), what
        assert s.do_step(0.0, 0.1), what  # the instance still works


def test_foreign_and_wrong_version_refused_with_reason() -> None:
    data = encode_state({"x": 1.0}, "Pedestal", "abc")
    assert decode_state(data, "Pedestal", "abc") == {"x": 1.0}
    with pytest.raises(StateFormatError, match="FMU 'Pedestal', not 'Tracker'"):
        decode_state(data, "Tracker", "abc")
    with pytest.raises(StateFormatError, match="another build"):
        decode_state(data, "Pedestal", "abd")
    v3 = data[:len(MAGIC)] + struct.pack("<I", VERSION + 1) + data[len(MAGIC) + 4:]
    with pytest.raises(StateFormatError, match="version 3"):
        decode_state(v3, "Pedestal", "abc")


def test_codec_keeps_types_bits_and_sharing() -> None:
    shared = [1.0]
    g = np.random.Generator(np.random.PCG64(123))
    g.standard_normal(3)
    tree = {"f": -0.0, "nan": float("nan"), "big": 2**100, "c": 1 + 2j, "t": (1, "a", None),
            "a": np.arange(6, dtype=np.int64).reshape(2, 3), "z": np.array([1j, -0.0]),
            "np": np.float64(0.1), "s1": shared, "s2": shared, "g": g, 3: True}
    back = decode_state(encode_state(tree, "M", None), "M", None)
    assert list(back) == list(tree)
    assert str(back["f"]) == "-0.0" and back["nan"] != back["nan"] and back["big"] == 2**100
    assert back["c"] == 1 + 2j and back["t"] == (1, "a", None) and back[3] is True
    assert back["a"].dtype == np.int64 and (back["a"] == tree["a"]).all()
    assert back["z"].tobytes() == tree["z"].tobytes()
    assert type(back["np"]) is np.float64 and back["np"] == 0.1
    assert back["s1"] is back["s2"]  # shared references stay shared
    assert back["g"].standard_normal(5).tolist() == g.standard_normal(5).tolist()


@pytest.mark.parametrize("name", ["Pedestal", "TargetGenerator"])
def test_crafted_state_through_fmu_gives_error_and_runs_nothing(
        fmu_dir: Path, name: str, tmp_path: Path) -> None:
    marker = tmp_path / "pwned"
    with opened(fmu_dir, name, "a") as a:
        drv = Driver(a, name)
        drv.run(0, 5)
        s = get_state(a)
        good = serialize(a, s)
        free_state(a, s)
        ref = drv.run(5, 5)
        header_len = struct.unpack_from("<I", good, len(MAGIC) + 4)[0]
        try:
            header = json.loads(good[len(MAGIC) + 8:len(MAGIC) + 8 + header_len])
        except ValueError:  # (the old pickle format: the attack below still applies)
            header = {"model": name, "bundle": None, "buffers": [], "tree": None}
        payloads = _payloads(marker, header["model"], header["bundle"])
        payloads["foreign FMU"] = _new_format(
            {**header, "model": "Tracker" if name != "Tracker" else "Pedestal"},
            good[len(MAGIC) + 8 + header_len:])
        for what, data in payloads.items():
            st = deserialize(a, data)  # pythonfmu cannot fail here; the state is marked
            assert not marker.exists(), f"{what}: the payload ran"
            a.log.clear()
            with pytest.raises(FmiError) as exc:
                a.call("fmi2SetFMUstate", st)
            assert exc.value.status == 3, what  # fmi2Error (C shim: an Error was logged)
            assert any("not a state of this FMU" in m for m in a.log), (what, a.log)
            free_state(a, st)
            assert not marker.exists(), f"{what}: the payload ran"
        # the instance is unchanged and still works: restore the good state, same outputs
        st = deserialize(a, good)
        a.call("fmi2SetFMUstate", st)
        free_state(a, st)
        assert drv.run(5, 5) == ref
