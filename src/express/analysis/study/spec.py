"""The study file: ``[study]`` in TOML, read and checked with every problem at once.

A study file names a model (relative to the study file), the kind of study, the
parameters varied with their ranges, fixed overrides and the outputs computed at every
point (``docs/studies.md``)::

    [study]
    model = "../forced-steering.toml"
    kind = "grid"                  # grid | lhs | sobol | optimise | sobol-indices
    outputs = ["critical_speed"]
    [study.parameters]
    Gamma = { values = [0.05, 0.1, 0.2] }
    kx1 = { from = "1 MN/m", to = "4 MN/m", count = 2 }
    [study.set]
    cyaw = "200 kN*s/m"

Quantities are numbers (SI) or strings with a unit, checked against the parameter's
dimension. Problems are :class:`~express.base.diagnostics.Problem` records naming the study
file and line; :func:`read_study` raises :class:`~express.base.diagnostics.ModelError` with
all of them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, cast, get_args

from express.analysis.study.outputs import LINEAR_OUTPUTS, OUTPUTS, RENAMED_OUTPUTS, OutputSettings, renamed_message
from express.base.diagnostics import ModelError, Problem
from express.base.names import did_you_mean
from express.io.toml_lines import find_line, line_index, parse_toml

__all__ = ["KINDS", "MAX_POINTS", "Constraint", "ParameterRange", "StudySpec", "parse_study", "point_count", "read_study"]

#: The kinds of study (``kind = ...`` of the study file).
StudyKind = Literal["grid", "lhs", "sobol", "optimise", "sobol-indices"]
KINDS: tuple[StudyKind, ...] = get_args(StudyKind)
_STUDY_KEYS = ("model", "kind", "outputs", "parameters", "set", "options", "samples", "seed", "title",
               "objective", "constraints", "optimiser")
_RANGE_KEYS = ("values", "from", "to", "count", "scale")
_OPTIMISER_KEYS = ("method", "iterations", "population", "tolerance")
OPTIMISERS = ("differential-evolution", "cobyla")
#: Most points of one study (a mistake in a count should not run for days).
MAX_POINTS = 10_000_000


@dataclass(frozen=True)
class ParameterRange:
    """One varied parameter.

    Attributes
    ----------
    name : str
    values : tuple of float
        The values of a grid (SI); for sampled kinds the two bounds.
    low, high : float
        Bounds (SI): the smallest and largest value.
    scale : str
        ``"linear"`` or ``"log"`` (spacing of ``from``/``to``/``count`` and of samples).
    unit : str
        The unit the study file used (for displays), ``""`` for SI numbers.
    line : int or None
    """

    name: str
    values: tuple[float, ...]
    low: float
    high: float
    scale: str = "linear"
    unit: str = ""
    line: int | None = None


@dataclass(frozen=True)
class Constraint:
    """``lower <= output <= upper`` (either bound may be None)."""

    output: str
    lower: float | None
    upper: float | None
    line: int | None = None


@dataclass(frozen=True)
class StudySpec:
    """A checked study file.

    Attributes
    ----------
    path : Path
        The study file.
    text : str
        Its text (stored in the results' metadata).
    model : Path
        The model file (resolved against the study file's directory).
    kind : str
        One of :data:`KINDS`.
    parameters : tuple of ParameterRange
    fixed : dict of str to float
        ``[study.set]`` overrides (SI), applied at every point.
    outputs : tuple of str
        Names of :data:`~express.analysis.study.outputs.OUTPUTS`.
    settings : OutputSettings
        ``[study.options]``.
    samples : int
        Points of ``lhs``/``sobol``, base samples of ``sobol-indices``, evaluations of
        ``optimise``.
    seed : int
    objective : tuple of (str, str) or None
        ``("maximise" | "minimise", output)`` of ``optimise``.
    constraints : tuple of Constraint
    optimiser : dict
        ``method``, ``iterations``, ``population``, ``tolerance`` of ``optimise``.
    """

    path: Path
    text: str
    model: Path
    kind: StudyKind
    parameters: tuple[ParameterRange, ...]
    fixed: dict[str, float]
    outputs: tuple[str, ...]
    settings: OutputSettings = field(default_factory=OutputSettings)
    samples: int = 0
    seed: int = 0
    title: str = ""
    objective: tuple[str, str] | None = None
    constraints: tuple[Constraint, ...] = ()
    optimiser: dict[str, Any] = field(default_factory=dict)

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the varied parameters, in file order."""
        return tuple(p.name for p in self.parameters)


class _Checker:
    """Collects problems with the line of each key path."""

    def __init__(self, source: str, text: str):
        self.source = source
        self.index = line_index(text)
        self.problems: list[Problem] = []

    def line(self, *path: str) -> int | None:
        return find_line(self.index, ("study", *path))

    def add(self, path: tuple[str, ...], item: str, message: str) -> None:
        self.problems.append(Problem(self.source, self.line(*path), item, message))


def read_study(path: str | Path) -> StudySpec:
    """Read and check a study file (and the model it names).

    Raises
    ------
    ModelError
        Every problem of the study file (and of its model), each with file and line.
    """
    from express.base.limits import read_input_text

    path = Path(path)
    # bounded, UTF-8, and refused by its kind (a directory, a device, a FIFO nobody writes into)
    return parse_study(read_input_text(path, what="the study file"), path)


def parse_study(text: str, path: str | Path) -> StudySpec:
    """Check the text of a study file at ``path`` (the model is found relative to it)."""
    path = Path(path)
    source = str(path)
    data = parse_toml(text, source)
    check = _Checker(source, text)
    study = data.get("study")
    if not isinstance(study, dict):
        raise ModelError([Problem(source, None, "[study]", "the file has no [study] table")])
    for key in data:
        if key != "study":
            check.problems.append(Problem(source, find_line(check.index, (key,)), f"[{key}]", "unknown table; a study file has only [study]"))
    for key in study:
        if key not in _STUDY_KEYS:
            check.add((key,), f"study.{key}", f"unknown key{_hint(key, _STUDY_KEYS)}")
    kind = study.get("kind", "grid")
    if kind not in KINDS:
        check.add(("kind",), "study.kind", f"unknown kind {kind!r}; use one of {', '.join(KINDS)}")
        kind = "grid"
    kind = cast(StudyKind, kind)
    model = _model(check, study, path)
    outputs = _outputs(check, study)
    settings = _settings(check, study.get("options", {}), path)
    run_outputs = [name for name in outputs if name not in LINEAR_OUTPUTS]
    if settings.linearisation != "tangent" and run_outputs:
        check.add(("options", "linearisation"), "study.options.linearisation",
                  f"the equivalent linearisation is of the linear outputs; {', '.join(run_outputs)} march the whole "
                  "nonlinear elements: compute them in a study without it")
    parameters: tuple[ParameterRange, ...] = ()
    fixed: dict[str, float] = {}
    if model is not None:
        parameters = _parameters(check, study.get("parameters"), model, kind)
        fixed = _fixed(check, study.get("set", {}), model, {p.name for p in parameters})
    samples = _samples(check, study, kind)
    seed = _integer(check, study, "seed", 0, 0, 2**32 - 1)
    objective, constraints, optimiser = _optimisation(check, study, kind, outputs)
    if kind == "optimise" and settings.check == "local":
        check.add(("options", "check"), "study.options.check", 'check = "local" follows neighbouring points of a '
                  'grid or sample; an optimisation uses the grid check')
    if parameters:
        total, how = point_count(kind, len(parameters), [len(p.values) for p in parameters], samples, optimiser)
        if total > MAX_POINTS:
            check.add(("parameters",), "study.parameters",
                      f"the study expands to {total} points ({how}); at most {MAX_POINTS}")
    title = study.get("title", "")
    if not isinstance(title, str):
        check.add(("title",), "study.title", "must be a string")
        title = ""
    if check.problems:
        raise ModelError(check.problems)
    assert model is not None
    return StudySpec(
        path=path, text=text, model=Path(model.source), kind=kind, parameters=parameters, fixed=fixed,
        outputs=outputs, settings=settings, samples=samples, seed=seed, title=title, objective=objective,
        constraints=constraints, optimiser=optimiser,
    )


def _hint(name: str, choices) -> str:
    return did_you_mean(name, choices)


def _model(check: _Checker, study: dict, path: Path):
    from express.io import load_model

    name = study.get("model")
    if not isinstance(name, str) or not name.strip():
        check.add(("model",), "study.model", "give the model file, e.g. model = \"vehicle.toml\" (relative to the study file)")
        return None
    model_path = (path.parent / name) if not Path(name).is_absolute() else Path(name)
    if not model_path.is_file():
        what = ("is a folder, not a model file" if model_path.is_dir()
                else "is not a regular file (a device or a pipe)" if model_path.exists() else None)
        check.add(("model",), "study.model", f"{model_path}: {what}" if what else f"no such model file: {model_path}")
        return None
    try:
        return load_model(model_path)
    except ModelError as error:
        check.problems.extend(error.problems)
        return None


def _outputs(check: _Checker, study: dict) -> tuple[str, ...]:
    names = study.get("outputs", ["critical_speed"])
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        check.add(("outputs",), "study.outputs", 'give a list of output names, e.g. ["critical_speed"]')
        return ()
    if not names:
        check.add(("outputs",), "study.outputs", f"no outputs; offered: {', '.join(OUTPUTS)}")
    good = []
    for name in names:
        if name in RENAMED_OUTPUTS:
            check.add(("outputs",), f"output {name}", str(renamed_message(name)))
        elif name not in OUTPUTS:
            check.add(("outputs",), f"output {name}", f"unknown output{_hint(name, OUTPUTS)} (offered: {', '.join(OUTPUTS)})")
        elif name not in good:
            good.append(name)
    return tuple(good)


def _settings(check: _Checker, table: Any, path: Path) -> OutputSettings:
    if not isinstance(table, dict):
        check.add(("options",), "study.options", "must be a table")
        return OutputSettings()
    problems: list[tuple[str, str]] = []
    settings = OutputSettings.from_table(table, path.parent, problems)
    for key, message in problems:
        check.add(("options", key), f"study.options.{key}", message)
    return settings


def _dimension(parameter) -> Any:
    """The parameter's dimension (a name or :class:`~express.base.units.Dimension`), or None."""
    from express.base.units import dimension_of

    known = getattr(parameter, "dimension", None)
    if known is not None:
        return known
    unit = getattr(parameter, "unit", "")
    if unit and unit not in ("1", "-"):
        try:
            return dimension_of(unit)
        except ValueError:
            return None
    return None


def _quantity(check: _Checker, value: Any, parameter, where: tuple[str, ...], item: str) -> tuple[float, str] | None:
    """A number (SI) or ``"number unit"`` checked against the parameter's dimension."""
    from express.base.units import UnitError, parse_quantity

    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        check.add(where, item, f"expected a number or a quantity such as \"2 MN/m\", got {value!r}")
        return None
    if isinstance(value, str):
        try:
            number, unit = parse_quantity(value, _dimension(parameter))
        except UnitError as error:
            check.add(where, item, f"bad unit: {error}")
            return None
    else:
        number, unit = float(value), ""
    if not math.isfinite(number):
        check.add(where, item, f"value {value!r} is not finite")
        return None
    return float(number), unit


def _parameter_of(check: _Checker, model, name: str, where: tuple[str, ...], item: str):
    parameter = model.parameters.get(name)
    if parameter is None:
        check.add(where, item, f"the model has no such parameter{_hint(name, model.parameters)}")
        return None
    return parameter


def _parameters(check: _Checker, table: Any, model, kind: str) -> tuple[ParameterRange, ...]:
    if not isinstance(table, dict) or not table:
        check.add(("parameters",), "study.parameters", "no parameters to vary; add e.g. Gamma = { values = [0.05, 0.1] }")
        return ()
    ranges = []
    for name, spec in table.items():
        where = ("parameters", name)
        item = f"parameter {name}"
        parameter = _parameter_of(check, model, name, where, item)
        if not isinstance(spec, dict):
            check.add(where, item, "give a table: { values = [...] } or { from = ..., to = ..., count = ... }")
            continue
        for key in spec:
            if key not in _RANGE_KEYS:
                check.add(where, item, f"unknown key {key!r}{_hint(key, _RANGE_KEYS)}")
        if parameter is None:
            continue
        found = _range(check, spec, parameter, where, item, kind)
        if found is not None:
            ranges.append(found)
    return tuple(ranges)


def _range(check: _Checker, spec: dict, parameter, where, item, kind: str) -> ParameterRange | None:
    import numpy as np

    scale = spec.get("scale", "linear")
    if scale not in ("linear", "log"):
        check.add(where, item, f'scale must be "linear" or "log", got {scale!r}')
        return None
    if "values" in spec:
        if kind != "grid":
            check.add(where, item, f"a {kind} study samples between from and to; a list of values is for a grid")
            return None
        raw = spec["values"]
        if not isinstance(raw, list) or not raw:
            check.add(where, item, "empty range: values is an empty list")
            return None
        parsed = [_quantity(check, value, parameter, where, item) for value in raw]
        if any(p is None for p in parsed):
            return None
        values = tuple(p[0] for p in parsed)  # type: ignore[index]
        if len(set(values)) != len(values):
            check.add(where, item, "values repeats a value")
            return None
        unit = next((p[1] for p in parsed if p[1]), "")  # type: ignore[index]
        return ParameterRange(parameter.name, values, min(values), max(values), scale, unit, check.line(*where))
    if "from" not in spec or "to" not in spec:
        check.add(where, item, "give values = [...] or from, to (and count for a grid)")
        return None
    low_q = _quantity(check, spec["from"], parameter, where, item)
    high_q = _quantity(check, spec["to"], parameter, where, item)
    if low_q is None or high_q is None:
        return None
    low, high = low_q[0], high_q[0]
    count = spec.get("count")
    if kind == "grid":
        if isinstance(count, bool) or not isinstance(count, int):
            check.add(where, item, "a grid needs count = N (a whole number >= 1)")
            return None
        if count < 1:
            check.add(where, item, f"empty range: count = {count}")
            return None
        if count > MAX_POINTS:  # before any allocation
            check.add(where, item, f"count = {count} is more than the limit of {MAX_POINTS} points of a study")
            return None
    elif count is not None:
        check.add(where, item, f"count is for a grid; a {kind} study takes study.samples")
        return None
    if not high > low and not (kind == "grid" and count == 1 and high == low):
        check.add(where, item, f"empty range: from ({spec['from']}) must be below to ({spec['to']})")
        return None
    if scale == "log" and not low > 0:
        check.add(where, item, "a log scale needs positive bounds")
        return None
    if kind == "grid":
        number = int(count)  # type: ignore[arg-type]  # checked above
        values = tuple((np.geomspace(low, high, number) if scale == "log" else np.linspace(low, high, number)).tolist())
        values = (low,) if count == 1 else values
    else:
        values = (low, high)
    return ParameterRange(parameter.name, values, low, high, scale, low_q[1] or high_q[1], check.line(*where))


def _fixed(check: _Checker, table: Any, model, varied: set[str]) -> dict[str, float]:
    if not isinstance(table, dict):
        check.add(("set",), "study.set", "must be a table of NAME = value")
        return {}
    fixed = {}
    for name, value in table.items():
        where = ("set", name)
        item = f"set {name}"
        parameter = _parameter_of(check, model, name, where, item)
        if parameter is None:
            continue
        if name in varied:
            check.add(where, item, "is also a varied parameter; give it in one place")
            continue
        parsed = _quantity(check, value, parameter, where, item)
        if parsed is not None:
            fixed[name] = parsed[0]
    return fixed


def point_count(kind: str, dimensions: int, counts: list[int], samples: int, optimiser: dict) -> tuple[int, str]:
    """The points a study evaluates once expanded, and how they come about (in words).

    Examples
    --------
    >>> point_count("sobol-indices", 3, [2, 2, 2], 1000, {})
    (5000, 'samples x (parameters + 2) = 1000 x 5 for Sobol indices')
    """
    if kind == "grid":
        return math.prod(counts), " x ".join(map(str, counts)) + " grid"
    if kind == "sobol-indices":
        return samples * (dimensions + 2), f"samples x (parameters + 2) = {samples} x {dimensions + 2} for Sobol indices"
    if kind == "optimise":
        population = optimiser.get("population", 0) * dimensions
        iterations = optimiser.get("iterations", 0) + 1
        return population * iterations, f"population x parameters x (iterations + 1) = {population} x {iterations}"
    return samples, f"{samples} samples"


def _integer(check: _Checker, table: dict, key: str, default: int, low: int, high: int, path=()) -> int:
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        check.add((*path, key), ".".join(("study", *path, key)), f"must be a whole number from {low} to {high}, got {value!r}")
        return default
    return value


def _samples(check: _Checker, study: dict, kind: str) -> int:
    if kind in ("grid", "optimise"):
        if "samples" in study:
            what = "count per parameter" if kind == "grid" else "optimiser.iterations and optimiser.population"
            check.add(("samples",), "study.samples", f"a {kind} study takes {what}, not samples")
        return 0
    if "samples" not in study:
        check.add(("kind",), "study.samples", f"a {kind} study needs samples = N")
        return 0
    return _integer(check, study, "samples", 0, 1, MAX_POINTS)


def _optimisation(check: _Checker, study: dict, kind: str, outputs: tuple[str, ...]):
    keys = ("objective", "constraints", "optimiser")
    if kind != "optimise":
        for key in keys:
            if key in study:
                check.add((key,), f"study.{key}", "is for kind = \"optimise\"")
        return None, (), {}
    objective = None
    table = study.get("objective")
    if not isinstance(table, dict) or len(table) != 1 or next(iter(table)) not in ("maximise", "minimise"):
        check.add(("objective",), "study.objective", 'give one of maximise = "OUTPUT" or minimise = "OUTPUT"')
    else:
        sense, name = next(iter(table.items()))
        if name in RENAMED_OUTPUTS:
            check.add(("objective",), "study.objective", str(renamed_message(name)))
        elif name not in outputs:
            check.add(("objective",), "study.objective", f"{name!r} is not one of the study's outputs ({', '.join(outputs)})")
        else:
            objective = (sense, name)
    constraints = []
    for name, bounds in (study.get("constraints") or {}).items():
        where = ("constraints", name)
        item = f"constraint {name}"
        if name in RENAMED_OUTPUTS:
            check.add(where, item, str(renamed_message(name)))
            continue
        if name not in outputs:
            check.add(where, item, f"not one of the study's outputs ({', '.join(outputs)})")
            continue
        if not isinstance(bounds, dict) or not bounds or set(bounds) - {"min", "max"}:
            check.add(where, item, "give { max = X } and/or { min = X } (SI)")
            continue
        numbers = {}
        for key, value in bounds.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                check.add(where, item, f"{key} must be a finite number (SI)")
            else:
                numbers[key] = float(value)
        constraints.append(Constraint(name, numbers.get("min"), numbers.get("max"), check.line(*where)))
    optimiser = {"method": "differential-evolution", "iterations": 30, "population": 8, "tolerance": 1e-3}
    table = study.get("optimiser", {})
    if not isinstance(table, dict):
        check.add(("optimiser",), "study.optimiser", "must be a table")
        table = {}
    for key in table:
        if key not in _OPTIMISER_KEYS:
            check.add(("optimiser", key), f"study.optimiser.{key}", f"unknown key{_hint(key, _OPTIMISER_KEYS)}")
    method = table.get("method", optimiser["method"])
    if method not in OPTIMISERS:
        check.add(("optimiser", "method"), "study.optimiser.method", f"unknown method {method!r}; use one of {', '.join(OPTIMISERS)}")
    optimiser["method"] = method
    optimiser["iterations"] = _integer(check, table, "iterations", 30, 1, 100_000, ("optimiser",))
    optimiser["population"] = _integer(check, table, "population", 8, 2, 1000, ("optimiser",))
    tolerance = table.get("tolerance", 1e-3)
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not tolerance > 0:
        check.add(("optimiser", "tolerance"), "study.optimiser.tolerance", "must be a positive number")
    else:
        optimiser["tolerance"] = float(tolerance)
    return objective, tuple(constraints), optimiser
