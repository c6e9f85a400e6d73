"""Regenerate every seed reproduction report (figures, markdown and JSON under reports/out/).

Builds the four FMUs once from the working tree (``axir.fmus.build.build_all``, into a
temporary directory unless ``--fmu-dir`` is given), then runs ``seed000.py``, ``seed001.py``,
``seed002.py`` and ``seed002_constants.py`` one after the other, each in its own Python process,
with ``--fmu-dir`` and ``--out`` passed on.
Stops at the first report that fails and exits with its status.

Usage: ``.venv/bin/python reports/make_all.py [--fmu-dir DIR] [--out DIR] [--only seed002]
[--runs N]`` (``--runs``: Monte Carlo runs of seed002 and seed002_constants, default 50).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPORTS = ("seed000", "seed001", "seed002", "seed002_constants")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu-dir", type=Path, default=None,
                    help="directory with the four FMUs (default: build them into a temp dir)")
    ap.add_argument("--out", type=Path, default=HERE / "out", help="output directory")
    ap.add_argument("--only", action="append", choices=REPORTS,
                    help="run only this report (repeatable)")
    ap.add_argument("--runs", type=int, default=None, help="seed002: Monte Carlo runs (50)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="axir_reports_fmus_") as tmp:
        fmu_dir = args.fmu_dir
        if fmu_dir is None:
            from axir.fmus.build import build_all

            fmu_dir = Path(tmp)
            build_all(fmu_dir)
            print(f"make_all: built the FMUs into {fmu_dir}", flush=True)
        for name in args.only or REPORTS:
            cmd = [sys.executable, str(HERE / f"{name}.py"), "--fmu-dir", str(fmu_dir),
                   "--out", str(args.out)]
            if name.startswith("seed002") and args.runs is not None:
                cmd += ["--runs", str(args.runs)]
            t0 = time.perf_counter()
            print(f"make_all: {' '.join(cmd[1:])}", flush=True)
            code = subprocess.call(cmd)
            print(f"make_all: {name} exited {code} after {time.perf_counter() - t0:.0f} s",
                  flush=True)
            if code != 0:
                return code
    print(f"make_all: reports in {args.out}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
