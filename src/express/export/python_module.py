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

from express.equations import EquationsOfMotion
from express.export.json_export import matrix_items, shown_value
from express.export.matlab import local_names, symbol_renaming

__all__ = ["to_python"]

_RESERVED = frozenset({"p", "numpy", "float", "abs"})


class _Printer(NumPyPrinter):
    """NumPy printer: full-precision floats, ``Min``/``Max`` without ``functools``."""

    def _print_Float(self, expr: sp.Float) -> str:  # noqa: N802 - sympy's naming
        return _literal(float(expr))

    def _minmax(self, expr: sp.Expr, func: str) -> str:
        args = sorted(expr.args, key=sp.default_sort_key)
        text = self._print(args[-1])
        for arg in reversed(args[:-1]):
            text = f"numpy.{func}({self._print(arg)}, {text})"
        return text

    def _print_Max(self, expr: sp.Expr) -> str:  # noqa: N802
        return self._minmax(expr, "maximum")

    def _print_Min(self, expr: sp.Expr) -> str:  # noqa: N802
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
        Source of the module (see the module docstring for its contents).

    Raises
    ------
    ValueError
        If the matrices are inconsistent, a matrix name is not a Python identifier, or an
        entry uses a function numpy cannot express.
    """
    items = matrix_items(eom)
    names = [key for key, _ in items]
    for key in names:
        if not key.isidentifier() or keyword.iskeyword(key) or key in _RESERVED:
            raise ValueError(f"matrix name {key!r} cannot be a Python variable name")
    reserved = _RESERVED | set(names)

    def usable(candidate: str) -> bool:
        return (
            candidate.isidentifier()
            and candidate.isascii()
            and not keyword.iskeyword(candidate)
            and candidate not in reserved
        )

    locals_ = local_names(eom.parameters, usable)
    rename = symbol_renaming(eom, items, locals_)
    printer = _Printer({"strict": True, "fully_qualified_modules": True})

    def code(expr: sp.Expr) -> str:
        try:
            return printer.doprint(expr.xreplace(rename) if rename else expr)
        except NotImplementedError as exc:
            raise ValueError(f"cannot write {sp.sstr(expr)!r} with numpy: {exc}") from exc

    body: list[str] = []
    b = body.append
    for par in eom.parameters:
        b(f"    {locals_[par]} = float(p[{par!r}])")
    for key, mat in items:
        b(f"    {key} = numpy.zeros(({mat.rows}, {mat.cols}))")
        for i in range(mat.rows):
            for j in range(mat.cols):
                entry = mat[i, j]
                if entry == 0:
                    continue
                if j < i and i < mat.cols and j < mat.rows and entry == mat[j, i]:
                    b(f"    {key}[{i}, {j}] = {key}[{j}, {i}]")
                else:
                    b(f"    {key}[{i}, {j}] = {code(entry)}")
    b("    return {" + ", ".join(f"{key!r}: {key}" for key in names) + "}")
    modules = set(printer.module_imports)
    if modules - {"numpy"}:
        raise ValueError(f"generated code would need modules {sorted(modules - {'numpy'})}")

    m = len(eom.inputs)
    equation = "M q'' + C q' + K q = " + ("P u + Pd u'" if m else "0")
    renamed = [f"{par} -> {loc}" for par, loc in locals_.items() if par != loc]
    values = {par: _literal(float(eom.values[par])) for par in sorted(eom.values)}
    units = {par: repr(str(eom.units[par])) for par in sorted(eom.units)}
    doc_name = " ".join(str(eom.name).split())
    shown = [(par, shown_value(eom, par)) for par in eom.parameters]
    listing = [f"    {par} = {text}" for par, text in shown if text is not None]
    lines = [
        f'"""Equations of motion of the model {doc_name!r}: {equation}.',
        "",
        "Generated by EXPRESS; do not edit. Only numpy is needed.",
        "",
        *(["Parameter values, in the unit of the model file (``VALUES`` holds them in SI,",
           "``UNITS`` the unit each was given in):", "", *listing, ""] if listing else []),
        "Call ``matrices(p)`` with a mapping holding every name of ``PARAMETERS`` (SI",
        "units), or ``matrices()`` to use ``VALUES``; the result maps each name of",
        "``MATRICES`` to a float array, rows ordered as ``DOFS``, columns as ``DOFS``",
        "(``M``, ``C``, ``K``) or ``INPUTS`` (``P``, ``Pd``).",
        '"""',
        "",
        "import numpy",
        "",
        f"NAME = {str(eom.name)!r}",
        f"DOFS = {_tuple(eom.dofs)}",
        f"ELIMINATED = {_tuple(eom.eliminated)}",
        f"INPUTS = {_tuple(eom.inputs)}",
        f"PARAMETERS = {_tuple(eom.parameters)}",
        f"VALUES = {_dict(values)}",
        f"UNITS = {_dict(units)}",
        f"MATRICES = {_tuple(names)}",
        "",
        "",
        "def matrices(p=None):",
        '    """Evaluate the matrices.',
        "",
        "    Parameters",
        "    ----------",
        "    p : Mapping[str, float], optional",
        "        Value of every parameter of ``PARAMETERS`` (extra keys are ignored);",
        "        ``VALUES`` when omitted.",
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
        "    return _matrices(p)",
        "",
        "",
        "def _matrices(p):",
    ]
    if renamed:
        lines.append("    # Local names of parameters whose own name is unsafe here:")
        lines += [f"    #   {line}" for line in renamed]
    return "\n".join(lines + body) + "\n"
