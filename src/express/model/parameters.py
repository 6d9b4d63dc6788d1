"""The parameter graph of a model: given values, derived expressions, derivation nodes.

A parameter is a number with a unit (*primary*), an expression of other parameters
(*derived*: ``P0 = (mc + 2*mt + 4*mw)*g/8``, parsed by :mod:`express.base.expressions`,
never evaluated as code), or an output of a *derivation* — a named function node for
a computation without a closed form, such as ``[rail.creep]``: f1, f2 from the wheel
load, radii, E and nu through the Hertz ellipse and Kalker's table.  The model keeps
the graph (:attr:`~express.model.records.Parameter.expression`,
:attr:`~express.model.records.Model.derivations`), and every value in
:attr:`~express.model.records.Model.parameters` is current: the readers evaluate it
(:func:`resolve`), and :func:`with_values` — behind ``--set``,
:meth:`VehicleModel.with_values <express.numeric.statespace.VehicleModel.with_values>` and
every point of a study — re-evaluates every dependent of what it changes.

Derivation functions belong to the layer that knows them: the rail layer registers
``"kalker"`` with :func:`register_derivation`.  This module knows only which module
registers a known kind, and imports it on first use, so that the model layer does
not depend on the rail layer.

:func:`evaluation_order` gives the derived parameters and derivation nodes in
dependency order, each with its expression or its function's name: what an exporter
needs to compute the derived values from the primary ones.

Examples
--------
>>> from express.io import load_model
>>> model = load_model("examples/forced-steering.toml")
>>> heavy = with_values(model, {"mc": "60 t"})
>>> round(heavy.parameters["P0"].value / model.parameters["P0"].value, 4)
1.7353
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import replace

import sympy as sp

from express.base.diagnostics import ModelError, Problem
from express.base.expressions import ExpressionError, expression_value, parse_expression
from express.base.names import did_you_mean
from express.base.units import (
    DIMENSIONS,
    KMH,
    Dimension,
    UnitError,
    check_dimension,
    format_quantity,
    is_angular_frequency,
    parse_quantity,
    si_unit,
)
from express.base.units import (
    dimension as units_dimension,
)
from express.model.parameter_ranges import check_ranges
from express.model.parameter_units import infer_dimensions, use_sites
from express.model.records import Derivation, Model, Parameter

__all__ = [
    "CommandLineText",
    "DerivationFunction",
    "derivation_function",
    "display_unit",
    "display_value",
    "evaluation_order",
    "expression_value",
    "graph_problems",
    "override_values",
    "parameter_problems",
    "quantity_value",
    "register_derivation",
    "resolve",
    "undefined_name_problems",
    "units_map",
    "with_values",
]

#: A derivation function: keyword arguments (SI floats) -> results by key (SI).
DerivationFunction = Callable[..., Mapping[str, float]]
_FUNCTIONS: dict[str, DerivationFunction] = {}
#: The module that registers each known derivation kind (imported on first use).
_PROVIDERS = {"kalker": "express.rail.build", "profiles": "express.rail.build",
              "free_free_beam": "express.model.beam_modes"}


def register_derivation(kind: str, function: DerivationFunction) -> None:
    """Make ``function`` the derivation called ``kind`` (``[rail.creep]`` is ``"kalker"``).

    It is called with the derivation's arguments as keywords (floats, SI) and returns
    its results by key (floats, SI); it raises ``ValueError`` for arguments outside
    its range (the message says why).
    """
    _FUNCTIONS[kind] = function


def derivation_function(kind: str) -> DerivationFunction:
    """The function registered as ``kind`` (its module imported on first use).

    Raises
    ------
    ValueError
        For a kind no module registers.
    """
    if kind not in _FUNCTIONS and kind in _PROVIDERS:
        importlib.import_module(_PROVIDERS[kind])
    try:
        return _FUNCTIONS[kind]
    except KeyError:
        raise ValueError(f"unknown derivation {kind!r} (known: {', '.join(sorted(_PROVIDERS))})") from None


def _names(expression) -> set[str]:
    return {symbol.name for symbol in sp.sympify(expression).free_symbols}


# ------------------------------------------------------------------ the graph

_Node = str | Derivation  # a derived parameter's name, or a derivation


def _producers(model: Model) -> dict[str, Derivation]:
    """The derivation that sets each of its outputs (only outputs still derived)."""
    producers = {}
    for derivation in model.derivations:
        for _, name, _ in derivation.outputs:
            parameter = model.parameters.get(name)
            if parameter is not None and parameter.derived_by == derivation.item:
                producers[name] = derivation
    return producers


def _inputs(node: _Node, model: Model) -> set[str]:
    if isinstance(node, Derivation):
        return set().union(*(_names(expression) for _, expression, _ in node.inputs))
    expression = model.parameters[node].expression
    return _names(expression) if expression is not None else set()


def _where(node: _Node, model: Model) -> str:
    if isinstance(node, Derivation):
        return f"{node.item}" + (f" (line {node.line})" if node.line is not None else "")
    line = model.parameters[node].line
    return node + (f" (line {line})" if line is not None else "")


def _order(model: Model) -> tuple[list[_Node], list[Problem]]:
    """Derived parameters and derivations in dependency order, and every cycle."""
    producers = _producers(model)
    nodes: list[_Node] = [n for n, p in model.parameters.items() if p.expression is not None]
    nodes += [d for d in model.derivations if any(producers.get(name) is d for _, name, _ in d.outputs)]

    def upstream(node: _Node) -> list[_Node]:
        found: list[_Node] = []
        for name in sorted(_inputs(node, model)):
            parameter = model.parameters.get(name)
            if parameter is None:
                continue
            if parameter.expression is not None:
                found.append(name)
            elif name in producers:
                found.append(producers[name])
        return found

    def key(node: _Node) -> object:
        return node if isinstance(node, str) else ("derivation", id(node))

    order: list[_Node] = []
    problems: list[Problem] = []
    state: dict[object, int] = {}  # 1 on the current path, 2 done
    cycles: set[frozenset] = set()
    for root in nodes:  # depth first, without recursion (chains may be long)
        if key(root) in state:
            continue
        state[key(root)] = 1
        path, stack = [root], [iter(upstream(root))]
        while stack:
            child = next(stack[-1], None)
            if child is None:
                done = path.pop()
                stack.pop()
                state[key(done)] = 2
                order.append(done)
            elif state.get(key(child)) == 1:
                cycle = path[[key(n) for n in path].index(key(child)) :]
                signature = frozenset(key(n) for n in cycle)
                if signature not in cycles:
                    cycles.add(signature)
                    problems.append(_cycle_problem(cycle, model))
            elif key(child) not in state:
                state[key(child)] = 1
                path.append(child)
                stack.append(iter(upstream(child)))
    return order, problems


#: Members of a cycle named in its message; a longer cycle is counted.
CYCLE_SHOWN = 6


def _cycle_problem(cycle: list[_Node], model: Model) -> Problem:
    """One problem per cycle: its members (the first :data:`CYCLE_SHOWN`, then a count)."""
    first = cycle[0]
    shown = [*cycle, first] if len(cycle) <= CYCLE_SHOWN else cycle[:CYCLE_SHOWN]
    chain = " uses ".join(_where(node, model) for node in shown)
    if len(cycle) > CYCLE_SHOWN:
        chain += f" uses ... ({len(cycle)} definitions in the cycle, back to {_where(first, model)})"
    if isinstance(first, Derivation):
        return Problem(model.source, first.line, first.item, f"circular definition: {chain}")
    return Problem(model.source, model.parameters[first].line, f"parameter {first}", f"circular definition: {chain}")


def graph_problems(model: Model) -> list[Problem]:
    """Undefined names in parameter definitions and derivation inputs, and cycles."""
    problems = []
    known = set(model.parameters)
    for name, parameter in model.parameters.items():
        if parameter.expression is not None:
            missing = sorted(_names(parameter.expression) - known)
            if missing:
                plural = "s" if len(missing) > 1 else ""
                problems.append(Problem(
                    model.source, parameter.line, f"parameter {name}",
                    f"undefined name{plural} {', '.join(missing)} where a number is required",
                ))
    for derivation in model.derivations:
        for argument, expression, _ in derivation.inputs:
            missing = sorted(_names(expression) - known)
            if missing:
                problems.append(Problem(
                    model.source, derivation.line, derivation.item,
                    f"{argument}: undefined name{'s' if len(missing) > 1 else ''} {', '.join(missing)}",
                ))
    return problems + _order(model)[1]


def evaluation_order(model: Model) -> tuple[Parameter | Derivation, ...]:
    """Derived parameters and derivation nodes, each after everything it uses.

    For an exporter that computes the derived values from the primary ones: a
    :class:`~express.model.records.Parameter` step is ``name = expression``; a
    :class:`~express.model.records.Derivation` step calls the function ``kind`` with its
    inputs and sets its outputs.

    Raises
    ------
    ModelError
        For a cycle (naming it) or an undefined name.
    """
    problems = graph_problems(model)
    if problems:
        raise ModelError(problems)
    order, _ = _order(model)
    return tuple(model.parameters[node] if isinstance(node, str) else node for node in order)


def _evaluate(model: Model) -> dict[str, Parameter]:
    """Every parameter with its value computed from the primary ones (ModelError)."""
    order, problems = _order(model)
    if problems:
        raise ModelError(problems)
    values = {name: p.value for name, p in model.parameters.items() if p.is_primary}
    parameters = dict(model.parameters)
    for node in order:
        if any(name not in values for name in _inputs(node, model)):
            continue  # an input failed: reported at its own definition
        if isinstance(node, Derivation):
            outcome = _derive(node, model, values)
            if isinstance(outcome, Problem):
                problems.append(outcome)
                continue
            for key, name, _ in node.outputs:
                if parameters.get(name) is not None and parameters[name].derived_by == node.item:
                    values[name] = outcome[key]
                    parameters[name] = replace(parameters[name], value=outcome[key])
            continue
        parameter = model.parameters[node]
        try:
            value = expression_value(parameter.expression, values)
        except (KeyError, ValueError) as error:
            problems.append(Problem(model.source, parameter.line, f"parameter {node}", _reason(error)))
            continue
        values[node] = value
        parameters[node] = replace(parameter, value=value)
    if problems:
        raise ModelError(problems)
    return parameters


def _derive(derivation: Derivation, model: Model, values: Mapping[str, float]) -> dict[str, float] | Problem:
    arguments = {}
    for argument, expression, _ in derivation.inputs:
        try:
            arguments[argument] = expression_value(expression, values)
        except (KeyError, ValueError) as error:
            return Problem(model.source, derivation.line, derivation.item, f"{argument}: {_reason(error)}")
    try:
        results = dict(derivation_function(derivation.kind)(**arguments, **dict(derivation.settings)))
    except ValueError as error:
        return Problem(model.source, derivation.line, derivation.item, str(error))
    bad = sorted(key for key, value in results.items() if not math.isfinite(value))
    if bad:
        return Problem(model.source, derivation.line, derivation.item, f"{', '.join(bad)} not finite")
    return results


def _reason(error: Exception) -> str:
    if isinstance(error, KeyError):
        return f"no value for {error.args[0]}"
    return str(error)


# ------------------------------------------------------------------ reading and overrides


def parameter_problems(model: Model) -> list[Problem]:
    """Every problem of the parameter graph and of the units, for a reader to report
    together with its own: undefined names, cycles, dimension mismatches."""
    problems = graph_problems(model)
    problems += infer_dimensions(model)[1]
    return problems


def resolve(model: Model) -> Model:
    """``model`` with every parameter's dimension settled and every value evaluated.

    Raises
    ------
    ModelError
        For the problems of :func:`parameter_problems`, a value that cannot be
        computed (division by zero, contact data out of range), or a value outside
        the valid range of its use (:mod:`express.model.parameter_ranges`), all at once.
    """
    problems = parameter_problems(model)
    if problems:
        raise ModelError(problems)
    dims = infer_dimensions(model)[0]
    parameters = {name: replace(p, dimension=dims.get(name, p.dimension)) for name, p in model.parameters.items()}
    model = replace(model, parameters=parameters)
    model = replace(model, parameters=_evaluate(model))
    check_ranges(model)
    return model


def undefined_name_problems(model: Model, names: Iterable[str] | None = None) -> list[Problem]:
    """One problem per use of a name that is not a parameter (or of ``names``), with
    the file and line of the item that uses it."""
    wanted = set(names) if names is not None else None
    problems, seen = [], set()
    for site in use_sites(model):
        for name in sorted(_names(site.expression)):
            if name in model.parameters if wanted is None else name not in wanted:
                continue
            if (site.item, name) not in seen:
                seen.add((site.item, name))
                problems.append(Problem(model.source, site.line, site.item, f"{site.what}: undefined name {name}"))
    return problems


class _Uses:
    """What the uses of a model's values imply for a ``--set``: the dimension of each
    name (inferred once, for a classic model whose values carry no unit) and the names
    used directly as a pure number (a conicity, a friction: not an angle)."""

    def __init__(self, model: Model):
        self.model = model
        self._dims: dict[str, Dimension] | None = None
        self.pure = {site.expression.name for site in use_sites(model)
                     if site.dimension == "dimensionless" and isinstance(site.expression, sp.Symbol)}

    def dimension(self, name: str) -> Dimension | None:
        if self._dims is None:  # names without a value (a classic model's) take part too
            placeholders = {n: Parameter(n, math.nan) for n in _settable(self.model) if n not in self.model.parameters}
            model = replace(self.model, parameters={**self.model.parameters, **placeholders})
            self._dims = infer_dimensions(model)[0]
        return self._dims.get(name)


class CommandLineText(str):
    """A value as typed on the command line (``--set v=100``): its bare speed is km/h, the
    command line's shorthand (rail usage).  The library never applies the shorthand to
    any other text: ``with_values({"v": "30"})`` is 30 m/s."""

    __slots__ = ()


def quantity_value(text: str, dimension: Dimension | None = None, pure: bool = False) -> float:
    """An SI value from text: ``"100 km/h"``, ``"4 MN/m"``, ``"0.05"``, ``"1/3"``.

    A number with a unit is checked against ``dimension`` (with ``pure``, a value used
    as a pure number, an angle unit is refused with a hint); a bare number is SI —
    except a speed typed on the command line (:class:`CommandLineText`), which is km/h
    (``--set v=100`` is 100 km/h).

    Raises
    ------
    UnitError
        For text that is not a number (with a unit), or a unit of another dimension.
    """
    try:
        value, unit = parse_quantity(text, "dimensionless" if pure else dimension)
    except UnitError as error:
        try:
            expression = parse_expression(text)
        except ExpressionError:
            raise error from None
        if expression.free_symbols or not expression.is_number:
            raise error from None
        value, unit = float(expression), ""
    if unit:
        if dimension is not None:
            check_dimension(unit, dimension)
    elif dimension == DIMENSIONS["speed"] and isinstance(text, CommandLineText):
        value *= KMH
    if not math.isfinite(value):
        raise UnitError(f'"{text}" is not a finite number')
    return value


def _settable(model: Model) -> set[str]:
    names = set(model.parameters)
    for site in use_sites(model):
        names |= _names(site.expression)
    return names


def override_values(model: Model, overrides: Mapping[str, float | str]) -> dict[str, float]:
    """SI values of ``overrides`` (``{name: text or SI number}``), every problem at once.

    A name must be a parameter of the model (or a name its values use); a text value
    is read by :func:`quantity_value` against the parameter's dimension.

    Raises
    ------
    ModelError
        Naming each unknown parameter (with the closest name) and each bad value.
    """
    problems, values = [], {}
    settable: set[str] | None = None
    uses: _Uses | None = None
    for name, value in overrides.items():
        if name not in model.parameters:
            settable = settable if settable is not None else _settable(model)
            if name not in settable:
                problems.append(Problem(model.source, None, f"parameter {name}", _unknown(name, settable)))
                continue
        parameter = model.parameters.get(name)
        dimension = parameter.dimension if parameter is not None else None
        try:
            if _infinite_damping(value, dimension):
                number = math.inf  # a locked damper (express.assembly.first_order.series_limits)
            elif isinstance(value, str):
                uses = uses if uses is not None else _Uses(model)
                number = quantity_value(value, dimension if dimension is not None else uses.dimension(name),
                                        pure=name in uses.pure)
            elif isinstance(value, bool):
                raise UnitError(f"expected a number, got {value}")
            else:
                number = float(value)
                if not math.isfinite(number):
                    raise UnitError(f"{value} is not a finite number")
        except (UnitError, TypeError, ValueError) as error:
            shown = f'"{value}": ' if isinstance(value, str) else ""
            problems.append(Problem(model.source, None, f"parameter {name}", f"{shown}{error}"))
            continue
        values[name] = number
    if problems:
        raise ModelError(problems)
    return values


def _infinite_damping(value, dimension) -> bool:
    """``inf`` given for a damping: a series element's locked damper (other elements
    with it are refused where their matrices are evaluated, as not finite)."""
    infinite = (isinstance(value, str) and value.strip().lower() in ("inf", "infinity")) or (
        isinstance(value, float) and value == math.inf)
    return infinite and dimension is not None and dimension in (units_dimension("damping"),
                                                                units_dimension("rotational_damping"))


def _unknown(name: str, known: set[str]) -> str:
    return f"no such parameter in the model{did_you_mean(name, known)}"


def _written_unit(value: float | str) -> str:
    """The unit of a ``--set`` text, kept for display and ``convert`` when the file gave the
    parameter none (``"5 t"`` -> ``"t"``); none for a bare number, an expression or an
    angular frequency (shown in Hz)."""
    if not isinstance(value, str):
        return ""
    try:
        unit = parse_quantity(value)[1].strip()
        return "" if unit in ("-", "1") or is_angular_frequency(unit) else unit
    except UnitError:
        return ""


def with_values(model: Model, overrides: Mapping[str, float | str]) -> Model:
    """A copy of ``model`` with parameter values replaced and every dependent re-evaluated.

    Parameters
    ----------
    model : Model
    overrides : mapping of str to float or str
        New values: floats in SI, or texts with a unit (``"60 t"``, ``"100 km/h"``; a bare
        number is SI, a speed too, except :class:`CommandLineText`, the command line's
        ``--set``, whose bare speed is km/h).  Giving a value to a derived parameter makes
        it a given one (its expression is dropped).

    Raises
    ------
    ModelError
        For an unknown name, a value of the wrong dimension, a derived value that
        cannot be computed, or a value outside the valid range of its use
        (:mod:`express.model.parameter_ranges`; a negative stiffness or damping only warns).
    """
    values = override_values(model, overrides)
    if not values:
        return model
    parameters = dict(model.parameters)
    for name, value in values.items():
        previous = parameters.get(name)
        unit = (previous.unit if previous is not None else "") or _written_unit(overrides[name])
        if previous is None:
            parameters[name] = Parameter(name, value, unit=unit)
        else:
            parameters[name] = replace(previous, value=value, unit=unit, expression=None, derived_by=None)
    changed = replace(model, parameters=parameters)
    changed = replace(changed, parameters=_evaluate(changed))
    check_ranges(changed, {name: overrides[name] for name in values})
    return changed


# ------------------------------------------------------------------ display


def display_unit(parameter: Parameter) -> str:
    """The unit to show a parameter in: as written, else the SI unit of its dimension."""
    if parameter.unit.strip():
        return parameter.unit.strip()
    dim = parameter.dimension
    if dim is None or dim.is_dimensionless:
        return ""
    for name, known in DIMENSIONS.items():
        if known == dim:
            return si_unit(name)
    return dim.si()


def display_value(parameter: Parameter) -> str:
    """``"15 kN*s/m"``: the value in the unit the user wrote (SI unit if derived)."""
    return format_quantity(parameter.value, display_unit(parameter))


def units_map(model: Model) -> dict[str, str]:
    """The display unit of every parameter that has one, by name (sorted)."""
    shown = {name: display_unit(p) for name, p in sorted(model.parameters.items())}
    return {name: unit for name, unit in shown.items() if unit}
