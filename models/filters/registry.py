"""The filter registry: the kinds a Tracker axis can run and the factory that builds them.

Layering: :mod:`.base` (interface, tuning) ← the filter modules ← this registry. The IMM filter
runs on filterpy, so :mod:`.imm` is imported only when an IMM filter is requested: a Tracker
with the default α-β filters never imports filterpy (bundled FMUs stay light to load).
"""

from __future__ import annotations

from .alphabeta import AlphaBetaAxis
from .base import AxisFilter, FilterConfig
from .kalman import KalmanCV
from .svd import SVDFilter, SVDReducedFilter
from .vd import VDFilter

#: Filter kinds accepted by :func:`make_axis_filter` (and the Tracker's ``filter_*``).
FILTER_KINDS = ("alphabeta", "kalman", "svd", "svd_reduced", "vd", "imm")

#: Python packages beyond numpy/scipy a filter kind needs (the rest run on numpy alone). An FMU
#: records them per parameter value, so ``axir requirements`` can say what a host Python needs.
EXTRA_PACKAGES: dict[str, tuple[str, ...]] = {"imm": ("filterpy",)}

_CLASSES: dict[str, type[AxisFilter]] = {
    "alphabeta": AlphaBetaAxis, "kalman": KalmanCV, "svd": SVDFilter,
    "svd_reduced": SVDReducedFilter, "vd": VDFilter,
}


def _filter_class(kind: str) -> type[AxisFilter]:
    """The class of filter ``kind`` (one of :data:`FILTER_KINDS`); imports filterpy for "imm"
    only."""
    if kind == "imm":
        try:
            from .imm import IMMFilter  # lazy: filterpy only when an IMM filter is requested
        except ImportError as e:
            raise ValueError(f"filter kind 'imm' needs the Python package "
                             f"{' and '.join(EXTRA_PACKAGES['imm'])} (pip install "
                             f"{' '.join(EXTRA_PACKAGES['imm'])}) in the Python this runs on: "
                             f"{e}") from None
        return IMMFilter
    try:
        return _CLASSES[kind]
    except KeyError:
        raise ValueError(f"unknown filter kind {kind!r}: valid {', '.join(FILTER_KINDS)}") \
            from None


def make_axis_filter(kind: str, cfg: FilterConfig | None = None) -> AxisFilter:
    """A fresh filter of ``kind`` (one of :data:`FILTER_KINDS`)."""
    cls = _filter_class(kind)
    if cfg is not None and cfg.quant is not None and kind != "svd_reduced":
        raise ValueError(f"fixed-point emulation is implemented for 'svd_reduced' only, "
                         f"not {kind!r}")
    return cls(cfg)
