"""Running a study file end to end: points, checkpoint, final file (``express study``).

:func:`run_study` checks the destination, builds the vehicle (a bad model stops here,
before anything is written), evaluates the points that the checkpoint lacks on the
chosen :class:`~express.analysis.study.runner.Engine`, appending each finished chunk to
the checkpoint, then writes the final file whole and removes the checkpoint. A study
killed mid-way continues with ``resume=True``; the final file is the same as an
uninterrupted run's, because the rows are in point order and every number is written
exactly.
"""

from __future__ import annotations

import hashlib
import math
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from express import __version__
from express.analysis.study import runner
from express.analysis.study.outputs import OUTPUTS
from express.analysis.study.results import FORMATS, Checkpoint, ResultTable, checkpoint_path, result_bytes
from express.analysis.study.runner import Engine, blocked, make_task
from express.analysis.study.sampling import study_points, to_ranges
from express.analysis.study.spec import StudySpec
from express.base.data import DataRecord
from express.base.diagnostics import UsageError

__all__ = ["StudySummary", "default_workers", "parameter_units", "run_study", "study"]


@dataclass(frozen=True, repr=False)
class StudySummary(DataRecord):
    """What a finished study did.

    Attributes
    ----------
    output : Path
    points : int
        Points in the results file.
    computed : int
        Points evaluated by this run (the others came from the checkpoint).
    failed : int
        Points with a message in ``error`` and no value for some output.
    seconds : float
        Wall-clock time of this run.
    workers : int
    extra : dict
        ``best`` (optimise), ``indices`` (sobol-indices), ``files`` written besides the output.
    table : ResultTable or None
        The results in memory (:meth:`to_xarray`, :meth:`to_pandas`).
    """

    output: Path
    points: int
    computed: int
    failed: int
    seconds: float
    workers: int
    extra: dict = field(default_factory=dict)
    table: ResultTable | None = field(default=None, repr=False, compare=False)

    def as_dict(self) -> dict[str, Any]:
        return {"output": str(self.output), "points": self.points, "computed": self.computed,
                "failed": self.failed, "seconds": self.seconds, "workers": self.workers, **self.extra}

    def to_xarray(self):
        """The study's results as an :class:`xarray.Dataset` over ``point`` (each parameter
        and output with its ``units``; ``error``): the table this run wrote, else the
        output file read back."""
        if self.table is not None:
            return self.table.to_xarray()
        from express.analysis.result_data import study_dataset
        from express.analysis.study.results import read_table

        return study_dataset(read_table(self.output), {name: unit for name, (unit, _) in OUTPUTS.items()})

    def _summary(self) -> list[str]:
        return [f"{self.points} points in {self.output} ({self.computed} computed, {self.failed} failed)",
                f"{self.seconds:.2f} s on {self.workers} worker(s)"]


def default_workers() -> int:
    """All local cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def parameter_units(spec: StudySpec) -> dict[str, str]:
    """SI unit of every varied parameter (from its dimension) and output."""
    from express.base.units import DIMENSIONS, dimension_of, si_unit
    from express.io import load_model

    model = load_model(spec.model)
    units = {name: unit for name, (unit, _group) in OUTPUTS.items()}
    for r in spec.parameters:
        parameter = model.parameters[r.name]
        known = getattr(parameter, "dimension", None)
        unit = ""
        if isinstance(known, str) and known in DIMENSIONS:
            unit = si_unit(known)
        elif known is not None:
            unit = next((si_unit(n) for n, d in DIMENSIONS.items() if d == known), getattr(known, "si", lambda: "")())
        elif parameter.unit or r.unit:
            try:
                name = dimension_of(parameter.unit or r.unit)
                unit = si_unit(name) if name in DIMENSIONS else name
            except ValueError:
                unit = ""
        units[r.name] = "" if unit in ("-", "1") else unit
    return units


def _metadata(spec: StudySpec) -> dict[str, str]:
    return {"study": spec.text, "study_file": spec.path.name, "model": spec.model.name, "kind": spec.kind,
            "title": spec.title, "software": f"EXPRESS {__version__}",
            "linearisation": spec.settings.linearisation_spec.describe()}


def _progress(total: int, done: int, enabled: bool):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, initial=done, unit="pt", file=sys.stderr, dynamic_ncols=True, smoothing=0.1)


def _check_output(spec: StudySpec, output: Path) -> None:
    from express.io.output import check_destination

    if output.suffix.lower() not in FORMATS:
        raise UsageError(f"-o {output}: unknown results format; use {', '.join(FORMATS)}")
    check_destination(output, inputs=[spec.path, spec.model], binary=True)


#: Hours a study may be estimated to take on the workers at hand before it is refused
#: (``--max-hours`` raises it; ``docs/studies.md``).
MAX_HOURS = 24.0
#: Points evaluated (and discarded) to estimate the cost of a study of more than
#: :data:`CALIBRATE_ABOVE` points: the first, the middle and the last; the median counts.
CALIBRATION_POINTS = 3
CALIBRATE_ABOVE = 1000


@dataclass(frozen=True)
class CostEstimate:
    """What a study will cost, from a calibration before it starts.

    Attributes
    ----------
    points : int
        Points left to evaluate.
    seconds_per_point : float
        Median of the calibration points, in this process.
    workers : int
        Workers at hand (local processes, or the cluster's threads); 1 for an optimiser
        that evaluates one point at a time (COBYLA).
    what : str
        What :attr:`points` counts, for the message.
    """

    points: int
    seconds_per_point: float
    workers: int
    what: str = "points"

    @property
    def hours(self) -> float:
        return self.points * self.seconds_per_point / max(1, self.workers) / 3600.0


def estimate_cost(engine: Engine, indices: np.ndarray, points: np.ndarray) -> CostEstimate:
    """Time a few points (:data:`CALIBRATION_POINTS`) in this process and scale to the
    study's ``indices`` on the engine's workers."""
    picks = sorted({0, len(indices) // 2, len(indices) - 1})[:CALIBRATION_POINTS]
    return CostEstimate(len(indices), _seconds_per_point(engine, [int(indices[k]) for k in picks],
                                                         points[picks]), engine.parallel)


def _seconds_per_point(engine: Engine, indices: list[int], points: np.ndarray) -> float:
    """Median time of evaluating ``points`` one by one in this process (s)."""
    times = []
    for index, point in zip(indices, points, strict=True):
        started = time.perf_counter()
        runner.evaluate_points(engine.task, [index], [np.asarray(point).tolist()])
        times.append(time.perf_counter() - started)
    return float(np.median(times))


def optimisation_evaluations(spec: StudySpec) -> int:
    """The most evaluations the optimiser of ``spec`` may ask for: ``population x
    parameters x (iterations + 1)`` for differential evolution (the first population and
    one per generation), ``iterations x population`` for COBYLA."""
    settings = spec.optimiser
    if settings["method"] == "cobyla":
        return int(settings["iterations"] * settings["population"])
    return int(settings["population"] * len(spec.parameters) * (settings["iterations"] + 1))


def estimate_optimisation_cost(engine: Engine, spec: StudySpec, done: int) -> CostEstimate:
    """Time :data:`CALIBRATION_POINTS` points of the bounds (a quarter, the middle and
    three quarters of every range) and scale to the optimiser's remaining maximum number
    of evaluations; differential evolution evaluates a population at once on the
    engine's workers, COBYLA one point at a time."""
    fractions = np.linspace(0.25, 0.75, CALIBRATION_POINTS)
    points = to_ranges(np.repeat(fractions[:, None], len(spec.parameters), axis=1), spec.parameters)
    seconds = _seconds_per_point(engine, list(range(CALIBRATION_POINTS)), points)
    workers = 1 if spec.optimiser["method"] == "cobyla" else engine.parallel
    return CostEstimate(max(0, optimisation_evaluations(spec) - done), seconds, workers, "evaluations at most")


def check_cost(estimate: CostEstimate, max_hours: float | None) -> None:
    """Refuse a study estimated to take longer than ``max_hours`` (default :data:`MAX_HOURS`).

    Raises
    ------
    UsageError
        With the estimate and the ways to proceed.
    """
    bound = MAX_HOURS if max_hours is None else max_hours
    if estimate.hours <= bound:
        return
    raise UsageError(
        f"the study would take about {estimate.hours:.3g} h: {estimate.points} {estimate.what} at "
        f"{estimate.seconds_per_point:.3g} s each (measured) on {estimate.workers} "
        f"worker{'s' if estimate.workers != 1 else ''}, more than the bound of {bound:g} h; give --max-hours "
        f"{math.ceil(estimate.hours)} to run it anyway, fewer points, or a cluster (--scheduler)"
    )


def run_study(
    spec: StudySpec, output: str | Path, *, workers: int | None = None, scheduler: str | None = None,
    resume: bool = False, progress: bool = False, max_hours: float | None = None,
) -> StudySummary:
    """Run a checked study and write its results file (module docstring).

    Parameters
    ----------
    spec : StudySpec
    output : path
        ``.csv``, ``.parquet`` or ``.nc``.
    workers : int, optional
        Local processes; default all local cores.
    scheduler : str, optional
        Dask scheduler address; the points run on its cluster.
    resume : bool
        Continue from the checkpoint beside ``output``.
    progress : bool
        Show a progress bar on standard error.
    max_hours : float, optional
        Refuse a study estimated (:func:`estimate_cost`) to take longer on the workers at
        hand; default :data:`MAX_HOURS`.

    Raises
    ------
    ModelError, UsageError, OutputError
        Bad model, checkpoint or destination (nothing written).
    """
    output = Path(output)
    _check_output(spec, output)
    started = time.perf_counter()
    run = _compute(spec, lambda identity: Checkpoint(checkpoint_path(output), identity), workers=workers,
                   scheduler=scheduler, resume=resume, progress=progress, max_hours=max_hours)
    files = _write(spec, output, run.table, run.grid, run.extra)
    run.checkpoint.remove()
    return StudySummary(output, len(run.table.values), run.computed, _failed(run.table),
                        time.perf_counter() - started, run.workers, {**run.extra, "files": files}, run.table)


def study(
    spec: StudySpec | str | Path, *, workers: int | None = None, scheduler: str | None = None,
    progress: bool = False, max_hours: float | None = None,
):
    """Run a study in memory and return its results as an :class:`xarray.Dataset`.

    The same computation as :func:`run_study` (``express study``) with nothing written:
    the points are kept in memory instead of a checkpoint, and the dataset is the one
    :func:`run_study` writes to a ``.nc`` file (:func:`express.analysis.study.results.study_dataset_of`),
    so that every number is the file's, bit for bit.

    Parameters
    ----------
    spec : StudySpec or path
        A checked study (:func:`express.analysis.study.spec.read_study`) or the path of a
        study file (read and checked here).
    workers : int, optional
        Local processes; default all local cores (as ``express study``).
    scheduler : str, optional
        Dask scheduler address; the points run on its cluster.
    progress : bool
        Show a progress bar on standard error.
    max_hours : float, optional
        Refuse a study estimated to take longer (:func:`check_cost`); default :data:`MAX_HOURS`.

    Returns
    -------
    xarray.Dataset
        For a ``grid`` study the outputs on the grid's axes (one dimension per varied
        parameter, its values [SI] as the coordinate); for the other kinds one ``point``
        dimension, with the varied parameters as variables. Every variable has its SI
        ``units`` attribute (``""`` for a pure number); ``error`` holds each point's
        message (``""`` for none). The attributes are the file's metadata (``study``: the
        study file's text, ``study_file``, ``model``, ``kind``, ``title``, ``software``,
        ``linearisation``), and, as JSON text, ``best`` (``optimise``: the best feasible
        point) or ``indices`` (``sobol-indices``: first-order and total Sobol indices).

    Raises
    ------
    InputError, ModelError, UsageError
        A bad study file or model, or a study refused by its cost.

    Examples
    --------
    >>> import express
    >>> results = express.study("examples/studies/critical_speed_map.toml")  # doctest: +SKIP
    >>> results.critical_speed.sel(kx1=2e6, method="nearest")  # doctest: +SKIP
    """
    import json

    from express.analysis.study.results import MemoryCheckpoint, study_dataset_of
    from express.analysis.study.spec import read_study

    if isinstance(spec, (str, os.PathLike)):
        spec = read_study(spec)
    elif not isinstance(spec, StudySpec):
        from express.base.diagnostics import ArgumentError

        raise ArgumentError(f"spec must be a StudySpec (express.analysis.study.spec.read_study) or the path of a "
                            f"study file, got {type(spec).__name__}")
    run = _compute(spec, MemoryCheckpoint, workers=workers, scheduler=scheduler, resume=False, progress=progress,
                   max_hours=max_hours)
    dataset = study_dataset_of(run.table, _metadata(spec), run.grid)
    for key in ("best", "indices"):
        if key in run.extra:
            dataset.attrs[key] = json.dumps(run.extra[key], allow_nan=True)
    return dataset


@dataclass
class _Run:
    """What :func:`_compute` did: the table, the points it evaluated, extras, the grid's
    axes (None unless a grid), the workers used and the checkpoint (to remove)."""

    table: ResultTable
    computed: int
    extra: dict
    grid: list | None
    workers: int
    checkpoint: Any


def _failed(table: ResultTable) -> int:
    return sum(1 for i in table.errors if np.isnan(table.results[i]).any())


def _compute(spec: StudySpec, make_checkpoint, *, workers: int | None, scheduler: str | None, resume: bool,
             progress: bool, max_hours: float | None) -> _Run:
    """Evaluate a study's points (or run its optimiser), each finished chunk appended to
    the checkpoint ``make_checkpoint(identity)`` makes (a file, or memory)."""
    task = make_task(spec)
    units = parameter_units(spec)
    workers = default_workers() if workers is None else workers
    if spec.kind == "optimise":
        from express.analysis.study.optimise import run_optimisation

        count = spec.optimiser["population"] * len(spec.parameters)
        engine = Engine(task, min(workers, count), scheduler)
        identity: dict[str, Any] = {"key": task.key, "kind": spec.kind, "study": _digest(spec.text.encode()),
                    "names": list(spec.names), "outputs": list(spec.outputs)}
        checkpoint = make_checkpoint(identity)
        with engine:
            checkpoint.open(resume)
            done = sum(1 for _ in checkpoint.records())
            if optimisation_evaluations(spec) - done > CALIBRATE_ABOVE:
                try:
                    check_cost(estimate_optimisation_cost(engine, spec, done), max_hours)
                except UsageError:  # refused before any point was computed: nothing left behind
                    if not done:
                        checkpoint.remove()
                    raise
            table, computed, extra = run_optimisation(spec, engine, checkpoint, units, progress)
        grid = None
    else:
        points = study_points(spec)
        identity = {"key": task.key, "kind": spec.kind, "points": len(points),
                    "digest": _digest(np.ascontiguousarray(points).tobytes()),
                    "names": list(spec.names), "outputs": list(spec.outputs)}
        checkpoint = make_checkpoint(identity)
        engine = Engine(task, min(workers, len(points)), scheduler)
        with engine:
            checkpoint.open(resume)
            try:
                table, computed = _evaluate(engine, checkpoint, points, spec, units, progress, max_hours)
            except UsageError:  # refused before any point was computed: nothing left behind
                if not resume and checkpoint.exists() and not any(True for _ in checkpoint.records()):
                    checkpoint.remove()
                raise
        grid = [r.values for r in spec.parameters] if spec.kind == "grid" else None
        extra = {}
        if spec.kind == "sobol-indices":
            from express.analysis.study.optimise import sobol_indices

            extra["indices"] = sobol_indices(spec, table)
    return _Run(table, computed, extra, grid, engine.parallel, checkpoint)


def raise_lost(lost: list[dict], checkpoint: Path | None, count: int) -> None:
    """End a study whose points were lost to the machinery: exit status 1, the reason, the
    checkpoint kept (``--resume`` computes the lost points again; None: a study in memory)."""
    from express.base.diagnostics import AnalysisError

    reasons = sorted({record["error"] for record in lost})
    if checkpoint is None:
        raise AnalysisError(f"{len(lost)} of {count} points could not be evaluated ({'; '.join(reasons)[:300]}); "
                            "run the study again (or on fewer workers)")
    raise AnalysisError(f"{len(lost)} of {count} points could not be evaluated ({'; '.join(reasons)[:300]}); the "
                        f"checkpoint {checkpoint} keeps the others: run the study again with --resume to compute them")


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _evaluate(engine: Engine, checkpoint: Checkpoint, points: np.ndarray, spec: StudySpec, units, progress: bool,
              max_hours: float | None = None):
    count = len(points)
    table = ResultTable.empty(spec.names, units, spec.outputs, count)
    done = np.zeros(count, dtype=bool)
    for record in checkpoint.records():
        i = record["point"]
        if not (0 <= i < count) or record.get("values") != points[i].tolist():
            raise UsageError(f"{checkpoint.path}: the checkpoint does not match the study's points; delete it to start again")
        done[i] = True
    if blocked(engine.task):  # a block counts as done only when all its points are
        block = runner.BLOCK
        starts = np.arange(0, count, block)
        whole = np.add.reduceat(done, starts) == np.diff(np.append(starts, count))
        done = np.repeat(whole, block)[:count]
    todo = np.flatnonzero(~done)
    if count > CALIBRATE_ABOVE and len(todo):
        check_cost(estimate_cost(engine, todo, points[todo]), max_hours)
    bar = _progress(count, count - len(todo), progress)
    lost: list[dict] = []
    try:
        for records in engine.run(todo.tolist(), points[todo]):
            lost += [record for record in records if record.get("lost")]
            checkpoint.append([record for record in records if not record.get("lost")])
            if bar is not None:
                bar.update(len(records))
    finally:
        if bar is not None:
            bar.close()
    checkpoint.close()
    if lost:
        raise_lost(lost, checkpoint.path if checkpoint.exists() else None, count)
    for record in checkpoint.records():
        table.add(record)
    return table, len(todo)


def _write(spec: StudySpec, output: Path, table: ResultTable, grid, extra: dict) -> list[str]:
    """The final file (and the indices of a sobol-indices study), all or nothing."""
    from express.io.output import output_transaction, write_bytes

    files = [str(output)]
    with output_transaction([spec.path, spec.model]) as transaction:
        transaction.declare(output, binary=True)
        indices_path = None
        if "indices" in extra:
            indices_path = output.with_name(output.name + ".indices.csv")
            transaction.declare(indices_path)
            files.append(str(indices_path))
        write_bytes(output, result_bytes(output, table, _metadata(spec), grid))
        if indices_path is not None:
            from express.analysis.study.optimise import indices_csv

            write_bytes(indices_path, indices_csv(extra["indices"]))
    return files
