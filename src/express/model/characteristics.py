"""Nonlinear characteristics of an element (issue 31, item 2): its force against its
deflection or against its velocity, piecewise linear through breakpoints.

A :class:`Characteristic` holds the breakpoints ``(x_i, F_i)`` in SI, ``x`` strictly
increasing; between them the force is linear, beyond the first and the last it goes on
with the slope of the end segment.  ``x`` is the element's deflection ``delta`` from the
model's reference state (the static state of the linear analyses) or its rate
``delta'``; ``F`` is the force the element carries in the sense of a spring (``k delta``:
positive in extension, ``delta > 0``).  ``F(0)`` is the preload the element carries at the
reference state (zero for a velocity characteristic: a damper's table passes through zero).

How the linear analyses see it: the **tangent at the static state**, ``dF/dx`` at
``x = 0`` (zero velocity), in ``K`` (deflection) or ``C`` (velocity) with its symbol
(:attr:`Characteristic.tangent`).  At a breakpoint at ``x = 0`` it is the mean of the
two slopes: the limit at small amplitude of the equivalent (describing-function)
stiffness of a kink, ``(k1 + k2)/2``.

The keyword shapes (their breakpoints are expressions of the parameters):

- ``bilinear``: ``k1`` up to the knee ``d`` on either side (``compression_knee`` on the
  negative side, default ``d``), ``k2`` beyond; tangent ``k1``.
- ``blow-off``: a damper ``c`` up to the blow-off velocity ``v_b`` (or force ``F_b = c
  v_b``), beyond it ``+-(c v_b + c2 (|v| - v_b))``; on the negative (compression) side
  its own ``compression_velocity`` / ``compression_force`` if given; tangent ``c``.
- ``contact``: a one-sided contact of stiffness ``k`` on the compression side (``delta <
  0``; ``side = "extension"`` mirrors it), closed with a ``preload`` ``P`` at the reference
  state (lifting off at ``delta = P/k``; tangent ``k``) or open by a ``gap`` ``g`` (closing
  at ``delta = -g``; tangent 0), or touching with neither (tangent ``k/2``).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

__all__ = ["Characteristic", "bilinear", "blow_off", "characteristic_values", "contact", "table_tangent"]

ONE = sp.Integer(1)


@dataclass(frozen=True)
class Characteristic:
    """A piecewise-linear characteristic (module docstring).

    Attributes
    ----------
    of : str
        ``"deflection"`` or ``"velocity"``.
    shape : str
        ``"table"``, ``"bilinear"``, ``"blow-off"`` or ``"contact"``.
    points : tuple of (sympy.Expr, sympy.Expr)
        The breakpoints ``(x, F)`` [m or m/s, N; rotational rad or rad/s, N m].
    tangent : sympy.Expr
        ``dF/dx`` at the reference state, the linear analyses' stiffness [N/m] or damping
        [N s/m] (rotational per rad).
    source : str
        Where the points were given (the model file or a CSV file), for messages.
    keys : tuple of (str, sympy.Expr or str)
        A keyword shape's values as given (``("stiffness", k1)``, ``("side", "extension")``),
        to write it back; empty for a table.
    """

    of: str
    shape: str
    points: tuple[tuple[sp.Expr, sp.Expr], ...]
    tangent: sp.Expr
    source: str = ""
    keys: tuple[tuple[str, sp.Expr | str], ...] = ()

    @property
    def velocity(self) -> bool:
        """A force-velocity characteristic (a damper)."""
        return self.of == "velocity"


def table_tangent(x: list[float], f: list[float]) -> tuple[float, float]:
    """``(F(0), dF/dx at 0)`` of the piecewise-linear table ``x``, ``f`` (``x`` strictly
    increasing, at least two points): the slope of the segment holding 0, the mean of
    the two at a breakpoint, the end segment's beyond the ends."""
    slopes = [(f[i + 1] - f[i]) / (x[i + 1] - x[i]) for i in range(len(x) - 1)]
    if x[0] >= 0.0:
        return f[0] - slopes[0] * x[0], slopes[0]
    if x[-1] <= 0.0:
        return f[-1] - slopes[-1] * x[-1], slopes[-1]
    for i, point in enumerate(x):
        if point == 0.0:
            return f[i], 0.5 * (slopes[i - 1] + slopes[i])
    i = next(i for i in range(len(x) - 1) if x[i] < 0.0 < x[i + 1])
    return f[i] - slopes[i] * x[i], slopes[i]


def bilinear(k1: sp.Expr, knee: sp.Expr, k2: sp.Expr, compression_knee: sp.Expr | None = None) -> tuple:
    """The breakpoints and tangent of a bilinear spring (module docstring)."""
    low = knee if compression_knee is None else compression_knee
    points = ((-low - ONE, -k1 * low - k2), (-low, -k1 * low), (knee, k1 * knee), (knee + ONE, k1 * knee + k2))
    return points, k1


def blow_off(c: sp.Expr, v_blow: sp.Expr, c2: sp.Expr, compression: sp.Expr | None = None) -> tuple:
    """The breakpoints and tangent of a blow-off damper (module docstring); ``compression``
    the blow-off velocity on the negative side (default ``v_blow``)."""
    low = v_blow if compression is None else compression
    points = ((-low - ONE, -c * low - c2), (-low, -c * low), (v_blow, c * v_blow), (v_blow + ONE, c * v_blow + c2))
    return points, c


def contact(k: sp.Expr, preload: sp.Expr | None, gap: sp.Expr | None, extension: bool) -> tuple:
    """The breakpoints and tangent of a one-sided contact (module docstring): closed
    at the reference with a preload, open by a gap, or touching."""
    corner = preload / k if preload is not None else (-gap if gap is not None else sp.S.Zero)  # where F = 0
    tangent = k if preload is not None else (sp.S.Zero if gap is not None else k / 2)
    if extension:  # mirrored: pulls only in extension, F = max(0, k (delta - corner'))
        corner = -corner
        return ((corner - ONE, sp.S.Zero), (corner, sp.S.Zero), (corner + ONE, k)), tangent
    return ((corner - ONE, -k), (corner, sp.S.Zero), (corner + ONE, sp.S.Zero)), tangent


def characteristic_values(characteristic: Characteristic) -> dict[str, sp.Expr]:
    """The characteristic as the named values of its element's term for the time domain
    (:class:`~express.assembly.equations.ElementTerm`): ``x<i>``, ``f<i>`` the breakpoints,
    ``tangent``, and ``velocity`` (1 for a force-velocity characteristic, else 0)."""
    values: dict[str, sp.Expr] = {}
    for i, (x, f) in enumerate(characteristic.points):
        values[f"x{i}"], values[f"f{i}"] = sp.sympify(x), sp.sympify(f)
    values["tangent"] = sp.sympify(characteristic.tangent)
    values["velocity"] = sp.Integer(1 if characteristic.velocity else 0)
    return values
