"""Optimisation and global sensitivity as study kinds.

``kind = "optimise"``
    Maximise or minimise one output over the parameters' bounds, subject to bounds on
    other outputs (``[study.constraints]``, e.g. ``max_YQ = { max = 0.8 }``):

    ``differential-evolution`` (default)
        :func:`scipy.optimize.differential_evolution` in the unit cube of the bounds
        (geometric for ``scale = "log"``), constraints by Deb's feasibility rules
        (:class:`scipy.optimize.NonlinearConstraint`), a whole population evaluated at once
        on the study's workers; ``population`` members per parameter, ``iterations``
        generations, the study seed.
    ``cobyla``
        :func:`scipy.optimize.minimize` (COBYLA) from the centre of the bounds, one
        evaluation at a time, at most ``iterations * population`` of them.

    Every evaluation is a row of the results file, in the order of evaluation (the
    history); the best feasible one is reported. A point whose outputs could not be
    computed counts as infeasible. The optimiser is deterministic, so ``--resume``
    replays it from the checkpoint and evaluates only what is missing.

``kind = "sobol-indices"``
    First-order and total Sobol indices (:func:`SALib.analyze.sobol.analyze`, bootstrap
    confidence intervals with the study seed) of every output, from Saltelli's points
    (:func:`~express.analysis.study.sampling.saltelli_points`); written beside the results
    as ``RESULTS.indices.csv``.
"""

from __future__ import annotations

import csv
import io
import math
import sys
import warnings

import numpy as np

from express.analysis.study.results import Checkpoint, ResultTable
from express.analysis.study.runner import Engine
from express.analysis.study.sampling import salib_problem, to_ranges
from express.analysis.study.spec import StudySpec
from express.base.diagnostics import UsageError

__all__ = ["indices_csv", "run_optimisation", "sobol_indices"]

#: Stand-in for an output that could not be computed, far outside any bound.
_FAR = 1e300


class _History:
    """Evaluations in order, each computed once (cached by vector) and checkpointed."""

    def __init__(self, spec: StudySpec, engine: Engine, checkpoint: Checkpoint, progress):
        self.spec = spec
        self.engine = engine
        self.checkpoint = checkpoint
        self.saved = {record["point"]: record for record in checkpoint.records()}
        self.records: list[dict] = []
        self.by_vector: dict[bytes, dict] = {}
        self.computed = 0
        self.progress = progress

    def evaluate(self, unit_points: np.ndarray) -> list[dict]:
        """Records of the points (unit cube, shape (S, D)), new ones evaluated together."""
        # COBYLA may step slightly outside its bounds: evaluate on the bounds instead
        vectors = to_ranges(np.clip(np.atleast_2d(unit_points), 0.0, 1.0), self.spec.parameters)
        wanted: list[dict | None] = []
        new_indices, new_vectors = [], []
        for vector in vectors:
            key = vector.tobytes()
            if key in self.by_vector:
                wanted.append(self.by_vector[key])
                continue
            index = len(self.records)
            saved = self.saved.get(index)
            if saved is not None:
                if saved["values"] != vector.tolist():
                    raise UsageError(f"{self.checkpoint.path}: the checkpoint does not match this optimisation; "
                                     "delete it to start again")
                record = saved
            else:
                record = {"point": index, "values": vector.tolist(), "pending": True}
                new_indices.append(index)
                new_vectors.append(vector)
            self.records.append(record)
            self.by_vector[key] = record
            wanted.append(record)
        if new_indices:
            for records in self.engine.run(new_indices, np.array(new_vectors)):
                self.checkpoint.append(records)
                for done in records:
                    self.records[done["point"]].clear()
                    self.records[done["point"]].update(done)
                if self.progress is not None:
                    self.progress.update(len(records))
            self.computed += len(new_indices)
        return [r for r in wanted if r is not None]

    def output(self, record: dict, name: str) -> float:
        value = record["outputs"][self.spec.outputs.index(name)]
        return math.nan if value is None else float(value)


def _objective(history: _History, spec: StudySpec):
    sense, name = spec.objective  # type: ignore[misc]
    sign = -1.0 if sense == "maximise" else 1.0

    def energy(points: np.ndarray) -> np.ndarray:  # DE's vectorized form: shape (D, S)
        records = history.evaluate(np.asarray(points).T)
        values = np.array([sign * history.output(r, name) for r in records])
        return np.where(np.isfinite(values), values, _FAR)

    return energy


def _constraint_values(history: _History, spec: StudySpec, points: np.ndarray) -> np.ndarray:
    """Constraint outputs, shape (M, S); an output that could not be computed violates."""
    records = history.evaluate(points)
    rows = []
    for c in spec.constraints:
        values = np.array([history.output(r, c.output) for r in records])
        far = c.upper + _FAR if c.upper is not None else c.lower - _FAR  # type: ignore[operator]
        rows.append(np.where(np.isfinite(values), values, far))
    return np.array(rows)


def _vectorized_constraints(history: _History, spec: StudySpec, x) -> np.ndarray:
    """DE's vectorized constraint form: ``x`` shape (D, S) -> (M, S); (D,) -> (M,)."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        return _constraint_values(history, spec, x[None, :])[:, 0]
    return _constraint_values(history, spec, x.T)


def _feasible(history: _History, spec: StudySpec, record: dict) -> bool:
    for c in spec.constraints:
        value = history.output(record, c.output)
        if not math.isfinite(value) or (c.upper is not None and value > c.upper) or (
            c.lower is not None and value < c.lower
        ):
            return False
    _sense, name = spec.objective  # type: ignore[misc]
    return math.isfinite(history.output(record, name))


def run_optimisation(spec: StudySpec, engine: Engine, checkpoint: Checkpoint, units: dict[str, str], progress: bool):
    """Run the optimiser (module docstring); returns the history table, the number of
    points evaluated by this run and ``{"best": ...}``."""
    from scipy.optimize import NonlinearConstraint, differential_evolution, minimize

    d = len(spec.parameters)
    settings = spec.optimiser
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(unit="pt", file=sys.stderr, dynamic_ncols=True, desc="optimise")
    history = _History(spec, engine, checkpoint, bar)
    try:
        if settings["method"] == "differential-evolution":
            constraints = [NonlinearConstraint(lambda x: _vectorized_constraints(history, spec, x),
                                               [c.lower if c.lower is not None else -np.inf for c in spec.constraints],
                                               [c.upper if c.upper is not None else np.inf for c in spec.constraints])]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)  # "differential_evolution: the 'workers' ..."
                differential_evolution(
                    _objective(history, spec), [(0.0, 1.0)] * d, vectorized=True, updating="deferred",
                    popsize=settings["population"], maxiter=settings["iterations"], tol=settings["tolerance"],
                    seed=spec.seed, polish=False, init="latinhypercube",
                    constraints=constraints if spec.constraints else (),
                )
        else:
            energy = _objective(history, spec)
            cons = []
            for k, c in enumerate(spec.constraints):
                def value(x, k=k):
                    return _constraint_values(history, spec, np.asarray(x)[None, :])[k, 0]
                if c.upper is not None:
                    cons.append({"type": "ineq", "fun": lambda x, v=value, u=c.upper: u - v(x)})
                if c.lower is not None:
                    cons.append({"type": "ineq", "fun": lambda x, v=value, lo=c.lower: v(x) - lo})
            minimize(lambda x: float(energy(np.asarray(x)[:, None])[0]), np.full(d, 0.5), method="COBYLA",
                     bounds=[(0.0, 1.0)] * d, constraints=cons,
                     options={"maxiter": settings["iterations"] * settings["population"], "rhobeg": 0.25,
                              "tol": settings["tolerance"]})
    finally:
        if bar is not None:
            bar.close()
    table = ResultTable.empty(spec.names, units, spec.outputs, len(history.records))
    for record in history.records:
        table.add(record)
    return table, history.computed, {"best": _best(history, spec)}


def _best(history: _History, spec: StudySpec) -> dict | None:
    sense, name = spec.objective  # type: ignore[misc]
    feasible = [r for r in history.records if _feasible(history, spec, r)]
    if not feasible:
        return None
    pick = max if sense == "maximise" else min
    best = pick(feasible, key=lambda r: (history.output(r, name), -r["point"]))
    return {"point": best["point"], "parameters": dict(zip(spec.names, best["values"], strict=True)),
            "outputs": {n: history.output(best, n) for n in spec.outputs}, "objective": name, "sense": sense,
            "evaluations": len(history.records)}


def sobol_indices(spec: StudySpec, table: ResultTable) -> dict[str, dict]:
    """First-order and total Sobol indices of every output (nan when a point failed)."""
    from SALib.analyze import sobol

    problem = salib_problem(spec.parameters)
    result: dict[str, dict] = {}
    for name in spec.outputs:
        y = table.column(name)
        entry: dict = {}
        if not np.all(np.isfinite(y)):
            entry = {key: [math.nan] * len(spec.names) for key in ("S1", "S1_conf", "ST", "ST_conf")}
            entry["note"] = f"{int(np.sum(~np.isfinite(y)))} points have no {name}; indices not computed"
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                analysis = sobol.analyze(problem, y, calc_second_order=False, print_to_console=False, seed=spec.seed)
            entry = {key: [float(v) for v in analysis[key]] for key in ("S1", "S1_conf", "ST", "ST_conf")}
        entry["parameters"] = list(spec.names)
        result[name] = entry
    return result


def indices_csv(indices: dict[str, dict]) -> bytes:
    """``output,parameter,S1,S1_conf,ST,ST_conf`` rows."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["output", "parameter", "S1", "S1_conf", "ST", "ST_conf"])
    for output, entry in indices.items():
        for k, parameter in enumerate(entry["parameters"]):
            writer.writerow([output, parameter] + [repr(entry[key][k]) if math.isfinite(entry[key][k]) else "nan"
                                                   for key in ("S1", "S1_conf", "ST", "ST_conf")])
    return buffer.getvalue().encode("utf-8")
