"""Elements along any line: a direction vector or the line joining the element's ends.

An element with ``direction = [dx, dy, dz]`` or ``direction = "line"`` carries the
vector ``v`` (:attr:`express.model.records.Element.vector`: as given, or ``p_S - p_T``,
its ends' positions at rest). Its unit vector is ``n = v / |v|`` and its deflection

    delta = n . (u_S - u_T)

with ``u`` each end's small-motion displacement (:func:`express.assembly.kinematics.point_motion`
per axis). The generator keeps the exact arithmetic of ``QQ(parameters)`` without a
square root: it assembles the unnormalised form ``v . (u_S - u_T)`` and scales the
element's stiffness and damping by ``1 / (v . v)``, so that K gains exactly
``k n n^T`` over the ends' relative motion (``k v v^T / (v . v)``) and C ``c n n^T``.

The preload's geometric stiffness (:func:`line_geometric_terms`): an element carrying
the tension ``N`` along a line of length ``L = n . (p_S - p_T)`` adds
``N/L (I - n n^T)`` over the relative motion of its ends: to second order its length
grows by ``|du_perp|^2 / (2 L)`` (the string or pendulum result: a link of length
``L`` carrying ``W`` has lateral stiffness ``W / L``; a mass hung on it swings at
``sqrt(g/L)``). Written with ``mu = N / |v|`` (the tension per unit of ``v``):
``N/L = mu (v . v) / (v . d)`` and ``N n = mu v``, both free of square roots when
``mu = k (v . du_s) / (v . v)`` comes from a static deflection (``[gravity]``).
"""

from __future__ import annotations

from dataclasses import replace

import sympy as sp

from express.base.diagnostics import Problem
from express.model.records import Model

__all__ = ["end_position", "exact_norm", "line_problems", "line_vector", "scale", "squared_length", "unit_term"]


def end_position(model: Model, point_id: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """A CP's position at rest [m]: its body's position plus its offset (a ground
    CP's offset is its position)."""
    point = model.point(point_id)
    try:
        base = model.body(point.host).position
    except KeyError:
        base = (sp.S.Zero,) * 3
    return tuple(sp.expand(sp.sympify(b) + sp.sympify(o)) for b, o in zip(base, point.offset, strict=True))


def line_vector(model: Model, element) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """The vector ``v`` of a line element: ``p_S - p_T`` for ``direction = "line"``,
    else the given direction (unnormalised) [m or -]."""
    if element.through_ends:
        start, end = end_position(model, element.s_end), end_position(model, element.t_end)
        return tuple(sp.expand(a - b) for a, b in zip(start, end, strict=True))
    return element.vector


def squared_length(vector) -> sp.Expr:
    """``v . v``."""
    return sp.expand(sum((sp.sympify(c) ** 2 for c in vector), sp.S.Zero))


def scale(model: Model, element) -> sp.Expr:
    """``1 / (v . v)``: the factor of a line element's stiffness and damping over its
    unnormalised deflection ``v . (u_S - u_T)``; 1 for an axis element."""
    if element.vector is None:
        return sp.S.One
    return 1 / squared_length(line_vector(model, element))


def exact_norm(vector, values: dict[str, float]) -> sp.Expr | None:
    """``|v|`` as a rational function of the parameters, or None when it has none
    (``sqrt(2)``). A square root of a perfect square is taken with the sign that makes
    it positive at ``values``."""
    squared = sp.factor(squared_length(vector))
    root = sp.powdenest(sp.sqrt(squared), force=True)
    if any(not power.exp.is_Integer for power in root.atoms(sp.Pow)):
        return None
    try:
        number = float(root.subs(values))
    except (TypeError, ValueError):
        return root
    return -root if number < 0 else root


def unit_term(model: Model, element, term):
    """A nonlinear element's record (``ElementTerm``, ``ClearanceTerm``) with its true
    deflection ``n . du`` [m]: a line element's gradient over ``v . du`` divided by
    ``|v|``; an axis element's record as it is."""
    if element.vector is None:
        return term
    inverse = 1 / sp.sqrt(squared_length(line_vector(model, element)))
    return replace(term, gradient={d: v * inverse for d, v in term.gradient.items()},
                   inputs={u: v * inverse for u, v in term.inputs.items()})


def line_problems(model: Model) -> list[Problem]:
    """A line element whose vector is zero (``"line"`` between coincident points, say of
    a substructure's connector): one problem each, with its line."""
    return [Problem(model.source, e.line, f"TSD {e.id}", f"its direction {tuple(line_vector(model, e))} is the zero "
                    "vector (a line between coincident points): it gives no line")
            for e in model.elements if e.vector is not None and squared_length(line_vector(model, e)) == 0]
