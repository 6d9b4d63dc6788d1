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
Only the non-zero entries are written (read from the matrices' sparse storage, each
distinct entry printed once), so the cost follows their number, not ``n**2``.

Derived parameters
------------------
When the model derives parameters from others (the record's
:attr:`~express.assembly.equations.EquationsOfMotion.derivation`), the function takes the
*given* parameters only (``p`` and the default struct hold those) and computes the
derived ones after unpacking them, before the matrices::

    function [M, C, K, P, Pd, values] = NAME(p)
    ...
    % Derived parameters: computed from the given ones unless set in p.
    if isfield(p, 'P0'), P0 = p.P0; else, P0 = g.*(mc + 2*mt + 4*mw)/8; end
    if ~(isfield(p, 'f1') && isfield(p, 'f2'))
        [kalker_f11, kalker_f22] = kalker_creep(P0, r0, Rrail, Emod, nu);  % rail.creep
    end
    if isfield(p, 'f1'), f1 = p.f1; else, f1 = kalker_f11; end
    ...
    if nargout > 5
        values = struct();             % every parameter value used
        values.Emod = Emod;
        ...
    end
    end

    function [f11, f22] = kalker_creep(...)   % local functions after the main one
    ...

A derived parameter set in ``p`` is used as given. The creep coefficients are computed
by the local function ``kalker_creep`` (Hertz ellipse and Kalker's table as literal
arrays, :mod:`express.export.kalker_code`). Without derived parameters the file is as
before: one function, no ``values`` output.

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

from express.assembly.equations import DerivationCall, DerivationStep, DerivedParameter, EquationsOfMotion
from express.export.assignments import EntryCode, matrix_assignments
from express.export.derivation import FUNCTIONS, DerivationPlan, derivation_plan
from express.export.json_export import matrix_items, parameter_symbols, shown_value
from express.export.kalker_code import KALKER_MATLAB_FUNCTIONS, matlab_kalker

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
#: Last output of a function with derived parameters: every parameter value used.
VALUES_OUTPUT = "values"
#: The local function computing each derivation kind (:mod:`express.export.kalker_code`).
_CALLS = {"kalker": KALKER_MATLAB_FUNCTIONS[0]}
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

    def _print_Float(self, expr: sp.Float) -> str:
        return _literal(float(expr))


def _literal(value: float) -> str:
    if math.isnan(value):
        return "NaN"
    if math.isinf(value):
        return "Inf" if value > 0 else "-Inf"
    return repr(value)


def _field(par: str, struct: str = "p") -> str:
    """``p.name``, or the dynamic form ``p.('end')`` for keywords (MATLAB rejects those)."""
    return f"{struct}.{par}" if par not in MATLAB_KEYWORDS else f"{struct}.('{par}')"


def _comment(text: Any) -> str:
    return " ".join(str(text).split())


def symbol_renaming(
    eom: EquationsOfMotion,
    items: list[tuple[str, sp.ImmutableMatrix]],
    locals_: dict[str, str],
    extra: Iterable[sp.Expr] = (),
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
    extra : iterable of sympy.Expr, optional
        Further expressions written as code (the derivation steps).

    Returns
    -------
    dict of sympy.Symbol to sympy.Symbol
        Only the parameters whose local name differs from their name.
    """
    found = {name: set(symbols) for name, symbols in parameter_symbols(eom, items).items()}
    for expression in extra:
        for sym in sp.sympify(expression).free_symbols:
            found.setdefault(sym.name, set()).add(sym)
    mapping: dict[sp.Symbol, sp.Symbol] = {}
    for name, symbols in found.items():
        if locals_.get(name, name) != name:
            for sym in sorted(symbols, key=sp.default_sort_key):
                mapping[sym] = sp.Symbol(locals_[name])
    return mapping


def step_expressions(plan: DerivationPlan) -> list[sp.Expr]:
    """Every expression the derivation steps of ``plan`` write as code."""
    found: list[sp.Expr] = []
    for step in plan.steps:
        if isinstance(step, DerivedParameter):
            found.append(step.expression)
        else:
            found += [expression for _, expression in step.inputs]
    return found


def exported_names(eom: EquationsOfMotion, plan: DerivationPlan) -> list[str]:
    """Names an export handles: the record's parameters, then (sorted) the given and
    derived ones only the derivation uses."""
    names = list(eom.parameters)
    return names + sorted((set(plan.given) | set(plan.derived)) - set(names))


def call_temporaries(plan: DerivationPlan, taken: Iterable[str]) -> dict[tuple[int, str], str]:
    """Local name of each result of each function step: ``kalker_f11`` (``_2`` ... for a
    second call of the same kind), not one of ``taken``."""
    used = set(taken)
    names: dict[tuple[int, str], str] = {}
    count: dict[str, int] = {}
    for k, step in enumerate(plan.steps):
        if isinstance(step, DerivedParameter):
            continue
        count[step.kind] = count.get(step.kind, 0) + 1
        for key in FUNCTIONS[step.kind][1]:
            candidate = f"{step.kind}_{key}" + (f"_{count[step.kind]}" if count[step.kind] > 1 else "")
            while candidate in used:
                candidate += "_"
            used.add(candidate)
            names[(k, key)] = candidate
    return names


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
        docstring for its layout. Only the non-zero entries are written, so the cost
        follows their number.

    Raises
    ------
    ValueError
        If ``name``, a parameter name or a matrix name is not a valid MATLAB identifier
        (letters, digits and underscores, starting with a letter, at most 63 characters,
        not a keyword), if an entry uses a function Octave cannot express, or if a
        derivation step cannot be written.
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
        if not is_matlab_identifier(key) or key == "p" or key == VALUES_OUTPUT:
            raise ValueError(f"matrix name {key!r} cannot be a MATLAB output name")
    plan = derivation_plan(eom)
    names = exported_names(eom, plan)
    for par in names:
        if not (_IDENT.match(par) and len(par) <= _MAX_LEN):
            raise ValueError(
                f"parameter name {par!r} cannot be a MATLAB struct field name "
                "(letters, digits and underscores, starting with a letter, at most 63 "
                "characters)"
            )
    reserved = list(outputs)
    if plan.steps:
        reserved += [VALUES_OUTPUT, *KALKER_MATLAB_FUNCTIONS]
    locals_ = matlab_local_names(names, reserved)
    code = EntryCode(_Printer({"strict": True}), symbol_renaming(eom, items, locals_, step_expressions(plan)), "in MATLAB")
    given = plan.given if plan.steps else eom.parameters
    out = _header(eom, fname, items, plan, locals_)
    if given and all(par in eom.values for par in given):
        out += ["", "if nargin < 1", "    % Default parameter values (SI units).", "    p = struct();"]
        out += [f"    {_field(par)} = {_literal(float(eom.values[par]))};" for par in given]
        out.append("end")
    if given:
        out.append("")
        out += [f"{locals_[par]} = {_field(par)};" for par in given]
    if plan.steps:
        out += _derivation_code(plan, locals_, code)
    for key, mat in items:
        out += ["", f"{key} = zeros({mat.rows}, {mat.cols});"]
        for a in matrix_assignments(mat):
            i, j = a.row + 1, a.column + 1
            out.append(f"{key}({i}, {j}) = {key}({j}, {i});" if a.entry is None else f"{key}({i}, {j}) = {code(a.entry)};")
    if plan.steps:
        out += ["", f"if nargout > {len(outputs)}", f"    {VALUES_OUTPUT} = struct();"]
        out += [f"    {_field(par, VALUES_OUTPUT)} = {locals_[par]};" for par in (*plan.given, *plan.derived)]
        out.append("end")
    out += ["", "end"]
    text = "\n".join(out) + "\n"
    if any(isinstance(step, DerivationCall) for step in plan.steps):
        text += matlab_kalker()
    return text


def _header(
    eom: EquationsOfMotion,
    fname: str,
    items: list[tuple[str, sp.ImmutableMatrix]],
    plan: DerivationPlan,
    locals_: dict[str, str],
) -> list[str]:
    """The function line and the help text."""
    n, m = len(eom.dofs), len(eom.inputs)
    outputs = [key for key, _ in items]
    given = plan.given if plan.steps else eom.parameters
    signature = outputs + ([VALUES_OUTPUT] if plan.steps else [])
    out = [f"function [{', '.join(signature)}] = {fname}(p)"]
    h = out.append
    h(f"%{fname.upper()}  Equations of motion of the model {_comment(eom.name)!r}.")
    lhs = "M q'' + C q' + K q"
    h(f"%   {lhs} = P u + Pd u'" if m else f"%   {lhs} = 0")
    h(f"%   [{', '.join(outputs)}] = {fname}(p) returns the matrices for the")
    h("%   parameter struct p (one field per parameter, SI units).")
    if given and all(par in eom.values for par in given):
        h(f"%   {fname}() uses the default values listed below.")
    if plan.steps:
        h("%   The derived parameters are computed from the given ones (a derived")
        h("%   parameter set in p is used as given); the last output, values, holds")
        h("%   every parameter value used, given and derived.")
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
    title = "Given parameters" if plan.steps else "Parameters"
    h(f"%   {title} ({len(given)})" + (", in the unit of the model file:" if given else ": none"))
    width = max((len(par) for par in given), default=0)
    for par in given:
        line = f"%     {par:<{width}}"
        shown = shown_value(eom, par)
        if shown is not None:
            line += f" = {_comment(shown)}"
        if locals_[par] != par:
            line += f"  (local variable {locals_[par]})"
        out.append(line.rstrip())
    if plan.steps:
        h(f"%   Derived parameters ({len(plan.derived)}), computed here unless set in p:")
        for step in plan.steps:
            h(f"%     {_comment(_step_text(step))}")
        renamed = [par for par in plan.derived if locals_[par] != par]
        for par in renamed:
            h(f"%     ({par}: local variable {locals_[par]})")
    for key, mat in items:
        h(f"%   {key}: {mat.rows} x {mat.cols}")
    return out


def _step_text(step: DerivationStep) -> str:
    """A derivation step for the help text: ``P0 = g*(mc + 2*mt + 4*mw)/8``."""
    if isinstance(step, DerivedParameter):
        return f"{step.name} = {sp.sstr(step.expression)}"
    results = dict(step.outputs)
    arguments = dict(step.inputs)
    lhs = ", ".join(f"{results[key]} = {key}" for key in FUNCTIONS[step.kind][1] if key in results)
    call = ", ".join(sp.sstr(arguments[argument]) for argument in FUNCTIONS[step.kind][0])
    return f"{lhs} of {_CALLS[step.kind]}({call})  ({step.item})"


def _derivation_code(plan: DerivationPlan, locals_: dict[str, str], code: EntryCode) -> list[str]:
    """Each derived parameter from p when set there, else computed."""
    out = ["", "% Derived parameters: computed from the given ones unless set in p."]
    temporaries = call_temporaries(plan, set(locals_.values()) | set(KALKER_MATLAB_FUNCTIONS))
    for k, step in enumerate(plan.steps):
        if isinstance(step, DerivedParameter):
            local = locals_[step.name]
            out.append(f"if isfield(p, '{step.name}'), {local} = {_field(step.name)}; "
                       f"else, {local} = {code(step.expression)}; end")
            continue
        arguments, results = FUNCTIONS[step.kind]
        given_here = " && ".join(f"isfield(p, '{name}')" for _, name in step.outputs)
        inputs = dict(step.inputs)
        mapped = dict(step.outputs)
        targets = [temporaries[(k, key)] if key in mapped else "~" for key in results]
        while targets and targets[-1] == "~":
            targets.pop()
        call = ", ".join(code(sp.sympify(inputs[argument])) for argument in arguments)
        out.append(f"if ~({given_here})" if len(step.outputs) > 1 else f"if ~{given_here}")
        out.append(f"    [{', '.join(targets)}] = {_CALLS[step.kind]}({call});  % {step.item}")
        out.append("end")
        for key, name in step.outputs:
            local = locals_[name]
            out.append(f"if isfield(p, '{name}'), {local} = {_field(name)}; "
                       f"else, {local} = {temporaries[(k, key)]}; end")
    return out
