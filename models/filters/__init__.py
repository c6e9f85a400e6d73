"""Per-axis tracking filters (seed 000 α-β, seed 002 Kalman/FMD/SVD/VD, IMM for comparison).

Layers, imports one way: :mod:`.fmd` (detector) and :mod:`.gains` (α-β gain laws) ←
:mod:`.base` (interface, :class:`~.base.FilterConfig`) ← the filters (:mod:`.alphabeta`,
:mod:`.kalman`, :mod:`.svd`, :mod:`.vd`, :mod:`.imm`; :mod:`.fixedpoint` is the Table 3
quantiser of :mod:`.svd`) ← :mod:`.registry` (``FILTER_KINDS``, ``make_axis_filter``).
This ``__init__`` imports nothing, so ``import axir.models.filters.x`` stays light
(filterpy is imported by :mod:`.imm` only). See docs/filters.md.
"""
