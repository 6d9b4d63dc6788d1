"""The result of generation: symbolic equations of motion and their inputs.

``M q'' + C q' + K q = P u + Pd u'`` with ``q`` the generalized coordinates named in
``dofs`` and ``u`` the named inputs (ground displacements such as ``G1.x``, and the
rail inputs ``yR1``, ``dy1``, ``rho_B1``, ``S_B1`` ... when the rail modules are used).

A series (Maxwell) element adds its damper stroke ``<element>.stroke`` to ``q``: a
coordinate without mass (its row of ``M`` is zero) but with damping, a first-order
state (``docs/model-format.md``).  Clearance elements (bump stops) are not in the
matrices; :attr:`EquationsOfMotion.clearances` describes them for the nonlinear
simulation.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

#: Order in which matrices are exported when present.
MATRIX_ORDER = ("M", "C", "K", "P", "Pd")

#: Suffix of the internal coordinate of a series element: ``<element>.stroke``.
STROKE = "stroke"


@dataclass(frozen=True)
class ClearanceTerm:
    """A clearance element (bump stop), left out of the linear matrices.

    Its deflection is ``delta = sum gradient[dof] q[dof] + sum inputs[name] u[name]``;
    beyond the gap it pushes back with ``F = stiffness e + progressive e**3``,
    ``e = delta - gap`` (``delta > gap``) or ``delta + gap`` (``delta < -gap``), a
    generalized force ``-F * gradient`` on the DOFs.

    Attributes
    ----------
    element : str
        Element id.
    gradient : dict of str to sympy.Expr
        Coefficient of each DOF (after pin elimination).
    inputs : dict of str to sympy.Expr
        Coefficient of each input.
    gap : sympy.Expr
        [m or rad], >= 0.
    stiffness, progressive : sympy.Expr
        [N/m] and [N/m^3] (rotational: [N m/rad] and [N m/rad^3]).
    """

    element: str
    gradient: dict[str, sp.Expr]
    inputs: dict[str, sp.Expr]
    gap: sp.Expr
    stiffness: sp.Expr
    progressive: sp.Expr = sp.S.Zero


@dataclass(frozen=True)
class EquationsOfMotion:
    """Symbolic linear equations of motion of a model.

    Attributes
    ----------
    name : str
        Model name, a valid identifier (used for the MATLAB function name).
    dofs : tuple of str
        Generalized coordinates ``<body>.<dof>`` in matrix order, length n.
    eliminated : tuple of str
        Virtual DOFs removed by the pinned joints (empty with ``keep_virtual``).
    inputs : tuple of str
        Names of the inputs ``u``, length m (may be empty).
    matrices : dict of str to sympy.ImmutableMatrix
        ``M``, ``C``, ``K`` (n x n) and, when inputs exist, ``P`` and ``Pd`` (n x m),
        in the order of :data:`MATRIX_ORDER`; further keys may follow.
    parameters : tuple of str
        Sorted names of every parameter symbol appearing in the matrices.
    values : dict of str to float
        Numerical values (SI units) known for parameters, by name.
    units : dict of str to str
        Unit the value was given in, by name (informative).
    clearances : tuple of ClearanceTerm
        Clearance elements (bump stops) for the nonlinear simulation; not in the matrices.
    """

    name: str
    dofs: tuple[str, ...]
    eliminated: tuple[str, ...]
    inputs: tuple[str, ...]
    matrices: dict[str, sp.ImmutableMatrix]
    parameters: tuple[str, ...]
    values: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    clearances: tuple[ClearanceTerm, ...] = ()

    @property
    def M(self) -> sp.ImmutableMatrix:  # noqa: N802 - the domain's name
        return self.matrices["M"]

    @property
    def C(self) -> sp.ImmutableMatrix:  # noqa: N802
        return self.matrices["C"]

    @property
    def K(self) -> sp.ImmutableMatrix:  # noqa: N802
        return self.matrices["K"]
