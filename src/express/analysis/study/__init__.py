"""Design studies: parameter studies over many variants of one vehicle, exact
sensitivities and optimisation (``docs/studies.md``).

Modules
-------
spec
    The study file (``[study]`` in TOML): reading and checking, every problem at once.
sampling
    The points of a study: grid, Latin hypercube, Sobol sequence, Saltelli samples.
outputs
    The quantities computed at every point (critical speed, damping, Q/P, FRF peak).
runner
    Evaluation of the points on local processes or a Dask cluster.
run
    A study end to end: checkpoint, resume, the final file (``express study``).
results
    The checkpoint and the results file: CSV, Parquet or netCDF.
critical
    Fast critical speed (exact crossing, same reported value as the stability code).
sensitivity
    Exact derivatives of eigenvalues and of the critical speed.
derivatives
    Derivatives of the matrices and of the parameter graph, compiled once per model.
optimise
    Bounded optimisation with constraints; Sobol indices.
figures
    Critical-speed map and tornado chart.
"""
