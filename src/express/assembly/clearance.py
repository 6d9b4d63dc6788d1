"""Clearance elements (bump stops) in numbers, for the nonlinear simulation.

A clearance element's deflection ``delta = g . q + h . u`` is linear; it pushes back
only beyond its gap ``e0``::

    e = delta - e0   (delta >  e0)      F = k e + k3 e^3
    e = delta + e0   (delta < -e0)      (F has the sign of e)
    e = 0            otherwise

and adds the generalized force ``-F g`` to the equations of motion.  The linear
analyses leave these elements out (the generator says so in one warning).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.assembly.equations import EquationsOfMotion
from express.model.parameters import expression_value

__all__ = ["Clearances", "clearance_force", "clearances_of"]


@dataclass(frozen=True)
class Clearances:
    """Every clearance element of a vehicle, evaluated.

    Attributes
    ----------
    names : tuple of str
        Element ids, length ``nb``.
    gradient : numpy.ndarray, shape (nb, n)
        ``g`` of each deflection over the coordinates ``q``.
    inputs : numpy.ndarray, shape (nb, m)
        ``h`` of each deflection over the inputs ``u``.
    gap, stiffness, progressive : numpy.ndarray, shape (nb,)
        ``e0`` [m or rad], ``k`` [N/m or N m/rad], ``k3`` [N/m^3 or N m/rad^3].
    """

    names: tuple[str, ...]
    gradient: np.ndarray
    inputs: np.ndarray
    gap: np.ndarray
    stiffness: np.ndarray
    progressive: np.ndarray

    @property
    def count(self) -> int:
        return len(self.names)


def _number(expression, values: dict[str, float]) -> float:
    try:
        return expression_value(expression, values)
    except KeyError as error:
        raise ValueError(f"no value for {error.args[0]}") from None


def clearances_of(equations: EquationsOfMotion, values: dict[str, float]) -> Clearances:
    """The clearance elements of ``equations`` at parameter ``values`` (SI).

    Raises
    ------
    ValueError
        Naming a parameter without a value, or a negative gap.
    """
    n, m = len(equations.dofs), len(equations.inputs)
    terms = equations.clearances
    gradient = np.zeros((len(terms), n))
    inputs = np.zeros((len(terms), m))
    gap, stiffness, progressive = (np.zeros(len(terms)) for _ in range(3))
    for b, term in enumerate(terms):
        for dof, value in term.gradient.items():
            gradient[b, equations.dofs.index(dof)] = _number(value, values)
        for name, value in term.inputs.items():
            inputs[b, equations.inputs.index(name)] = _number(value, values)
        gap[b] = _number(term.gap, values)
        stiffness[b] = _number(term.stiffness, values)
        progressive[b] = _number(term.progressive, values)
        if not gap[b] >= 0:
            raise ValueError(f"clearance element {term.element}: gap must be >= 0, got {gap[b]:g}")
    return Clearances(tuple(t.element for t in terms), gradient, inputs, gap, stiffness, progressive)


def clearance_force(delta: np.ndarray, gap: np.ndarray, stiffness: np.ndarray, progressive: np.ndarray) -> np.ndarray:
    """Force ``F`` [N or N m] of clearance elements at deflections ``delta`` (module
    docstring); arrays broadcast.

    Examples
    --------
    >>> clearance_force(np.array([0.005, 0.03, -0.03]), 0.01, 1e6, 0.0)
    array([     0.,  20000., -20000.])
    """
    penetration = np.where(delta > gap, delta - gap, np.where(delta < -gap, delta + gap, 0.0))
    return stiffness * penetration + progressive * penetration**3
