"""Python export: a self-contained module that evaluates the matrices with numpy.

This module owns :func:`to_python`. The generated module imports only ``numpy`` (no
sympy at run time, no ``eval``) and provides::

    NAME: str               model name
    DOFS: tuple[str, ...]    generalized coordinates, matrix order
    ELIMINATED, INPUTS, PARAMETERS: tuple[str, ...]
    VALUES: dict[str, float] default parameter values (SI), possibly partial
    UNITS: dict[str, str]
    MATRICES: tuple[str, ...] names of the matrices returned, in order
    matrices(p=None) -> dict[str, numpy.ndarray]

``matrices(p)`` needs every name of ``PARAMETERS`` in ``p`` (extra keys are ignored) and
raises ``KeyError`` naming the missing ones; ``matrices()`` uses ``VALUES`` when it has
every parameter. To change a few values: ``matrices({**VALUES, "m": 40e3})``.

A model with derived parameters (:attr:`~express.assembly.equations.EquationsOfMotion.derivation`)
gets a module that computes them: ``PARAMETERS`` and ``VALUES`` are then the *given*
parameters only, and the module adds::

    DERIVED: tuple[str, ...]   derived parameters, in evaluation order
    parameter_values(p=None) -> dict[str, float]   every value, given and derived
    kalker_creep(wheel_load, wheel_radius, rail_head_radius, youngs_modulus, poisson)
                               -> (f11, f22)      when the creep coefficients are derived

Closed forms are written as code, Kalker's coefficients through ``kalker_creep`` with
its table as literal tuples (:mod:`express.export.kalker_code`). A derived parameter
present in ``p`` is used as given. Changing ``mc`` in
``matrices({**VALUES, "mc": 60e3})`` moves the wheel load and the creep coefficients
exactly as ``--set mc=...`` does.

Inside the module the parameters are unpacked into local variables of their own names;
names that are Python keywords, not identifiers, or clash with a matrix name, ``p``,
``numpy``, ``float`` or ``abs`` become ``p_<name>`` (see
:func:`express.export.matlab.local_names`).
"""

from __future__ import annotations

import keyword
import math
from typing import Any

import sympy as sp
from sympy.printing.numpy import NumPyPrinter

from express.assembly.equations import DerivedParameter, EquationsOfMotion
from express.export.assignments import EntryCode, matrix_assignments
from express.export.derivation import FUNCTIONS, DerivationPlan, derivation_plan
from express.export.json_export import matrix_items, shown_value
from express.export.kalker_code import KALKER_PYTHON_NAMES, python_kalker
from express.export.matlab import (
    call_temporaries,
    exported_names,
    local_names,
    step_expressions,
    symbol_renaming,
)

__all__ = ["to_python"]

_RESERVED = frozenset({"p", "numpy", "float", "abs"})
#: Reserved as well in a module with derived parameters.
_RESERVED_DERIVED = frozenset({"parameter_values", "matrices", "_matrices", *KALKER_PYTHON_NAMES})
#: The module-level function computing each derivation kind.
_CALLS = {"kalker": "kalker_creep"}


class _Printer(NumPyPrinter):
    """NumPy printer: full-precision floats, ``Min``/``Max`` without ``functools``."""

    def _print_Float(self, expr: sp.Float) -> str:
        return _literal(float(expr))

    def _minmax(self, expr: sp.Expr, func: str) -> str:
        args = sorted(expr.args, key=sp.default_sort_key)
        text = self._print(args[-1])
        for arg in reversed(args[:-1]):
            text = f"numpy.{func}({self._print(arg)}, {text})"
        return text

    def _print_Max(self, expr: sp.Expr) -> str:
        return self._minmax(expr, "maximum")

    def _print_Min(self, expr: sp.Expr) -> str:
        return self._minmax(expr, "minimum")


def _literal(value: float) -> str:
    if math.isnan(value):
        return "float('nan')"
    if math.isinf(value):
        return "float('inf')" if value > 0 else "-float('inf')"
    return repr(value)


def _tuple(names: Any, indent: str = "    ") -> str:
    names = [str(name) for name in names]
    if not names:
        return "()"
    one_line = "(" + ", ".join(repr(x) for x in names) + ("," if len(names) == 1 else "") + ")"
    if len(one_line) <= 72:
        return one_line
    return "(\n" + "".join(f"{indent}{x!r},\n" for x in names) + ")"


def _dict(mapping: dict[str, str]) -> str:
    if not mapping:
        return "{}"
    return "{\n" + "".join(f"    {k!r}: {v},\n" for k, v in mapping.items()) + "}"


def to_python(eom: EquationsOfMotion) -> str:
    """Write the equations of motion as an importable Python module using numpy.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.

    Returns
    -------
    str
        Source of the module (see the module docstring for its contents). Only the
        non-zero entries are written, so the cost follows their number.

    Raises
    ------
    ValueError
        If the matrices are inconsistent, a matrix name is not a Python identifier, an
        entry uses a function numpy cannot express, or a derivation step cannot be
        written.
    """
    items = matrix_items(eom)
    names = [key for key, _ in items]
    for key in names:
        if not key.isidentifier() or keyword.iskeyword(key) or key in _RESERVED:
            raise ValueError(f"matrix name {key!r} cannot be a Python variable name")
    plan = derivation_plan(eom)
    reserved = _RESERVED | set(names) | (_RESERVED_DERIVED if plan.steps else set())

    def usable(candidate: str) -> bool:
        return (
            candidate.isidentifier()
            and candidate.isascii()
            and not keyword.iskeyword(candidate)
            and candidate not in reserved
        )

    locals_ = local_names(exported_names(eom, plan), usable)
    printer = _Printer({"strict": True, "fully_qualified_modules": True})
    code = EntryCode(printer, symbol_renaming(eom, items, locals_, step_expressions(plan)), "with numpy")
    body: list[str] = []
    b = body.append
    for par in eom.parameters:
        b(f"    {locals_[par]} = float(p[{par!r}])")
    for key, mat in items:
        b(f"    {key} = numpy.zeros(({mat.rows}, {mat.cols}))")
        for a in matrix_assignments(mat):
            i, j = a.row, a.column
            b(f"    {key}[{i}, {j}] = {key}[{j}, {i}]" if a.entry is None else f"    {key}[{i}, {j}] = {code(a.entry)}")
    b("    return {" + ", ".join(f"{key!r}: {key}" for key in names) + "}")
    derivation = _parameter_values(plan, locals_, code) if plan.steps else []
    modules = set(code.printer.module_imports)
    if modules - {"numpy"}:
        raise ValueError(f"generated code would need modules {sorted(modules - {'numpy'})}")
    lines = _module_head(eom, plan, names, locals_)
    if plan.steps:
        lines += derivation
    lines += _matrices_function(plan)
    if any(not isinstance(step, DerivedParameter) for step in plan.steps):
        lines += python_kalker().split("\n")
        lines += ["", ""]
    lines.append("def _matrices(p):")
    renamed = [f"{par} -> {loc}" for par, loc in locals_.items() if par != loc and par in eom.parameters]
    if renamed:
        lines.append("    # Local names of parameters whose own name is unsafe here:")
        lines += [f"    #   {line}" for line in renamed]
    return "\n".join(lines + body) + "\n"


def _module_head(
    eom: EquationsOfMotion, plan: DerivationPlan, names: list[str], locals_: dict[str, str]
) -> list[str]:
    """The module docstring and the constants."""
    m = len(eom.inputs)
    equation = "M q'' + C q' + K q = " + ("P u + Pd u'" if m else "0")
    given = plan.given if plan.steps else eom.parameters
    value_names = sorted(par for par in given if par in eom.values) if plan.steps else sorted(eom.values)
    values = {par: _literal(float(eom.values[par])) for par in value_names}
    units = {par: repr(str(eom.units[par])) for par in sorted(eom.units)}
    doc_name = " ".join(str(eom.name).split())
    shown = [(par, shown_value(eom, par)) for par in given]
    listing = [f"    {par} = {text}" for par, text in shown if text is not None]
    title = "Given parameter values" if plan.steps else "Parameter values"
    lines = [
        f'"""Equations of motion of the model {doc_name!r}: {equation}.',
        "",
        "Generated by EXPRESS; do not edit. Only numpy is needed.",
        "",
        *([f"{title}, in the unit of the model file (``VALUES`` holds them in SI,",
           "``UNITS`` the unit each was given in):", "", *listing, ""] if listing else []),
    ]
    if plan.steps:
        lines += [
            "Derived parameters (``DERIVED``), computed from the given ones by",
            "``parameter_values(p)`` unless ``p`` sets them (then used as given):",
            "",
            *[f"    {_step_text(step)}" for step in plan.steps],
            "",
        ]
    lines += [
        "Call ``matrices(p)`` with a mapping holding every name of ``PARAMETERS`` (SI",
        "units), or ``matrices()`` to use ``VALUES``; the result maps each name of",
        "``MATRICES`` to a float array, rows ordered as ``DOFS``, columns as ``DOFS``",
        "(``M``, ``C``, ``K``) or ``INPUTS`` (``P``, ``Pd``).",
    ]
    if plan.steps:
        lines += [
            "To change a given value: ``matrices({**VALUES, 'mc': 40e3})``; the derived",
            "ones follow.",
        ]
    lines += [
        '"""',
        "",
        "import numpy",
        "",
        f"NAME = {str(eom.name)!r}",
        f"DOFS = {_tuple(eom.dofs)}",
        f"ELIMINATED = {_tuple(eom.eliminated)}",
        f"INPUTS = {_tuple(eom.inputs)}",
        f"PARAMETERS = {_tuple(given)}",
        *([f"DERIVED = {_tuple(plan.derived)}"] if plan.steps else []),
        f"VALUES = {_dict(values)}",
        f"UNITS = {_dict(units)}",
        f"MATRICES = {_tuple(names)}",
        "",
        "",
    ]
    return lines


def _step_text(step) -> str:
    """A derivation step for the docstring: ``P0 = g*(mc + 2*mt + 4*mw)/8``."""
    if isinstance(step, DerivedParameter):
        return f"{step.name} = {sp.sstr(step.expression)}"
    results = dict(step.outputs)
    arguments = dict(step.inputs)
    lhs = ", ".join(f"{results[key]} = {key}" for key in FUNCTIONS[step.kind][1] if key in results)
    call = ", ".join(sp.sstr(arguments[argument]) for argument in FUNCTIONS[step.kind][0])
    return f"{lhs} of {_CALLS[step.kind]}({call})  ({step.item})"


_CHECKS = [
    "    if p is None:",
    "        missing = [name for name in PARAMETERS if name not in VALUES]",
    "        if missing:",
    "            raise KeyError(",
    "                'no default value for parameter(s) ' + ', '.join(missing)",
    "                + '; call matrices(p) with a value for each'",
    "            )",
    "        p = VALUES",
    "    missing = [name for name in PARAMETERS if name not in p]",
    "    if missing:",
    "        raise KeyError('missing parameter(s) ' + ', '.join(missing))",
]


def _parameter_values(plan: DerivationPlan, locals_: dict[str, str], code: EntryCode) -> list[str]:
    """``parameter_values(p)``: the given values, then each derivation step."""
    lines = [
        "def parameter_values(p=None):",
        '    """Every parameter value: the given ones and the derived ones computed from them.',
        "",
        "    Parameters",
        "    ----------",
        "    p : Mapping[str, float], optional",
        "        Value of every parameter of ``PARAMETERS`` (extra keys are ignored; a name",
        "        of ``DERIVED`` is used as given); ``VALUES`` when omitted.",
        "",
        "    Returns",
        "    -------",
        "    dict of str to float",
        "        The values of ``PARAMETERS`` and ``DERIVED`` (SI).",
        "",
        "    Raises",
        "    ------",
        "    KeyError",
        "        If a parameter has no value.",
        "    ValueError",
        "        If a derived value cannot be computed (e.g. contact data out of range).",
        '    """',
        *_CHECKS,
    ]
    lines += [f"    {locals_[par]} = float(p[{par!r}])" for par in plan.given]
    temporaries = call_temporaries(plan, set(locals_.values()) | set(KALKER_PYTHON_NAMES))
    for k, step in enumerate(plan.steps):
        if isinstance(step, DerivedParameter):
            local = locals_[step.name]
            lines.append(f"    {local} = float(p[{step.name!r}]) if {step.name!r} in p else {code(step.expression)}")
            continue
        arguments, results = FUNCTIONS[step.kind]
        inputs = dict(step.inputs)
        mapped = dict(step.outputs)
        targets = [temporaries[(k, key)] if key in mapped else "_" for key in results]
        call = ", ".join(code(sp.sympify(inputs[argument])) for argument in arguments)
        lines.append("    if " + " or ".join(f"{name!r} not in p" for _, name in step.outputs) + ":")
        lines.append(f"        {', '.join(targets)} = {_CALLS[step.kind]}({call})  # {step.item}")
        for key, name in step.outputs:
            lines.append(f"    {locals_[name]} = float(p[{name!r}]) if {name!r} in p else {temporaries[(k, key)]}")
    everything = (*plan.given, *plan.derived)
    lines.append("    return {" + ", ".join(f"{par!r}: {locals_[par]}" for par in everything) + "}")
    return [*lines, "", ""]


def _matrices_function(plan: DerivationPlan) -> list[str]:
    """``matrices(p)``: the checks (or ``parameter_values``), then ``_matrices``."""
    lines = [
        "def matrices(p=None):",
        '    """Evaluate the matrices.',
        "",
        "    Parameters",
        "    ----------",
        "    p : Mapping[str, float], optional",
        "        Value of every parameter of ``PARAMETERS`` (extra keys are ignored);",
    ]
    if plan.steps:
        lines += ["        a name of ``DERIVED`` is used as given; ``VALUES`` when omitted."]
    else:
        lines += ["        ``VALUES`` when omitted."]
    lines += [
        "",
        "    Returns",
        "    -------",
        "    dict of str to numpy.ndarray",
        "        Each matrix of ``MATRICES`` as a float array.",
        "",
        "    Raises",
        "    ------",
        "    KeyError",
        "        If a parameter has no value.",
        '    """',
    ]
    if plan.steps:
        lines.append("    return _matrices(parameter_values(p))")
    else:
        lines += [*_CHECKS, "    return _matrices(p)"]
    return [*lines, "", ""]
