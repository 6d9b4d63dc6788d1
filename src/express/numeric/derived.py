"""A derived vehicle, or a readable generation, as cache data and back
(:mod:`express.io.cache` stores them).

The entry of a numerical vehicle holds what :func:`express.numeric.statespace.load_vehicle`
needs without symbolic work: the equations' names (DOFs, eliminated DOFs, inputs,
parameters, values, units), the compiled matrices (the programs of their distinct
entries and where each goes) and the program of the rail numbers (speed, wheelset data,
station positions).  The symbolic matrices are rebuilt from the programs only when
something asks for them (:class:`LazyMatrices`: a sensitivity, a report); the
clearances (bump stops) are stored as a small program too.

The entry of a readable generation (``express generate`` and the exporters) holds the
factored entries of every matrix and of ``T`` as one program, rebuilt into the same
SymPy expressions (``Add``, ``Mul``, ``Pow`` of the same arguments), so the exports are
the same bytes.

Reading checks every field's type and every program (:meth:`ExpressionProgram.from_data`);
anything else raises :class:`~express.numeric.program.ProgramError`, and the caller
rebuilds the entry.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from express.assembly.equations import ClearanceTerm, ElementTerm, EquationsOfMotion, Matrices
from express.base.diagnostics import InputError
from express.numeric.compiled import CompiledExpressions, CompiledMatrices
from express.numeric.program import ExpressionProgram, ProgramError, checked_list, checked_strings

if TYPE_CHECKING:  # the symbolic side is imported where used: a warm load reads the programs only
    import sympy as sp

    from express.assembly.generator import GenerationResult
    from express.model.records import Model

__all__ = [
    "CachedVehicle",
    "CompiledVehicle",
    "LazyMatrices",
    "generation_entry",
    "read_compiled_entry",
    "read_generation_entry",
    "read_vehicle_entry",
    "vehicle_entry",
]


#: The fields of :class:`express.assembly.equations.Matrices`.
_FIELDS = frozenset(("M", "C", "K", "P", "Pd", "further"))


class LazyMatrices(Matrices):
    """The symbolic matrices of a cached vehicle, rebuilt on first use: reading any matrix
    (by name, by key, iterating, comparing) builds them all once."""

    def __init__(self, build: Callable[[], Mapping[str, Any]]):  # no dataclass fields yet
        object.__setattr__(self, "_build", build)

    def __getattribute__(self, name: str) -> Any:
        if name in _FIELDS:
            build = object.__getattribute__(self, "_build")
            if build is not None:
                object.__setattr__(self, "_build", None)
                built = Matrices.of(build())
                for field_name in _FIELDS:
                    object.__setattr__(self, field_name, getattr(built, field_name))
        return object.__getattribute__(self, name)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Matrices):
            return NotImplemented
        return all(getattr(self, name) == getattr(other, name) for name in sorted(_FIELDS))

    def __hash__(self) -> int:
        return hash(tuple(getattr(self, name) for name in sorted(_FIELDS)))


@dataclass(frozen=True)
class CachedVehicle:
    """A vehicle's derivation read back from the cache.

    Attributes
    ----------
    equations : EquationsOfMotion
        With :class:`LazyMatrices`; ``derivation`` as given to :func:`read_vehicle_entry`.
    compiled : CompiledMatrices
    rail_numbers : CompiledExpressions or None
    """

    equations: EquationsOfMotion
    compiled: CompiledMatrices
    rail_numbers: CompiledExpressions | None


def vehicle_entry(
    equations: EquationsOfMotion, compiled: CompiledMatrices, rail_numbers: CompiledExpressions | None
) -> dict[str, Any]:
    """The cache data of a derived vehicle (JSON-ready)."""
    constant, speed_dependent, scatter = compiled.programs()
    clearances, program = _clearance_data(equations.clearances)
    terms, term_program = _element_term_data(equations.element_terms)
    return {
        "name": equations.name,
        "kind": "vehicle",
        "element_terms": terms,
        "element_term_program": term_program.to_data(),
        "dofs": list(equations.dofs),
        "eliminated": list(equations.eliminated),
        "inputs": list(equations.inputs),
        "parameters": list(equations.parameters),
        "clearances": clearances,
        "clearance_program": program.to_data(),
        "speed": compiled.speed,
        "compiled_parameters": list(compiled.parameters),
        "shapes": {key: list(shape) for key, shape in compiled.shapes.items()},
        "scatter": {key: [part.tolist() for part in parts] for key, parts in scatter.items()},
        "constant": constant.to_data(),
        "speed_dependent": speed_dependent.to_data(),
        "rail_numbers": None if rail_numbers is None else rail_numbers.program.to_data(),
    }


def _checked(read: Callable) -> Callable:
    """Any failure of ``read`` on damaged data as a :class:`ProgramError` (an error in the
    model itself, an ``InputError``, passes: the derivation will report it)."""

    @functools.wraps(read)
    def checked(payload: Any, model: Model) -> Any:
        try:
            return read(payload, model)
        except InputError:
            raise
        except (ValueError, TypeError, KeyError, IndexError, OverflowError, RecursionError, SyntaxError) as error:
            raise ProgramError(f"{type(error).__name__}: {error}") from None

    return checked


@dataclass(frozen=True)
class CompiledVehicle:
    """The compiled part of a vehicle entry: what a warm load evaluates, no SymPy.

    Attributes
    ----------
    compiled : CompiledMatrices
    rail_numbers : CompiledExpressions or None
    dofs, inputs : tuple of str
        The equations' coordinates and inputs (the rows and columns of the matrices).
    """

    compiled: CompiledMatrices
    rail_numbers: CompiledExpressions | None
    dofs: tuple[str, ...]
    inputs: tuple[str, ...]


def read_compiled_entry(payload: Any) -> CompiledVehicle:
    """The compiled matrices and rail numbers of :func:`vehicle_entry`'s data, every
    field checked (no symbolic work).

    Raises
    ------
    ProgramError
        For data that is not a vehicle entry.
    """
    try:
        return _compiled_entry(payload)
    except ProgramError:
        raise
    except (ValueError, TypeError, KeyError, IndexError, OverflowError, RecursionError, SyntaxError) as error:
        raise ProgramError(f"{type(error).__name__}: {error}") from None


def _compiled_entry(payload: Any) -> CompiledVehicle:
    data = _mapping(payload)
    if data.get("kind") != "vehicle":
        raise ProgramError("not a vehicle entry")
    constant = ExpressionProgram.from_data(data.get("constant"))
    speed_dependent = ExpressionProgram.from_data(data.get("speed_dependent"))
    parameters = checked_strings(data.get("compiled_parameters"))
    speed = data.get("speed")
    if speed is not None and speed not in parameters:
        raise ProgramError("bad speed")
    if list(constant.parameters) != parameters or list(speed_dependent.parameters) != parameters:
        raise ProgramError("programs of other parameters")
    shapes = {key: _shape(value) for key, value in _mapping(data.get("shapes")).items()}
    scatter = {key: _scatter(value, shapes.get(key), constant.size, speed_dependent.size)
               for key, value in _mapping(data.get("scatter")).items()}
    if set(scatter) != set(shapes) or not {"M", "C", "K"} <= set(shapes):
        raise ProgramError("bad matrices")
    compiled = CompiledMatrices.from_programs(parameters, speed, shapes, scatter, constant, speed_dependent)
    rail = data.get("rail_numbers")
    rail_numbers = None if rail is None else CompiledExpressions.from_program(ExpressionProgram.from_data(rail))
    dofs, inputs = tuple(checked_strings(data.get("dofs"))), tuple(checked_strings(data.get("inputs")))
    if shapes["M"] != (len(dofs), len(dofs)):
        raise ProgramError("bad matrix shape")
    return CompiledVehicle(compiled, rail_numbers, dofs, inputs)


@_checked
def read_vehicle_entry(payload: Any, model: Model) -> CachedVehicle:
    """The vehicle of :func:`vehicle_entry`'s data, every field checked; the name, values,
    units and derivation steps come from ``model`` (the model the entry was derived from).

    Raises
    ------
    ProgramError
        For data that is not a vehicle entry.
    """
    part = _compiled_entry(payload)
    compiled = part.compiled
    equations = _equations(payload, model, LazyMatrices(lambda: _matrices(compiled)))
    return CachedVehicle(equations, compiled, part.rail_numbers)


def _equations(data: dict, model: Model, matrices: Mapping[str, Any]) -> EquationsOfMotion:
    """The equations of an entry: names from ``data``, values from ``model``."""
    from express.assembly.equations import derivation_steps
    from express.assembly.generator import equation_values

    parameters = tuple(checked_strings(data.get("parameters")))
    values, units = equation_values(model, parameters)
    return EquationsOfMotion(
        name=model.name,
        dofs=tuple(checked_strings(data.get("dofs"))),
        eliminated=tuple(checked_strings(data.get("eliminated"))),
        inputs=tuple(checked_strings(data.get("inputs"))),
        matrices=Matrices.of(matrices),
        parameters=parameters,
        values=values,
        units=units,
        clearances=_read_clearances(data.get("clearances"), ExpressionProgram.from_data(data.get("clearance_program"))),
        element_terms=_read_element_terms(data.get("element_terms"),
                                          ExpressionProgram.from_data(data.get("element_term_program"))),
        derivation=derivation_steps(model),
    )


def _matrices(compiled: CompiledMatrices) -> dict[str, Any]:
    """The symbolic matrices of the compiled ones (their programs' expressions put back)."""
    from express.assembly.generator import symbolic_matrix

    constant, speed_dependent, scatter = compiled.programs()
    expressions = (constant.expressions(), speed_dependent.expressions())
    result = {}
    for key, (places0, places1, sources0, sources1) in scatter.items():
        rows, columns = compiled.shapes[key]
        entries: dict[tuple[int, int], sp.Expr] = {}
        for which, places, sources in ((0, places0, sources0), (1, places1, sources1)):
            for place, source in zip(places.tolist(), sources.tolist(), strict=True):
                entries[divmod(place, columns)] = expressions[which][source]
        result[key] = symbolic_matrix(rows, columns, entries)
    return result


def _clearance_data(clearances: tuple[ClearanceTerm, ...]) -> tuple[list, ExpressionProgram]:
    import sympy as sp

    records, expressions = [], []
    for term in clearances:
        records.append({"element": term.element, "gradient": list(term.gradient), "inputs": list(term.inputs)})
        expressions += [*term.gradient.values(), *term.inputs.values(), term.gap, term.stiffness, term.progressive]
    names = sorted({symbol.name for expression in expressions for symbol in sp.sympify(expression).free_symbols})
    return records, ExpressionProgram.from_expressions(expressions, names)


def _read_clearances(data: Any, program: ExpressionProgram) -> tuple[ClearanceTerm, ...]:
    records = data if isinstance(data, list) else None
    if records is None:
        raise ProgramError("bad clearances")
    expressions = iter(program.expressions() if records else [])
    terms = []
    for record in records:
        record = _mapping(record)
        gradient_names, input_names = checked_strings(record.get("gradient")), checked_strings(record.get("inputs"))
        if program.size < 3:
            raise ProgramError("bad clearances")
        try:
            gradient = {name: next(expressions) for name in gradient_names}
            inputs = {name: next(expressions) for name in input_names}
            gap, stiffness, progressive = next(expressions), next(expressions), next(expressions)
        except StopIteration:
            raise ProgramError("bad clearances") from None
        terms.append(ClearanceTerm(_string(record.get("element")), gradient, inputs, gap, stiffness, progressive))
    if next(expressions, None) is not None:
        raise ProgramError("bad clearances")
    return tuple(terms)


def _element_term_data(terms: tuple[ElementTerm, ...]) -> tuple[list, ExpressionProgram]:
    """The element terms as records of names and one program of their expressions."""
    import sympy as sp

    records, expressions = [], []
    for term in terms:
        records.append({"element": term.element, "kind": term.kind, "gradient": list(term.gradient),
                        "inputs": list(term.inputs), "values": list(term.values)})
        expressions += [*term.gradient.values(), *term.inputs.values(), *term.values.values()]
    names = sorted({symbol.name for expression in expressions for symbol in sp.sympify(expression).free_symbols})
    return records, ExpressionProgram.from_expressions(expressions, names)


def _read_element_terms(data: Any, program: ExpressionProgram) -> tuple[ElementTerm, ...]:
    from express.model.records import ElementKind

    records = data if isinstance(data, list) else None
    if records is None:
        raise ProgramError("bad element terms")
    expressions = iter(program.expressions() if records else [])
    kinds = {kind.value for kind in ElementKind}
    terms = []
    try:
        for record in records:
            record = _mapping(record)
            kind = _string(record.get("kind"))
            if kind not in kinds:
                raise ProgramError("bad element kind")
            parts = [{name: next(expressions) for name in checked_strings(record.get(key))}
                     for key in ("gradient", "inputs", "values")]
            terms.append(ElementTerm(_string(record.get("element")), kind, *parts))
    except StopIteration:
        raise ProgramError("bad element terms") from None
    if next(expressions, None) is not None:
        raise ProgramError("bad element terms")
    return tuple(terms)


def _mapping(value: Any) -> dict:
    if not isinstance(value, dict) or not all(isinstance(key, str) for key in value):
        raise ProgramError("expected a mapping")
    return value


def _string(value: Any) -> str:
    if not isinstance(value, str):
        raise ProgramError("expected a text")
    return value


def _shape(value: Any) -> tuple[int, int]:
    if not (isinstance(value, list) and len(value) == 2 and all(type(x) is int and x >= 0 for x in value)):
        raise ProgramError("bad shape")
    return (value[0], value[1])


def _scatter(
    value: Any, shape: tuple[int, int] | None, constants: int, speed_dependent: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    if shape is None or not (isinstance(value, list) and len(value) == 4):
        raise ProgramError("bad scatter")
    cells = shape[0] * shape[1]
    limits = (cells, cells, constants, speed_dependent)
    parts = []
    for part, limit in zip(value, limits, strict=True):
        if not (isinstance(part, list) and all(type(x) is int and 0 <= x < limit for x in part)):
            raise ProgramError("bad scatter")
        parts.append(np.array(part, dtype=np.intp))
    if len(parts[0]) != len(parts[2]) or len(parts[1]) != len(parts[3]):
        raise ProgramError("bad scatter")
    return parts[0], parts[1], parts[2], parts[3]


# --------------------------------------------------------------------------------------
# the readable generation (express generate and the exporters)
# --------------------------------------------------------------------------------------


def generation_entry(result: GenerationResult) -> dict[str, Any]:
    """The cache data of a readable generation: every distinct entry of the matrices and
    of ``T`` as one program, where each goes, the clearances and the warnings."""
    equations = result.equations
    distinct: dict[sp.Expr, int] = {}
    places: dict[str, Any] = {}
    for key, matrix in [*equations.matrices.items(), (_TRANSFORMATION, result.transformation)]:
        rows, columns = matrix.shape
        found = []
        for (i, j), expression in sorted(matrix.todok().items()):
            if expression != 0:
                found.append([i * columns + j, distinct.setdefault(expression, len(distinct))])
        places[key] = {"shape": [rows, columns], "entries": found}
    names = sorted({symbol.name for expression in distinct for symbol in expression.free_symbols})
    clearances, clearance_program = _clearance_data(equations.clearances)
    terms, term_program = _element_term_data(equations.element_terms)
    return {
        "name": equations.name,
        "kind": "generation",
        "element_terms": terms,
        "element_term_program": term_program.to_data(),
        "dofs": list(equations.dofs),
        "eliminated": list(equations.eliminated),
        "inputs": list(equations.inputs),
        "parameters": list(equations.parameters),
        "full_dofs": list(result.full_dofs),
        "clearances": clearances,
        "clearance_program": clearance_program.to_data(),
        "program": ExpressionProgram.from_expressions(list(distinct), names).to_data(),
        "places": places,
        "warnings": [[w.line, w.item, w.message] for w in result.warnings],
    }


@_checked
def read_generation_entry(payload: Any, model: Model) -> GenerationResult:
    """The generation of :func:`generation_entry`'s data, every field checked; names,
    values, units, derivation steps and the warnings' file come from ``model``.

    Raises
    ------
    ProgramError
        For data that is not a generation entry.
    """
    from express.assembly.generator import GenerationResult
    from express.base.diagnostics import Problem

    data = _mapping(payload)
    if data.get("kind") != "generation":
        raise ProgramError("not a generation entry")
    expressions = ExpressionProgram.from_data(data.get("program")).expressions()
    matrices = {key: _read_matrix(value, expressions) for key, value in _mapping(data.get("places")).items()}
    transformation = matrices.pop(_TRANSFORMATION, None)
    if transformation is None or not {"M", "C", "K"} <= set(matrices):
        raise ProgramError("bad matrices")
    warnings = []
    for item in checked_list(data.get("warnings")):
        if not (isinstance(item, list) and len(item) == 3 and (item[0] is None or type(item[0]) is int)):
            raise ProgramError("bad warning")
        warnings.append(Problem(model.source, item[0], _string(item[1]), _string(item[2])))
    equations = _equations(data, model, matrices)
    full_dofs = tuple(checked_strings(data.get("full_dofs")))
    if matrices["M"].shape != (len(equations.dofs),) * 2 or transformation.shape != (len(full_dofs), len(equations.dofs)):
        raise ProgramError("bad matrix shape")
    return GenerationResult(equations, tuple(warnings), transformation, full_dofs)


#: The key of ``T`` (``q = T q_r``) among the matrices of a generation entry.
_TRANSFORMATION = "transformation T"


def _read_matrix(value: Any, expressions: list[sp.Expr]) -> Any:
    from express.assembly.generator import symbolic_matrix

    data = _mapping(value)
    rows, columns = _shape(data.get("shape"))
    entries: dict[tuple[int, int], sp.Expr] = {}
    for item in checked_list(data.get("entries")):
        if not (isinstance(item, list) and len(item) == 2 and all(type(x) is int for x in item)):
            raise ProgramError("bad matrix entry")
        place, source = item
        if not (0 <= place < rows * columns and 0 <= source < len(expressions)):
            raise ProgramError("bad matrix entry")
        entries[divmod(place, columns)] = expressions[source]
    return symbolic_matrix(rows, columns, entries)


