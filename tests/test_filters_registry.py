"""The filter registry: every kind behind one interface; filterpy imported for IMM only."""

from __future__ import annotations

import subprocess
import sys

import pytest

from axir.models.filters.base import FilterConfig
from axir.models.filters.registry import FILTER_KINDS, make_axis_filter


def test_factory_and_interface() -> None:
    for kind in FILTER_KINDS:
        f = make_axis_filter(kind, FilterConfig())
        assert f.kind == kind and not f.initialised
        f.update(10.0, 1.0)
        assert f.x == (10.0, 0.0, 0.0) and f.n == 1
        for k in range(1, 6):
            f.update(10.0 + 5.0 * k, 1.0)
        assert f.x[1] == pytest.approx(5.0, abs=1.0) and len(f.P) == 3
        assert f.predict(0.0)[0] == pytest.approx(f.x[0])
        f.reset()
        assert not f.initialised
    with pytest.raises(ValueError, match="unknown filter kind"):
        make_axis_filter("ukf")
    with pytest.raises(ValueError, match="svd_reduced"):
        make_axis_filter("kalman", FilterConfig(quant=lambda name, v: v))


def test_default_tracker_does_not_import_filterpy() -> None:
    """The registry imports the IMM module (filterpy) lazily: building and stepping the default
    Tracker (α-β filters, beams mode) leaves filterpy unloaded; asking for IMM loads it."""
    code = (
        "import sys\n"
        "import numpy as np\n"
        "from axir.models.tracker import Tracker\n"
        "trk = Tracker()\n"
        "trk.step(1e-4, {'beam': np.ones((4, 16, 3)), 'ped.az': 0.0, 'ped.el': 0.1, 'mode': 2})\n"
        "assert 'filterpy' not in sys.modules, 'default Tracker imported filterpy'\n"
        "Tracker(filter_x='imm')\n"
        "assert 'filterpy' in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
