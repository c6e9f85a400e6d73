"""Run an SSP archive in libcosim (PyPI ``libcosimpy``, a test dependency): the third-party
master our own is compared with (tests/test_libcosim.py, benchmarks/bench_libcosim.py)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..errors import AxirError
from ..ssp.importer import load_ssp


def run_libcosim(path: Path, variables: list[str], duration: float | None = None,
                 ) -> tuple[Any, Any]:
    """Run an SSP archive in libcosim (PyPI ``libcosimpy``, a test dependency) and record
    ``variables`` (``"Unit.variable"``) after every step.

    libcosim reads the archive itself (its SSP loader: components, ``.ssv`` parameter sets,
    connections, the ``osp:FixedStepAlgorithm`` step) and runs its fixed-step algorithm:
    every FMU steps from the outputs at t, then outputs are transferred (Jacobi).

    Returns ``(t, data)``: the times [s] after each step (numpy array, n) and the recorded
    values (n × len(variables)). The execution (instances and FMU libraries) is destroyed
    before returning.
    """
    import numpy as np

    try:
        from libcosimpy.CosimEnums import CosimVariableType
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
    except ImportError:  # pragma: no cover - libcosimpy is a test dependency
        raise AxirError("libcosim is not installed: pip install libcosimpy") from None
    sc = load_ssp(path)
    stop = sc.duration if duration is None else duration
    step_ns = round(sc.step * 1e9)
    n = round(stop * 1e9) // step_ns
    log_output_level(CosimLogLevel.WARNING)
    ex = CosimExecution.from_ssp_file(str(Path(path).resolve()))
    try:
        obs = CosimObserver.create_last_value()
        ex.add_observer(obs)
        reads: dict[tuple[int, Any], tuple[list[int], list[int]]] = {}
        for col, ref in enumerate(variables):
            unit, _, var = ref.partition(".")
            idx = ex.slave_index_from_instance_name(unit)
            if idx is None:
                raise AxirError(f"libcosim: no instance {unit!r} in {path}")
            found = {v.name.decode(): v for v in ex.slave_variables(idx)}.get(var)
            if found is None:
                raise AxirError(f"libcosim: {unit} has no variable {var!r}")
            vrs, cols = reads.setdefault((idx, found.type), ([], []))
            vrs.append(found.reference)
            cols.append(col)
        getters = {CosimVariableType.REAL.value: obs.last_real_values,
                   CosimVariableType.INTEGER.value: obs.last_integer_values,
                   CosimVariableType.BOOLEAN.value: obs.last_boolean_values}
        plan = [(getters[kind], idx, vrs, cols) for (idx, kind), (vrs, cols) in reads.items()]
        data = np.empty((n, len(variables)))
        t = np.empty(n)
        for k in range(n):
            if not ex.step(1):
                raise AxirError(f"libcosim: step {k + 1} failed: {ex.status()}")
            for get, idx, vrs, cols in plan:
                data[k, cols] = get(idx, vrs)
            t[k] = ex.status().current_time / 1e9
    finally:
        del ex  # cosim_execution_destroy: frees the instances and unloads the FMUs
    return t, data
