"""MATLAB / GNU Octave export: one function file returning the numeric matrices.

This module owns :func:`to_matlab`, the identifier rules for MATLAB
(:func:`is_matlab_identifier`) and the deterministic choice of safe local variable names
(:func:`local_names`, also used by the Python exporter).

The generated file ``NAME.m`` (MATLAB requires the file name to match) holds a single
function, no subfunctions::

    function [M, C, K, P, Pd] = NAME(p)
    %NAME  <help: model, DOF order, input order, parameters with values and units>
    if nargin < 1                      % only when every parameter has a value
        p = struct();
        p.J1 = 12.5;
        ...
    end
    J1 = p.J1;                         % parameters unpacked into locals
    ...
    M = zeros(2, 2);
    M(1, 1) = J1 + b.^2.*m;           % one line per non-zero entry
    K(2, 1) = K(1, 2);                 % mirrored entry of a symmetric pair
    ...

``P`` and ``Pd`` (and further matrices, sorted by name) are extra outputs when present.
The struct ``p`` has one field per parameter, named exactly as the parameter (a field
named like a keyword is read as ``p.('end')``, which MATLAB and Octave both accept).

Local names
-----------
A parameter is unpacked into a local variable of its own name, except when that name is a
MATLAB/Octave keyword (``end``, ``if``, ``function`` ...), one of the output matrix
names, the argument ``p``, or a function the generated code may call (``zeros``,
``sqrt``, ``abs``, ``pi`` ...). Such a parameter gets the local name ``p_<name>`` (with
underscores appended, or the tail replaced by a counter at 63 characters, until the name
is unique). The mapping depends only on the parameter names, so it is the same on every
run, and the header lists it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable
from typing import Any

import sympy as sp
from sympy.printing.octave import OctaveCodePrinter

from express.equations import EquationsOfMotion
from express.export.json_export import matrix_items, parameter_symbols, shown_value

__all__ = [
    "MATLAB_KEYWORDS",
    "MATLAB_RESERVED_FUNCTIONS",
    "is_matlab_identifier",
    "local_names",
    "matlab_local_names",
    "symbol_renaming",
    "to_matlab",
]

#: Keywords of MATLAB (``iskeyword``) and GNU Octave 7 (``iskeyword``), fixed here so the
#: output does not depend on the installed interpreter.
MATLAB_KEYWORDS = frozenset(
    """
    __FILE__ __LINE__ break case catch classdef continue do else elseif end
    end_try_catch end_unwind_protect endarguments endclassdef endenumeration endevents
    endfor endfunction endif endmethods endparfor endproperties endspmd endswitch
    endwhile for function global if otherwise parfor persistent return spmd switch try
    until unwind_protect unwind_protect_cleanup while arguments enumeration events
    methods properties
    """.split()
)

#: Names the generated code calls or may call (through ``sympy.octave_code``); a
#: parameter of such a name is unpacked under another name so it cannot shadow them.
MATLAB_RESERVED_FUNCTIONS = frozenset(
    """
    zeros struct nargin p i j e pi Inf inf NaN nan eps true false exp log log2 log10
    sqrt abs sign min max mod rem floor ceil round fix real imag conj angle
    sin cos tan cot sec csc asin acos atan atan2 acot asec acsc sinh cosh tanh coth
    sech csch asinh acosh atanh acoth asech acsch heaviside dirac gamma beta erf erfc
    """.split()
)

_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_MAX_LEN = 63  # namelengthmax


def is_matlab_identifier(name: str) -> bool:
    """Tell whether ``name`` is a valid MATLAB variable or function name.

    Parameters
    ----------
    name : str
        Candidate name.

    Returns
    -------
    bool
        True for ASCII letters, digits and underscores, starting with a letter, at most
        63 characters, and not a keyword.
    """
    return (
        isinstance(name, str)
        and len(name) <= _MAX_LEN
        and _IDENT.match(name) is not None
        and name not in MATLAB_KEYWORDS
    )


def local_names(
    names: Iterable[str],
    usable: Callable[[str], bool],
    *,
    prefix: str = "p_",
    max_len: int | None = None,
) -> dict[str, str]:
    """Choose unique, safe local variable names for parameters, deterministically.

    Parameters
    ----------
    names : iterable of str
        Parameter names, in a fixed order (e.g. ``eom.parameters``).
    usable : callable
        ``usable(candidate)`` is True when ``candidate`` may be used as a local name
        (a valid identifier that is neither a keyword nor otherwise reserved).
    prefix : str, optional
        Prefix of the replacement name, ``"p_"`` by default.
    max_len : int, optional
        Maximum length of a local name.

    Returns
    -------
    dict of str to str
        Local name by parameter name. A usable name maps to itself; any other becomes
        ``prefix + name`` (characters outside ``[A-Za-z0-9_]`` replaced by ``_``) with
        underscores appended until unique (or a counter ``_2``, ``_3`` ... in the last
        characters when ``max_len`` would be exceeded).
    """
    names = list(names)
    result: dict[str, str] = {}
    taken: set[str] = set()
    for name in names:
        if name not in taken and usable(name):
            result[name] = name
            taken.add(name)
    for name in names:
        if name in result:
            continue
        base = prefix + re.sub(r"[^A-Za-z0-9_]", "_", name)
        if max_len is not None:
            base = base[:max_len]
        candidate = base
        counter = 1
        while candidate in taken or not usable(candidate):
            if max_len is None or len(candidate) < max_len:
                candidate += "_"
            else:
                counter += 1
                suffix = f"_{counter}"
                candidate = base[: max_len - len(suffix)] + suffix
        result[name] = candidate
        taken.add(candidate)
    return result


def matlab_local_names(parameters: Iterable[str], outputs: Iterable[str]) -> dict[str, str]:
    """Local variable name of each parameter in the generated MATLAB function.

    Parameters
    ----------
    parameters : iterable of str
        Parameter names (valid MATLAB identifiers).
    outputs : iterable of str
        Output matrix names of the function.

    Returns
    -------
    dict of str to str
        See :func:`local_names`; reserved are the keywords, ``outputs``, ``p`` and
        :data:`MATLAB_RESERVED_FUNCTIONS`.
    """
    reserved = set(outputs) | MATLAB_RESERVED_FUNCTIONS

    def usable(candidate: str) -> bool:
        return is_matlab_identifier(candidate) and candidate not in reserved

    return local_names(parameters, usable, max_len=_MAX_LEN)


class _Printer(OctaveCodePrinter):
    """``octave_code`` with floats printed to full double precision."""

    def _print_Float(self, expr: sp.Float) -> str:  # noqa: N802 - sympy's naming
        return _literal(float(expr))


def _literal(value: float) -> str:
    if math.isnan(value):
        return "NaN"
    if math.isinf(value):
        return "Inf" if value > 0 else "-Inf"
    return repr(value)


def _field(par: str) -> str:
    """``p.name``, or the dynamic form ``p.('end')`` for keywords (MATLAB rejects those)."""
    return f"p.{par}" if par not in MATLAB_KEYWORDS else f"p.('{par}')"


def _comment(text: Any) -> str:
    return " ".join(str(text).split())


def symbol_renaming(
    eom: EquationsOfMotion,
    items: list[tuple[str, sp.ImmutableMatrix]],
    locals_: dict[str, str],
) -> dict[sp.Symbol, sp.Symbol]:
    """Substitution (for ``xreplace``) of the renamed parameters by their local names.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record.
    items : list of (str, sympy.ImmutableMatrix)
        Its matrices, from :func:`~express.export.json_export.matrix_items`.
    locals_ : dict of str to str
        Local name by parameter name, from :func:`local_names`.

    Returns
    -------
    dict of sympy.Symbol to sympy.Symbol
        Only the parameters whose local name differs from their name.
    """
    mapping: dict[sp.Symbol, sp.Symbol] = {}
    for name, symbols in parameter_symbols(eom, items).items():
        if locals_[name] != name:
            for sym in symbols:
                mapping[sym] = sp.Symbol(locals_[name])
    return mapping


def to_matlab(eom: EquationsOfMotion, name: str | None = None) -> str:
    """Write the equations of motion as a MATLAB / GNU Octave function file.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.
    name : str, optional
        Function name (the file must be saved as ``NAME.m``); ``eom.name`` by default.

    Returns
    -------
    str
        Source of the function file ``function [M, C, K, ...] = NAME(p)``; see the module
        docstring for its layout.

    Raises
    ------
    ValueError
        If ``name``, a parameter name or a matrix name is not a valid MATLAB identifier
        (letters, digits and underscores, starting with a letter, at most 63 characters,
        not a keyword), or if an entry uses a function Octave cannot express.
    """
    fname = eom.name if name is None else name
    if not is_matlab_identifier(fname):
        raise ValueError(
            f"{fname!r} is not a valid MATLAB function name: use letters, digits and "
            "underscores, start with a letter, at most 63 characters, not a keyword"
        )
    items = matrix_items(eom)
    outputs = [key for key, _ in items]
    for key in outputs:
        if not is_matlab_identifier(key) or key == "p":
            raise ValueError(f"matrix name {key!r} cannot be a MATLAB output name")
    for par in eom.parameters:
        if not (_IDENT.match(par) and len(par) <= _MAX_LEN):
            raise ValueError(
                f"parameter name {par!r} cannot be a MATLAB struct field name "
                "(letters, digits and underscores, starting with a letter, at most 63 "
                "characters)"
            )
    locals_ = matlab_local_names(eom.parameters, outputs)
    rename = symbol_renaming(eom, items, locals_)
    printer = _Printer({"strict": True})

    def code(expr: sp.Expr) -> str:
        try:
            return printer.doprint(expr.xreplace(rename) if rename else expr)
        except NotImplementedError as exc:
            raise ValueError(f"cannot write {sp.sstr(expr)!r} in MATLAB: {exc}") from exc

    n, m = len(eom.dofs), len(eom.inputs)
    out = [f"function [{', '.join(outputs)}] = {fname}(p)"]
    h = out.append
    h(f"%{fname.upper()}  Equations of motion of the model {_comment(eom.name)!r}.")
    lhs = "M q'' + C q' + K q"
    h(f"%   {lhs} = P u + Pd u'" if m else f"%   {lhs} = 0")
    h(f"%   [{', '.join(outputs)}] = {fname}(p) returns the matrices for the")
    h("%   parameter struct p (one field per parameter, SI units).")
    if eom.parameters and all(par in eom.values for par in eom.parameters):
        h(f"%   {fname}() uses the default values listed below.")
    h("%")
    h("%   Generated by EXPRESS; do not edit.")
    h("%")
    h(f"%   DOFs q ({n}):")
    for k, dof in enumerate(eom.dofs, 1):
        h(f"%     {k:>4}  {_comment(dof)}")
    h(f"%   Eliminated DOFs ({len(eom.eliminated)}): "
      + (", ".join(_comment(d) for d in eom.eliminated) or "none"))
    h(f"%   Inputs u ({m}):" + ("" if m else " none"))
    for k, inp in enumerate(eom.inputs, 1):
        h(f"%     {k:>4}  {_comment(inp)}")
    h(f"%   Parameters ({len(eom.parameters)})" + (", in the unit of the model file:" if eom.parameters else ": none"))
    width = max((len(par) for par in eom.parameters), default=0)
    for par in eom.parameters:
        line = f"%     {par:<{width}}"
        shown = shown_value(eom, par)
        if shown is not None:
            line += f" = {_comment(shown)}"
        if locals_[par] != par:
            line += f"  (local variable {locals_[par]})"
        out.append(line.rstrip())
    for key, mat in items:
        h(f"%   {key}: {mat.rows} x {mat.cols}")
    if eom.parameters and all(par in eom.values for par in eom.parameters):
        h("")
        h("if nargin < 1")
        h("    % Default parameter values (SI units).")
        h("    p = struct();")
        for par in eom.parameters:
            h(f"    {_field(par)} = {_literal(float(eom.values[par]))};")
        h("end")
    if eom.parameters:
        h("")
        for par in eom.parameters:
            h(f"{locals_[par]} = {_field(par)};")
    for key, mat in items:
        h("")
        h(f"{key} = zeros({mat.rows}, {mat.cols});")
        for i in range(mat.rows):
            for j in range(mat.cols):
                entry = mat[i, j]
                if entry == 0:
                    continue
                if j < i and j < mat.rows and i < mat.cols and entry == mat[j, i]:
                    h(f"{key}({i + 1}, {j + 1}) = {key}({j + 1}, {i + 1});")
                else:
                    h(f"{key}({i + 1}, {j + 1}) = {code(entry)};")
    h("")
    h("end")
    return "\n".join(out) + "\n"

