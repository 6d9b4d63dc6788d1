"""The points of a study: parameter vectors (SI), one row per point, in a fixed order.

=================  ===================================================================
kind               points
=================  ===================================================================
``grid``           every combination of the parameters' values, the last parameter
                   varying fastest (file order)
``lhs``            ``samples`` points of a Latin hypercube (:class:`scipy.stats.qmc.LatinHypercube`)
``sobol``          ``samples`` points of a scrambled Sobol sequence (:class:`scipy.stats.qmc.Sobol`)
``sobol-indices``  Saltelli's scheme for Sobol indices (:func:`SALib.sample.sobol.sample`):
                   ``samples * (D + 2)`` points for first and total indices of D parameters
=================  ===================================================================

Sampled kinds map the unit interval onto ``[from, to]`` linearly, or geometrically for
``scale = "log"``. The seed (``study.seed``, default 0) makes the points, and so the
results file, the same on every run.
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Sequence

import numpy as np

from express.analysis.study.spec import ParameterRange, StudySpec
from express.base.diagnostics import ArgumentError

__all__ = ["grid_points", "saltelli_points", "sample_points", "study_points", "to_ranges"]


def grid_points(ranges: Sequence[ParameterRange]) -> np.ndarray:
    """Every combination of the values, last parameter fastest; shape (N, D)."""
    return np.array(list(itertools.product(*(r.values for r in ranges))), dtype=float).reshape(-1, len(ranges))


def to_ranges(unit: np.ndarray, ranges: Sequence[ParameterRange]) -> np.ndarray:
    """Map points of the unit cube, shape (N, D), onto the parameters' bounds."""
    out = np.empty_like(unit, dtype=float)
    for j, r in enumerate(ranges):
        if r.scale == "log":
            out[:, j] = r.low * (r.high / r.low) ** unit[:, j]
        else:
            out[:, j] = r.low + (r.high - r.low) * unit[:, j]
    return out


def sample_points(ranges: Sequence[ParameterRange], kind: str, samples: int, seed: int) -> np.ndarray:
    """``lhs`` or ``sobol`` points, shape (samples, D)."""
    from scipy.stats import qmc

    d = len(ranges)
    if kind == "lhs":
        unit = qmc.LatinHypercube(d=d, seed=seed).random(samples)
    elif kind == "sobol":
        with warnings.catch_warnings():  # a count that is not a power of two is allowed
            warnings.simplefilter("ignore", UserWarning)
            unit = qmc.Sobol(d=d, scramble=True, seed=seed).random(samples)
    else:
        raise ArgumentError(f"unknown sampling kind {kind!r}")
    return to_ranges(unit, ranges)


def salib_problem(ranges: Sequence[ParameterRange]) -> dict:
    """The SALib problem of the parameters (bounds on the unit interval: the scale is
    applied by :func:`to_ranges`, so that a log parameter is sampled evenly in log)."""
    return {"num_vars": len(ranges), "names": [r.name for r in ranges], "bounds": [[0.0, 1.0]] * len(ranges)}


def saltelli_points(ranges: Sequence[ParameterRange], samples: int, seed: int) -> np.ndarray:
    """Saltelli's sample for first-order and total Sobol indices, shape (samples (D + 2), D)."""
    from SALib.sample import sobol as sobol_sample

    with warnings.catch_warnings():  # SALib warns when samples is not a power of two
        warnings.simplefilter("ignore")
        unit = sobol_sample.sample(salib_problem(ranges), samples, calc_second_order=False, seed=seed)
    return to_ranges(np.asarray(unit, dtype=float), ranges)


def study_points(spec: StudySpec) -> np.ndarray:
    """The points of a (non-optimising) study, shape (N, D), SI."""
    if spec.kind == "grid":
        return grid_points(spec.parameters)
    if spec.kind in ("lhs", "sobol"):
        return sample_points(spec.parameters, spec.kind, spec.samples, spec.seed)
    if spec.kind == "sobol-indices":
        return saltelli_points(spec.parameters, spec.samples, spec.seed)
    raise ArgumentError(f"a {spec.kind} study has no fixed points")
