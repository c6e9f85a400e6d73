"""Bundling (fmus/bundle.py, fmus/digest.py): import closure, hash, reproducible zip."""

from __future__ import annotations

import zipfile
from pathlib import Path

from axir.fmus.bundle import collect_sources, write_reproducible_zip
from axir.fmus.digest import source_digest


def test_closure_only_needed_models() -> None:
    src = collect_sources("pedestal_fmu")
    assert "models/pedestal.py" in src and "models/radar/unit.py" in src
    assert "models/radar/antenna.py" not in src  # not imported by the pedestal


def test_closure_has_no_build_time_code() -> None:
    """Only the runtime slave and what it needs ship in an FMU: no modelDescription writer,
    unit table, bundler or builder."""
    src = collect_sources("tracker_fmu")
    assert {"fmus/slave.py", "fmus/spec.py", "fmus/digest.py", "fmus/tracker_fmu.py"} <= set(src)
    for build_only in ("fmus/model_description.py", "fmus/units.py", "fmus/bundle.py",
                       "fmus/build.py"):
        assert build_only not in src


def test_source_digest_depends_on_paths_and_content_not_order() -> None:
    a = [("x.py", b"1"), ("y.py", b"2")]
    assert source_digest(a) == source_digest(a[::-1])
    assert source_digest(a) != source_digest([("x.py", b"2"), ("y.py", b"1")])
    assert source_digest([("a/b.py", b"")]) != source_digest([("a/c.py", b"")])


def test_reproducible_zip(tmp_path: Path) -> None:
    entries = {"b.txt": b"b" * 100, "modelDescription.xml": b"<x/>",
               "binaries/linux64/x.so": b"\x7fELF", "a.txt": b"a"}
    p, q = tmp_path / "p.fmu", tmp_path / "q.fmu"
    write_reproducible_zip(p, entries)
    write_reproducible_zip(q, dict(reversed(list(entries.items()))))
    assert p.read_bytes() == q.read_bytes()
    with zipfile.ZipFile(p) as z:
        infos = z.infolist()
        assert [i.filename for i in infos] == ["modelDescription.xml", "a.txt", "b.txt",
                                               "binaries/linux64/x.so"]
        assert {i.date_time for i in infos} == {(1980, 1, 1, 0, 0, 0)}
        assert (z.getinfo("binaries/linux64/x.so").external_attr >> 16) & 0o777 == 0o755
        assert (z.getinfo("a.txt").external_attr >> 16) & 0o777 == 0o644
        assert {n: z.read(n) for n in z.namelist()} == entries
    r = tmp_path / "r.ssp"
    write_reproducible_zip(r, entries, first=("b.txt",), stored=lambda n: n.endswith(".txt"))
    with zipfile.ZipFile(r) as z:
        assert z.namelist()[0] == "b.txt"
        assert z.getinfo("a.txt").compress_type == zipfile.ZIP_STORED
        assert z.getinfo("modelDescription.xml").compress_type == zipfile.ZIP_DEFLATED
    assert not list(tmp_path.glob("*.tmp"))
