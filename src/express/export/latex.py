r"""LaTeX export: the equations of motion as a fragment to ``\input`` in a document.

This module owns :func:`to_latex` and the typesetting of names
(:func:`latex_symbol_name` for parameters and inputs, :func:`latex_dof_name` for DOFs).

The output is a *fragment*: no ``\documentclass``, no preamble, no
``\begin{document}``. Include it in a document that loads ``amsmath`` (for ``bmatrix``,
``equation*`` and ``align*``)::

    \documentclass{article}
    \usepackage{amsmath}
    \begin{document}
    \input{lever.tex}
    \end{document}

The fragment sets the counter ``MaxMatrixCols`` to 20 (amsmath's default is 10). A
matrix or vector with more than 20 columns is split into blocks of at most 20 columns,
each labelled with its column range, so that every block stays printable. A matrix with
more than :data:`MAX_MATRIX_ROWS` rows (a long train) is instead listed entry by entry,
``K_{\mathrm{B1}.y,\,\mathrm{B2}.y} &= ...``, non-zero entries only, in an ``align*``
allowed to break across pages; the cost of the export then follows the non-zero entries.

Parameter names are typeset as ``letter_{rest}``: ``kLU`` -> ``k_{LU}``, ``J1`` ->
``J_{1}``, ``Icz`` -> ``I_{cz}``; a Greek letter name stands for the letter, alone or as
the head of the name (``Gamma`` -> ``\Gamma``, ``rho_B1`` and ``rhoB1`` ->
``\rho_{B1}``; a Greek name followed by a lower-case letter, as in ``pitch``, is not
Greek); ``head_rest`` -> ``head_{rest}``. DOFs ``B1.rz`` are typeset
``\mathrm{B1}.r_{z}`` and ``W1.y`` as ``\mathrm{W1}.y``.
"""

from __future__ import annotations

import re

import sympy as sp
from sympy.printing.latex import LatexPrinter, greek_letters_set, translate

from express.assembly.equations import EquationsOfMotion
from express.export.json_export import matrix_entries, matrix_items, parameter_symbols, shown_value

__all__ = ["MAX_COLUMNS", "MAX_MATRIX_ROWS", "latex_dof_name", "latex_symbol_name", "to_latex"]

#: Matrices wider than this are split into column blocks.
MAX_COLUMNS = 20
#: Matrices with more rows than this are listed entry by entry (non-zero entries only):
#: a ``bmatrix`` that tall cannot be printed, and its zeros would cost ``n**2``.
MAX_MATRIX_ROWS = 100

_GREEK = sorted(
    greek_letters_set | {g.capitalize() for g in greek_letters_set} | {"lamda", "Lamda"},
    key=lambda g: (-len(g), g),
)
_SPECIAL = {
    "\\": r"\textbackslash{}",
    "_": r"\_",
    "#": r"\#",
    "%": r"\%",
    "&": r"\&",
    "$": r"\$",
    "{": r"\{",
    "}": r"\}",
    "^": r"\^{}",
    "~": r"\~{}",
}


def _escape(text: str) -> str:
    return "".join(_SPECIAL.get(ch, ch) for ch in str(text))


def _head(head: str) -> str:
    if head in _GREEK:
        return translate(head)
    if len(head) == 1:
        return head
    return r"\mathrm{" + _escape(head) + "}"


def latex_symbol_name(name: str) -> str:
    r"""Typeset a parameter (or input) name.

    Parameters
    ----------
    name : str
        Symbol name.

    Returns
    -------
    str
        LaTeX math: ``kLU`` -> ``k_{LU}``, ``J1`` -> ``J_{1}``, ``Gamma`` -> ``\Gamma``,
        ``rho_B1`` -> ``\rho_{B1}``, ``m`` -> ``m``.
    """
    if name in _GREEK:
        return translate(name)
    if "_" in name and not name.startswith("_") and not name.endswith("_"):
        head, rest = name.split("_", 1)
        return _head(head) + "_{" + ",".join(_escape(r) for r in rest.split("_")) + "}"
    for greek in _GREEK:
        if name.startswith(greek) and not name[len(greek)].islower():
            return translate(greek) + "_{" + _escape(name[len(greek):]) + "}"
    if len(name) > 1 and name[0].isalpha() and name.isascii() and re.fullmatch(r"\w+", name):
        return name[0] + "_{" + _escape(name[1:]) + "}"
    if len(name) == 1 and name.isalpha():
        return name
    return r"\mathrm{" + _escape(name) + "}"


def latex_dof_name(name: str) -> str:
    r"""Typeset a DOF or input name ``<body>.<dof>``.

    Parameters
    ----------
    name : str
        E.g. ``B1.rz`` or ``G1.x``; a name without a dot is typeset as a symbol.

    Returns
    -------
    str
        ``\mathrm{B1}.r_{z}``, ``\mathrm{G1}.x``.
    """
    if "." not in name:
        return latex_symbol_name(name)
    body, dof = name.rsplit(".", 1)
    if re.fullmatch(r"r[xyz]", dof):
        dof_tex = "r_{" + dof[1] + "}"
    elif dof in ("x", "y", "z"):
        dof_tex = dof
    else:
        dof_tex = r"\mathrm{" + _escape(dof) + "}"
    return r"\mathrm{" + _escape(body) + "}." + dof_tex


def _matrix_name(key: str) -> str:
    return "P_{d}" if key == "Pd" else latex_symbol_name(key)


def _blocks(ncols: int) -> list[tuple[int, int]]:
    return [(a, min(a + MAX_COLUMNS, ncols)) for a in range(0, ncols, MAX_COLUMNS)] or [(0, 0)]


def _bmatrix(rows: list[list[str]]) -> list[str]:
    lines = [r"\begin{bmatrix}"]
    for k, row in enumerate(rows):
        lines.append("  " + " & ".join(row) + (r" \\" if k < len(rows) - 1 else ""))
    lines.append(r"\end{bmatrix}")
    return lines


def _equation(label: str, cells: list[list[str]], suffix: str = "") -> list[str]:
    """One ``equation*`` per column block of ``cells`` (rows of typeset entries)."""
    ncols = len(cells[0]) if cells else 0
    blocks = _blocks(ncols)
    out: list[str] = []
    for a, b in blocks:
        if len(blocks) > 1:
            out.append(f"% columns {a + 1}-{b} of {ncols}")
            lhs = rf"\left.{label}\right|_{{\text{{columns }} {a + 1}\text{{--}}{b}}}"
        else:
            lhs = label
        out.append(r"\begin{equation*}")
        out.append(f"{lhs} =")
        out.extend(_bmatrix([row[a:b] for row in cells]))
        if suffix:
            out[-1] += suffix
        out.append(r"\end{equation*}")
    return out


def to_latex(eom: EquationsOfMotion) -> str:
    r"""Typeset the equations of motion as a LaTeX fragment (no preamble).

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.

    Returns
    -------
    str
        LaTeX source needing ``amsmath``: the equation of motion, the DOF vector
        ``q = [...]^{T}``, the input vector ``u`` when there are inputs, and each matrix
        as a ``bmatrix`` in an ``equation*`` (column blocks of at most
        :data:`MAX_COLUMNS` for wider matrices). Parameter values and units are listed
        in comments.
    """
    items = matrix_items(eom)
    symbol_names = {
        sym: latex_symbol_name(name)
        for name, symbols in parameter_symbols(eom, items).items()
        for sym in symbols
    }
    printer = LatexPrinter({"symbol_names": symbol_names})
    m = len(eom.inputs)

    out = [
        f"% Equations of motion of the model {' '.join(str(eom.name).split())!r},",
        "% generated by EXPRESS.",
        r"% A LaTeX fragment without preamble: \input it in a document that loads amsmath.",
        f"% Matrices wider than {MAX_COLUMNS} columns are split into column blocks.",
    ]
    if eom.parameters:
        out.append("% Parameters (value in the unit of the model file, when known):")
        for par in eom.parameters:
            shown = shown_value(eom, par)
            out.append(f"%   {par}" + (f" = {' '.join(shown.split())}" if shown is not None else ""))
    if eom.eliminated:
        out.append("% Eliminated DOFs: " + ", ".join(eom.eliminated))
    out.append(rf"\setcounter{{MaxMatrixCols}}{{{MAX_COLUMNS}}}")
    out.append(r"\begin{align*}")
    rhs = r"P\,u + P_{d}\,\dot{u}" if m else "0"
    out.append(rf"  M\,\ddot{{q}} + C\,\dot{{q}} + K\,q &= {rhs}")
    out.append(r"\end{align*}")
    out.extend(_equation("q", [[latex_dof_name(d) for d in eom.dofs]], "^{T}"))
    if m:
        out.extend(_equation("u", [[latex_dof_name(u) for u in eom.inputs]], "^{T}"))
    cache: dict[sp.Expr, str] = {}

    def tex(value: sp.Expr) -> str:  # repeated entries are typeset once
        if value not in cache:
            cache[value] = printer.doprint(value)
        return cache[value]

    for key, mat in items:
        if mat.rows == 0 or mat.cols == 0:
            out.append(f"% {key} is empty ({mat.rows} x {mat.cols})")
            continue
        entries = matrix_entries(mat)
        if mat.rows > MAX_MATRIX_ROWS:
            out.extend(_listing(eom, key, mat, entries, tex))
            continue
        zero = tex(sp.S.Zero)
        cells = [[zero] * mat.cols for _ in range(mat.rows)]
        for i, j, value in entries:
            cells[i][j] = tex(value)
        out.extend(_equation(_matrix_name(key), cells))
    return "\n".join(out) + "\n"


def _listing(eom: EquationsOfMotion, key: str, mat: sp.MatrixBase, entries: list, tex) -> list[str]:
    """A matrix too tall for a ``bmatrix``: its non-zero entries, one per line, labelled
    by row and column names, in an ``align*`` that may break across pages."""
    rows = [latex_dof_name(d) for d in eom.dofs]
    cols = [latex_dof_name(u) for u in eom.inputs] if key in ("P", "Pd") or mat.cols != mat.rows else rows
    if len(cols) != mat.cols:
        cols = [str(j + 1) for j in range(mat.cols)]
    name = _matrix_name(key)
    out = [f"% {key} ({mat.rows} x {mat.cols}): {len(entries)} non-zero entries, listed "
           f"(more than {MAX_MATRIX_ROWS} rows)"]
    if not entries:
        return [*out, r"\begin{equation*}", f"{name} = 0", r"\end{equation*}"]
    out += [r"{\allowdisplaybreaks", r"\begin{align*}"]
    lines = [f"  {name}_{{{rows[i]},\\,{cols[j]}}} &= {tex(value)}" for i, j, value in entries]
    out.append(" \\\\\n".join(lines))
    return [*out, r"\end{align*}}"]
