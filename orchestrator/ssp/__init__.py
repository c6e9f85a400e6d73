"""SSP 1.0 export and import: one archive drives libcosim, other SSP tools and our master.

Modules: :mod:`.format` (namespaces, file names), :mod:`.export` (write an archive),
:mod:`.validate` (schema check), :mod:`.importer` (read an archive as a scenario),
:mod:`.cli` (``axir export-ssp``); the libcosim runner is :mod:`axir.orchestrator.tools.libcosim`.

``axir export-ssp [SCENARIO] -o radar.ssp`` writes an SSP 1.0 archive (Modelica Association
"System Structure and Parameterization" 1.0, schemas shipped in ``fmpy/ssp/schema``)::

    SystemStructure.ssd          the system: components, connectors, connections, units,
                                 DefaultExperiment (start, stop, fixed step)
    resources/<Unit>.fmu         the FMUs, byte for byte
    resources/<Unit>.ssv         one SSP parameter set per component (the scenario's values)

Decisions (documented in docs/other_tools.md):

- **Fixed step, Jacobi.** SSP has no variable step driven by an output, and libcosim's
  ``fixed_step_algorithm`` steps every FMU from the outputs at t, then transfers (Jacobi). The
  archive therefore describes a fixed-step Jacobi run: the step is the scenario's fixed step,
  else ``--step`` (default :data:`.export.DEFAULT_STEP`); it is written as the OSP annotation
  ``osp:FixedStepAlgorithm baseStepSize`` in the DefaultExperiment (libcosim reads it).
- **Jacobi parameters.** Parameters that depend on the master's order get their Jacobi value
  (:data:`axir.models.system.JACOBI_PARAMETERS`: the Tracker's ``gate_latency`` is 2 with a
  Jacobi master).
- **Seeds are explicit.** Every unit with a ``seed`` parameter gets the per-unit seed our
  master derives (:func:`axir.models.system.unit_seed`), written into its ``.ssv``, so a third-party
  master draws the same random numbers.
- **One ``.ssv`` per component.** libcosim applies component-level parameter bindings only
  (names = the FMU's variable names); a system-level set with prefixed names would be ignored.
- **Scalar connections.** Array connections are expanded element-wise (FMI 2.0 structured
  names, ``beam.up[3,2]``); every component declares a connector for each of its inputs,
  outputs and set parameters, with its SSP type and unit.
- **Namespace prefixes** are the conventional ``ssd``/``ssc``/``ssv``/``osp``: libcosim's
  parser (boost property_tree) matches element names with their prefixes literally.
- An ``org.axir.run`` annotation keeps what SSP cannot say (scenario name, base seed, recorded
  variables, decimation, the master algorithm); other tools ignore it.

:func:`.importer.load_ssp` reads such an archive (or any SSP 1.0 ``.ssp``/``.ssd`` within the
supported subset: FMU components, component-level parameter sets, connections without
transformations) into the same :class:`~axir.orchestrator.scenario_spec.Scenario` a TOML
file gives, so ``axir run radar.ssp`` runs the file our master and libcosim both read.
"""

