"""The result of generation: symbolic equations of motion and their inputs.

``M q'' + C q' + K q = P u + Pd u'`` with ``q`` the generalized coordinates named in
``dofs`` and ``u`` the named inputs (ground displacements such as ``G1.x``, and the
rail inputs ``yR1``, ``dy1``, ``rho_B1``, ``S_B1`` ... when the rail modules are used).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

#: Order in which matrices are exported when present.
MATRIX_ORDER = ("M", "C", "K", "P", "Pd")


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
    """

    name: str
    dofs: tuple[str, ...]
    eliminated: tuple[str, ...]
    inputs: tuple[str, ...]
    matrices: dict[str, sp.ImmutableMatrix]
    parameters: tuple[str, ...]
    values: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)

    @property
    def M(self) -> sp.ImmutableMatrix:  # noqa: N802 - the domain's name
        return self.matrices["M"]

    @property
    def C(self) -> sp.ImmutableMatrix:  # noqa: N802
        return self.matrices["C"]

    @property
    def K(self) -> sp.ImmutableMatrix:  # noqa: N802
        return self.matrices["K"]
