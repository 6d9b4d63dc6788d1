"""State-space form of ``M q'' + C q' + K q = P u + Pd u' + f`` with first-order coordinates.

Most coordinates carry mass; a series (Maxwell) element adds its damper stroke ``s``,
which has none (its row and column of ``M`` are zero) but is damped: a first-order
coordinate.  Split ``q`` into the massive coordinates ``D`` (``M_DD`` positive
definite) and the first-order ones ``F`` (``M`` zero in their rows and columns,
``C_FF`` invertible).  With ``w = q_D'`` the state is ``x = [q; w]`` (all ``n``
coordinates, then the ``n_D`` velocities), and the two row blocks of the equations
give, with ``Z = C_FF^-1``::

    q_F' = Z (P_F u + Pd_F u' + f_F - C_FD w - K_F q)                 (first order)
    M_DD w' = P~_D u + Pd~_D u' + f~_D - C~_DD w - K~_D q              (second order)

    X~_D = X_D - C_DF Z X_F  (X = P, Pd, K, f),   C~_DD = C_DD - C_DF Z C_FD

which is ``x' = A x + B u + Bd u' + G f``.

Limits of a series element (:func:`series_limits`, applied before the state form): with
zero damping ``c = 0`` the stroke follows the spring, ``s = delta``, no force passes
and the stroke is condensed out statically (``K~ = K - K_.s K_ss^-1 K_s.``, the same
for ``P``, ``P2``, ``Pd``), which removes exactly the element's stiffness; with zero
stiffness ``k = 0`` no force passes and the stroke, decoupled, is dropped; with
infinite damping the stroke is locked, ``s = 0``, and the element is its spring alone
(the stroke's row and column are dropped).  Each equals the model without the element
(or with the plain spring).  Without first-order coordinates this is the
usual ``A = [[0, I], [-M^-1 K, -M^-1 C]]`` with state ``[q; q']``, computed in the
same floating-point operations as before.

The speed enters as ``C(v) = C0 + C1 / v`` (creep damping) and ``P(v) = P0 + P2 v^2``;
creep damping acts on massive coordinates (wheelsets) only, so ``A(v) = A0 + A1 / v``
and ``B(v) = B0 + B2 v^2`` exactly.

Example: a mass ``m`` on a spring ``k0`` and a series ``(k, c)`` element to ground has
``q = [x, s]``, ``M = diag(m, 0)``, ``C = diag(0, c)``, ``K = [[k0 + k, -k], [-k, k]]``
and the eigenvalues of ``A`` (3 x 3) are the roots of
``m c s^3 + m k s^2 + (k0 + k) c s + k0 k``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.assembly.mass_blocks import MassInverse, mass_inverse
from express.base.diagnostics import InputError

__all__ = ["FirstOrderError", "IndefiniteMassError", "SeriesLimits", "StateForm", "series_limits", "state_form"]


class FirstOrderError(InputError):
    """The equations have no state-space form: ``bad`` names the coordinates at fault."""

    def __init__(self, message: str, bad: tuple[int, ...] = ()):
        super().__init__(message)
        self.bad = bad


class IndefiniteMassError(FirstOrderError):
    """The mass matrix of the coordinates with mass is not positive definite."""


@dataclass(frozen=True)
class StateForm:
    """``x' = (A0 + A1 / v) x + (B0 + B2 v^2) u + Bd u' + G f``, state ``x = [q; q_D']``.

    Attributes
    ----------
    n : int
        Number of coordinates ``q``.
    massive : numpy.ndarray of int, shape (n_D,)
        Indices of the massive coordinates (their velocities are states ``n + j``).
    first_order : numpy.ndarray of int, shape (n_F,)
        Indices of the first-order coordinates.
    a0, a1 : numpy.ndarray, shape (N, N)
        ``A(v) = a0 + a1 / v``; ``N = n + n_D``.
    b0, b2, bd : numpy.ndarray, shape (N, m)
        ``B(v) = b0 + b2 v^2``, ``Bd``.
    force : numpy.ndarray, shape (N, n)
        ``G``: how generalized forces ``f`` on the coordinates enter ``x'``.
    mass_inverse : numpy.ndarray, shape (n, n)
        ``M_DD^-1`` in the rows and columns of the massive coordinates, zero elsewhere.
    velocity : numpy.ndarray, shape (n, N)
        ``q' = velocity @ x + velocity_input @ u + velocity_rate @ u'``.
    velocity_input, velocity_rate : numpy.ndarray, shape (n, m)
    """

    n: int
    massive: np.ndarray
    first_order: np.ndarray
    a0: np.ndarray
    a1: np.ndarray
    b0: np.ndarray
    b2: np.ndarray
    bd: np.ndarray
    force: np.ndarray
    mass_inverse: np.ndarray
    velocity: np.ndarray
    velocity_input: np.ndarray
    velocity_rate: np.ndarray

    @property
    def size(self) -> int:
        """Number of states ``N = n + n_D``."""
        return self.a0.shape[0]

    def state_matrix(self, v: float) -> np.ndarray:
        """``A(v)`` [1/s], shape (N, N)."""
        return self.a0 + self.a1 / v

    def input_matrix(self, v: float) -> np.ndarray:
        """``B(v)``, shape (N, m)."""
        return self.b0 + self.b2 * v**2

    def velocities(self, states: np.ndarray, u: np.ndarray | None = None, u_rate: np.ndarray | None = None) -> np.ndarray:
        """``q'`` of every coordinate from states of shape (..., N) (and inputs (..., m))."""
        result = states @ self.velocity.T
        if u is not None and self.first_order.size:
            result = result + u @ self.velocity_input.T
        if u_rate is not None and self.first_order.size:
            result = result + u_rate @ self.velocity_rate.T
        return result


@dataclass(frozen=True)
class SeriesLimits:
    """The matrices with the strokes of series elements at a limit removed.

    Attributes
    ----------
    kept : numpy.ndarray of int
        Indices of the coordinates kept (in order).
    removed : tuple of str
        Names of the strokes removed.
    matrices : tuple of numpy.ndarray
        ``M, C0, C1, K, P0, P2, Pd`` on the kept coordinates.
    """

    kept: np.ndarray
    removed: tuple[str, ...]
    matrices: tuple[np.ndarray, ...]


def series_limits(dofs, mass, damping_base, damping_creep, stiffness, forcing_base, forcing_speed2,
                  forcing_rate, stroke: str = "stroke") -> SeriesLimits:
    """Remove the strokes of series elements whose damping is 0 or infinite or whose
    stiffness is 0 (module docstring).

    Parameters
    ----------
    dofs : sequence of str
        Coordinate names, ``<element>.stroke`` for a stroke; length n.
    mass, damping_base, damping_creep, stiffness : numpy.ndarray, shape (n, n)
    forcing_base, forcing_speed2, forcing_rate : numpy.ndarray, shape (n, m)
    stroke : str
        The suffix of a stroke's name.

    Returns
    -------
    SeriesLimits
        With ``removed`` empty (and the matrices as given) when no element is at a limit.

    Examples
    --------
    A mass on a spring ``k0`` and a series element ``(k, c = 0)``: the stroke is
    condensed out and only ``k0`` is left.

    >>> limits = series_limits(["B.x", "e.stroke"], np.diag([2.0, 0.0]), np.zeros((2, 2)),
    ...                        np.zeros((2, 2)), np.array([[5.0, -3.0], [-3.0, 3.0]]),
    ...                        np.zeros((2, 1)), np.zeros((2, 1)), np.zeros((2, 1)))
    >>> limits.removed, limits.matrices[3]
    (('e.stroke',), array([[2.]]))
    """
    matrices = (mass, damping_base, damping_creep, stiffness, forcing_base, forcing_speed2, forcing_rate)
    strokes = [i for i, name in enumerate(dofs) if name.endswith(f".{stroke}") and not mass[i, i]]
    locked = [i for i in strokes if np.isinf(damping_base[i, i])]
    free = [i for i in strokes if i not in locked and (damping_base[i, i] == 0 or stiffness[i, i] == 0)]
    if not locked and not free:
        return SeriesLimits(np.arange(len(dofs)), (), matrices)
    k = stiffness.copy()
    forcing = [forcing_base.copy(), forcing_speed2.copy(), forcing_rate.copy()]
    condensed = np.array([i for i in free if stiffness[i, i] != 0], dtype=int)
    if condensed.size:  # c = 0: the stroke follows the spring (s = delta), statically
        rest = _others(len(dofs), condensed)
        k_ss = stiffness[np.ix_(condensed, condensed)]
        coupling = np.linalg.solve(k_ss, stiffness[np.ix_(condensed, rest)]).T  # K_.s K_ss^-1
        k[np.ix_(rest, rest)] = stiffness[np.ix_(rest, rest)] - coupling @ stiffness[np.ix_(condensed, rest)]
        for target in forcing:
            target[rest] = target[rest] - coupling @ target[condensed]
    removed = sorted(set(locked) | set(free))
    kept = _others(len(dofs), removed)
    damping = damping_base.copy()
    damping[removed, :] = 0.0
    damping[:, removed] = 0.0  # an infinite damper's entries leave with its stroke
    square = (mass, damping, damping_creep, k)
    reduced = tuple(x[np.ix_(kept, kept)] for x in square) + tuple(f[kept] for f in forcing)
    return SeriesLimits(kept, tuple(dofs[i] for i in removed), reduced)


def _first_order_indices(mass: np.ndarray) -> np.ndarray:
    """Coordinates whose row and column of ``M`` are exactly zero."""
    return np.flatnonzero(~np.any(mass != 0.0, axis=0) & ~np.any(mass != 0.0, axis=1))


def state_form(
    mass: np.ndarray,
    damping_base: np.ndarray,
    damping_creep: np.ndarray,
    stiffness: np.ndarray,
    forcing_base: np.ndarray,
    forcing_speed2: np.ndarray,
    forcing_rate: np.ndarray,
) -> StateForm:
    """Build the state-space form (module docstring) from numerical matrices.

    Parameters
    ----------
    mass, damping_base, damping_creep, stiffness : numpy.ndarray, shape (n, n)
        ``M``, ``C0``, ``C1`` (``C = C0 + C1 / v``), ``K``.
    forcing_base, forcing_speed2, forcing_rate : numpy.ndarray, shape (n, m)
        ``P0``, ``P2`` (``P = P0 + P2 v^2``), ``Pd``.

    Raises
    ------
    FirstOrderError
        When ``M_DD`` is not positive definite, a massless coordinate is not damped
        (``C_FF`` singular) or carries creep damping; ``bad`` holds the coordinates.
    """
    n = mass.shape[0]
    first = _first_order_indices(mass)
    massive = _others(n, first)
    m_dd = mass[np.ix_(massive, massive)]
    try:
        minv = mass_inverse(m_dd)  # by blocks for a long train
    except np.linalg.LinAlgError:
        diagonal = np.diag(mass)
        bad = tuple(int(i) for i in range(n) if not diagonal[i] > 0)
        raise IndefiniteMassError("M is not positive definite", bad) from None
    n_d, n_f, m = massive.size, first.size, forcing_base.shape[1]
    size = n + n_d
    if n_f == 0:  # the usual second-order form, in the operations used before
        return _second_order_form(n, massive, first, minv, damping_base, damping_creep, stiffness, forcing_base, forcing_speed2, forcing_rate)
    c_ff = damping_base[np.ix_(first, first)]
    if np.linalg.matrix_rank(c_ff) < n_f:
        bad = tuple(int(first[i]) for i in range(n_f) if not np.any(c_ff[i]))
        raise FirstOrderError("a coordinate without mass has no damping either (C_FF is singular)", bad or tuple(int(i) for i in first))
    creep_on_first = np.any(damping_creep[first] != 0, axis=1) | np.any(damping_creep[:, first] != 0, axis=0)
    if creep_on_first.any():
        raise FirstOrderError("speed-dependent (creep) damping on a coordinate without mass", tuple(int(i) for i in first[creep_on_first]))
    z = np.linalg.inv(c_ff)
    c_df = damping_base[np.ix_(massive, first)]
    c_fd = damping_base[np.ix_(first, massive)]
    coupling = c_df @ z  # C_DF Z

    def tilde(matrix: np.ndarray) -> np.ndarray:  # X_D - C_DF Z X_F
        return matrix[massive] - coupling @ matrix[first]

    a0 = np.zeros((size, size))
    a1 = np.zeros((size, size))
    a0[massive, n + np.arange(n_d)] = 1.0
    a0[np.ix_(first, np.arange(n))] = -z @ stiffness[first]
    a0[np.ix_(first, n + np.arange(n_d))] = -z @ c_fd
    a0[n:, :n] = -minv.times(tilde(stiffness))
    a0[n:, n:] = -minv.times(damping_base[np.ix_(massive, massive)] - coupling @ c_fd)
    a1[n:, n:] = -minv.times(damping_creep[np.ix_(massive, massive)])
    b0, b2, bd = (np.zeros((size, m)) for _ in range(3))
    for target, matrix in ((b0, forcing_base), (b2, forcing_speed2), (bd, forcing_rate)):
        target[first] = z @ matrix[first]
        target[n:] = minv.times(tilde(matrix))
    force = np.zeros((size, n))
    force[np.ix_(first, first)] = z
    identity = np.eye(n)
    force[n:] = minv.times(tilde(identity))
    velocity = np.zeros((n, size))
    velocity[massive, n + np.arange(n_d)] = 1.0
    velocity[first] = a0[first]
    velocity_input = np.zeros((n, m))
    velocity_rate = np.zeros((n, m))
    velocity_input[first] = b0[first]
    velocity_rate[first] = bd[first]
    if np.any(forcing_speed2[first] != 0):
        raise FirstOrderError("speed-dependent forcing on a coordinate without mass", tuple(int(i) for i in first))
    inverse = np.zeros((n, n))
    inverse[np.ix_(massive, massive)] = minv.dense()
    return StateForm(n, massive, first, a0, a1, b0, b2, bd, force, inverse, velocity, velocity_input, velocity_rate)


def _second_order_form(n, massive, first, inverse: MassInverse, c0, c1, k, p0, p2, pd) -> StateForm:
    m = p0.shape[1]
    minv = inverse.dense()
    a0 = np.zeros((2 * n, 2 * n))
    a0[:n, n:] = np.eye(n)
    a0[n:, :n] = -inverse.times(k)
    a0[n:, n:] = -inverse.times(c0)
    a1 = np.zeros((2 * n, 2 * n))
    a1[n:, n:] = -inverse.times(c1)
    b0, b2, bd = (np.zeros((2 * n, m)) for _ in range(3))
    b0[n:] = inverse.times(p0)
    b2[n:] = inverse.times(p2)
    bd[n:] = inverse.times(pd)
    force = np.zeros((2 * n, n))
    force[n:] = minv
    velocity = np.zeros((n, 2 * n))
    velocity[:, n:] = np.eye(n)
    zeros = np.zeros((n, m))
    return StateForm(n, massive, first, a0, a1, b0, b2, bd, force, minv, velocity, zeros, zeros)


def _others(n: int, indices) -> np.ndarray:
    """The indices ``0 .. n-1`` not in ``indices``, ascending (``numpy.setdiff1d`` without
    its sort, which imports ``numpy.ma``: 35 ms of a warm command's start)."""
    keep = np.ones(n, dtype=bool)
    keep[np.asarray(indices, dtype=np.intp)] = False
    return np.flatnonzero(keep)
