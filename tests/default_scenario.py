"""The default ``closed-loop`` scenario in the direct loop (no FMUs): lock time, drops, RMS
range error while confirmed (issue 11 "must keep"). ``python tests/default_scenario.py [S]``."""

from __future__ import annotations

import math
import sys

sys.path.insert(0, "benchmarks")
from bench_loop import _scenario, direct_params

from axir.models.loop import DirectLoop


def main(duration: float) -> None:
    loop = DirectLoop.from_params(direct_params(_scenario(duration)))
    prev, lock, drops, se, n = None, math.nan, 0, 0.0, 0
    while loop.t < duration:
        loop.step()
        m = loop.out["RadarManager"]["mode"]
        if m == 2:
            if prev != 2 and math.isnan(lock):
                lock = loop.t
            e = loop.out["Tracker"]["track.range"] - loop.out["TargetGenerator"]["truth.range"]
            se += e * e
            n += 1
        if prev == 2 and m != 2:
            drops += 1
        prev = m
    print(f"closed-loop {duration:g} s (direct loop): lock {lock:.4f} s, drops {drops}, "
          f"RMS range confirmed {math.sqrt(se / max(n, 1)):.2f} m over {n} PRIs")


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 40.0)
