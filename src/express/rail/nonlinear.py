"""The nonlinear wheel/rail forces fed back as inputs: flange contact and creep saturation.

Flange contact (paper eqs. 10-11): the penetration ``dy`` beyond the flange
clearance ``delta`` enters the input ``<wheelset>.dy`` of P, which holds ``-kR``.

Creep saturation: the Shen-Hedrick-Elkins law (Shen, Hedrick & Elkins 1983,
"A comparison of alternative creep force models for rail vehicle dynamic analysis",
Proc. 8th IAVSD Symposium) limits the resultant creep force of each wheel to
``mu N``::

    F' = mu N (x - x**2 / 3 + x**3 / 27)   for x = F / (mu N) <= 3,   else mu N

and the linear forces are scaled by ``F' / F``.  The difference between the
saturated and the linear creep forces is fed back as generalized forces on the
wheelset's lateral and yaw DOFs.

All functions are vectorized over wheelsets (and time).  The laws themselves are the
compiled ufuncs :func:`penetration`, :func:`longitudinal_creepage` and
:func:`saturation_ratio`, which the time march (:mod:`express.analysis.time.integrator`) calls
on scalars: one formula each.
"""

from __future__ import annotations

import numpy as np
from numba import vectorize

from express.base.diagnostics import ArgumentError

__all__ = [
    "flange_penetration", "linear_creepages", "longitudinal_creepage", "penetration", "saturation_factor",
    "saturation_ratio", "wheelset_forces",
]


@vectorize(["float64(float64, float64)"], cache=True)
def penetration(relative, clearance):
    """Flange penetration ``dy`` [m] (eq. 11) of a lateral displacement ``relative`` from
    the rail [m] beyond the clearance ``delta`` [m]: zero inside it (a ufunc)."""
    if relative > clearance:
        return relative - clearance
    if relative < -clearance:
        return relative + clearance
    return 0.0


@vectorize(["float64(float64, float64)"], cache=True)
def saturation_ratio(force, limit):
    """Shen-Hedrick-Elkins ratio ``F' / F`` of a linear creep force ``F`` >= 0 [N] under
    the limit ``mu N`` [N] (a ufunc; :func:`saturation_factor` checks its arguments)::

        x = F / (mu N),   F' / F = 1 - x / 3 + x**2 / 27 for 0 < x <= 3,   1 / x beyond,   1 at x = 0
    """
    ratio = force / limit
    if not ratio > 0.0:
        return 1.0
    if ratio <= 3.0:
        return (ratio - ratio * ratio / 3.0 + ratio * ratio * ratio / 27.0) / ratio
    return 1.0 / ratio


@vectorize(["float64(float64, float64, float64, float64, float64, float64, float64)"], cache=True)
def longitudinal_creepage(relative, psi_dot, curvature, speed, conicity, r0, b):
    """``xi_x = Gamma (y - yR) / r0 + b psi' / v + b rho`` of the left wheel (the right
    wheel's is opposite) [-] (a ufunc): ``relative = y - yR`` [m], ``psi_dot`` [rad/s],
    ``curvature`` [1/m], ``speed`` [m/s], ``r0`` and ``b`` [m]."""
    return conicity * relative / r0 + b * psi_dot / speed + b * curvature


def flange_penetration(y, y_rail, clearance):
    """Flange penetration ``dy`` [m] (eq. 11): zero inside the clearance.

    Parameters
    ----------
    y, y_rail : array_like
        Wheelset lateral displacement and rail lateral irregularity [m].
    clearance : array_like
        Flange clearance ``delta`` [m].
    """
    return penetration(np.asarray(y, dtype=float) - y_rail, clearance)


def saturation_factor(force, limit):
    """Shen-Hedrick-Elkins ratio ``F' / F`` for a linear creep force ``F`` >= 0.

    Parameters
    ----------
    force : array_like
        Magnitude of the linear (Kalker) creep force of a wheel [N].
    limit : array_like
        ``mu N`` [N].

    Returns
    -------
    numpy.ndarray
        Factor in (0, 1]; 1 for a zero force.

    Raises
    ------
    ArgumentError
        For a limit that is not positive (a friction coefficient or wheel load of
        zero: no creep force can be transmitted; the model's ranges refuse both).

    Examples
    --------
    >>> float(saturation_factor(0.0, 1.0)), float(saturation_factor(3.0, 1.0))
    (1.0, 0.3333333333333333)
    """
    force = np.asarray(force, dtype=float)
    limit = np.asarray(limit, dtype=float)
    if not np.all(limit > 0.0):
        raise ArgumentError("the creep force limit mu N must be positive (friction and wheel load above zero)")
    return saturation_ratio(force, limit)


def linear_creepages(y, psi, y_dot, psi_dot, y_rail, curvature, speed, conicity, r0, b):
    """Longitudinal and lateral creepages of the wheels of a wheelset (``rail.md``).

    Returns
    -------
    longitudinal, lateral : numpy.ndarray
        ``xi_x = Gamma (y - yR) / r0 + b psi' / v + b rho`` (left wheel's sign; the
        right wheel has the opposite) and ``xi_y = y' / v - psi``.
    """
    longitudinal = longitudinal_creepage(np.asarray(y) - y_rail, psi_dot, curvature, speed, conicity, r0, b)
    lateral = np.asarray(y_dot) / speed - psi
    return longitudinal, lateral


def wheelset_forces(y, psi, y_dot, psi_dot, y_rail, curvature, speed, wheelsets, *, flange=True, saturation=True):
    """Wheel/rail forces on each wheelset.

    Parameters
    ----------
    y, psi, y_dot, psi_dot, y_rail, curvature : array_like, shape (..., n_wheelsets)
        States and track inputs at each wheelset.
    speed : float
        Forward speed [m/s].
    wheelsets : sequence of WheelsetData
        Numerical wheel/rail data.
    flange, saturation : bool
        Include flange contact / creep saturation.

    Returns
    -------
    dict of str to numpy.ndarray
        ``lateral_creep`` (F, saturated), ``yaw_creep`` (M, saturated), ``flange``
        (``-kR dy``), ``dy``, ``lateral`` (Q = creep + flange, force from the rails on
        the wheelset, y positive to the left), ``factor`` (saturation ratio), and the
        corrections ``lateral_correction`` and ``yaw_correction`` (saturated minus
        linear) that are fed back.
    """
    f1 = np.array([w.f1 for w in wheelsets])
    f2 = np.array([w.f2 for w in wheelsets])
    conicity = np.array([w.conicity for w in wheelsets])
    r0 = np.array([w.r0 for w in wheelsets])
    b = np.array([w.b for w in wheelsets])
    clearance = np.array([w.flange_clearance for w in wheelsets])
    k_rail = np.array([w.rail_stiffness for w in wheelsets])
    limit = np.array([w.friction * w.wheel_load for w in wheelsets])
    xi_x, xi_y = linear_creepages(y, psi, y_dot, psi_dot, y_rail, curvature, speed, conicity, r0, b)
    lateral_linear = -2.0 * f2 * xi_y
    yaw_linear = -2.0 * b * f1 * xi_x
    if saturation:
        factor = saturation_factor(np.hypot(f1 * xi_x, f2 * xi_y), limit)
    else:
        factor = np.ones_like(lateral_linear)
    dy = flange_penetration(y, y_rail, clearance) if flange else np.zeros_like(lateral_linear)
    flange_force = -k_rail * dy
    lateral_creep = factor * lateral_linear
    return {
        "lateral_creep": lateral_creep,
        "yaw_creep": factor * yaw_linear,
        "flange": flange_force,
        "dy": dy,
        "lateral": lateral_creep + flange_force,
        "factor": factor,
        "lateral_correction": (factor - 1.0) * lateral_linear,
        "yaw_correction": (factor - 1.0) * yaw_linear,
    }
