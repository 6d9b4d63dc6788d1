"""Nonlinear creep-force law of one wheel/rail contact: Polach's method with spin.

Polach's method (O. Polach, "A fast wheel-rail forces calculation computer code",
Vehicle System Dynamics 33 (Suppl.), 1999, 728-739; O. Polach, "Creep forces in
simulations of traction vehicles running on adhesion limit", Wear 258, 2005, 992-1000)
gives the tangential forces of an elliptic Hertz contact in closed form.  With the
creepages xi (longitudinal), eta (lateral), phi (spin, 1/m), the normal force N, the
friction coefficient mu, the semi-axes a (rolling direction) and b, the shear modulus G
and Kalker's coefficients C11, C22, C23 (:func:`express.rail.kalker.kalker_coefficients`):

* spin adds to the lateral creepage when it increases it:
  ``eta_C = eta + phi a`` if ``|eta + phi a| > |eta|``, else ``eta_C = eta``;
  ``s_C = sqrt(xi^2 + eta_C^2)``, ``s = sqrt(xi^2 + eta^2)``;
* the force of the translational creepages, from the gradient of the tangential stress
  in the area of adhesion::

      c = sqrt((C11 xi / s)^2 + (C22 eta / s)^2),  e = pi G a b c s_C / (4 mu N)
      F = (2 mu N / pi) (e / (1 + e^2) + atan(e))

  along ``-(xi, eta) / s_C``;
* the lateral force of spin::

      K_S = 1 + 6.3 (1 - exp(-a / b)),  e_M = (8/3) G b sqrt(ab) C23 s_C / (K_S mu N)
      d = (e_M^2 - 1) / (e_M^2 + 1)
      K_M = |e_M| (d^3/3 - d^2/2 + 1/6) - sqrt((1 - d^2)^3) / 3
      F_yS = -(9/16) a mu N K_M K_S phi / s_C

  (``K_M`` is written with ``2 / (e_M^2 + 1)`` so that neither end cancels).

Signs are Kalker's (``express.rail.contact``): the forces on the wheel oppose the
creepages, ``Fx = -F xi / s_C``, ``Fy = -F eta / s_C - F_yS``.  For small creepages
``F -> G a b c s_C`` and ``F_yS -> G (ab)^1.5 C23 phi``: the law tends to Kalker's
linear theory ``Fx = -f11 xi``, ``Fy = -f22 eta - f23 phi`` (tested), and the resultant
never exceeds ``mu N``.  Some published transcriptions of Polach's listing put
``|eta_C|`` in place of ``s_C`` in ``e_M``; with ``s_C`` the linear limit is Kalker's
``f23 phi`` for any longitudinal creepage, which is why it is used here.  The spin
moment (``f23 eta - f33 phi`` in the linear theory) is not part of the method.

The scalar kernel :func:`polach` is compiled (numba) for the simulation;
:func:`polach_forces` is its NumPy-facing form.
"""

from __future__ import annotations

import math

import numpy as np

from express.base.kernels import kernel

__all__ = ["FASTSIM_GRID", "fastsim", "polach", "polach_forces", "polach_longitudinal", "polach_with_slope",
           "spin_reduction"]


@kernel
def spin_reduction(epsilon_m: float) -> float:
    """Polach's ``K_M`` of the spin force for ``e_M >= 0`` (between ``-2 e_M / 3`` for
    small ``e_M`` and ``-2 / (3 e_M^3)`` for large), written without cancellation."""
    d = 2.0 / (epsilon_m * epsilon_m + 1.0)  # 1 - delta
    return epsilon_m * (0.5 * d * d - d * d * d / 3.0) - math.sqrt(max(2.0 * d - d * d, 0.0)) ** 3 / 3.0


@kernel
def polach(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """Tangential forces ``(Fx, Fy)`` [N] on the wheel by Polach's method.

    Parameters
    ----------
    normal : float
        Normal force N [N] (> 0; 0 gives no force).
    friction : float
        Coefficient of friction mu [-].
    a, b : float
        Semi-axes of the contact ellipse along and across the rolling direction [m].
    shear_modulus : float
        G [Pa].
    c11, c22, c23 : float
        Kalker's coefficients for a/b and Poisson's ratio [-].
    xi, eta : float
        Longitudinal and lateral creepage [-].
    phi : float
        Spin creepage [1/m].
    """
    fx, fy, _ = polach_with_slope(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi)
    return fx, fy


@kernel
def polach_with_slope(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """:func:`polach`'s ``(Fx, Fy)`` [N] and the tangent stiffness ``-dFx/dxi`` [N] of
    :func:`polach_longitudinal`."""
    if not normal > 0.0:
        return 0.0, 0.0, 0.0
    eta_c = eta
    if abs(eta + phi * a) > abs(eta):
        eta_c = eta + phi * a
    s_c = math.sqrt(xi * xi + eta_c * eta_c)
    if s_c == 0.0:
        return 0.0, 0.0, shear_modulus * a * b * c11
    limit = friction * normal
    force, gain = _translational(limit, a, b, shear_modulus, c11, c22, xi, eta, s_c)
    fx = -force * xi / s_c
    fy = -force * eta / s_c
    if phi != 0.0:
        k_s = 1.0 + 6.3 * (1.0 - math.exp(-a / b))
        e_m = 8.0 / 3.0 * shear_modulus * b * math.sqrt(a * b) * c23 * s_c / (k_s * limit)
        fy += 9.0 / 16.0 * a * limit * spin_reduction(e_m) * k_s * phi / s_c
    return fx, fy, (gain * xi * xi + force * eta_c * eta_c / s_c) / (s_c * s_c)


@kernel
def _translational(limit, a, b, shear_modulus, c11, c22, xi, eta, s_c):
    """Polach's force of the translational creepages ``F`` [N] and ``dF / ds_C`` [N]
    (``c`` held) for ``mu N = limit``, ``s_C > 0``."""
    s = math.sqrt(xi * xi + eta * eta)
    if not s > 0.0:
        return 0.0, 0.0
    c = math.sqrt((c11 * xi / s) ** 2 + (c22 * eta / s) ** 2)
    gain = math.pi * shear_modulus * a * b * c / (4.0 * limit)
    e = gain * s_c
    square = 1.0 + e * e
    return 2.0 * limit / math.pi * (e / square + math.atan(e)), 4.0 * limit / math.pi * gain / (square * square)


@kernel
def polach_longitudinal(normal, friction, a, b, shear_modulus, c11, c22, xi, eta, eta_c):
    """Polach's longitudinal force ``Fx`` [N] and its tangent stiffness ``-dFx/dxi`` [N]
    at ``xi`` for a lateral creepage ``eta`` (``eta_c`` with the spin's share, held):
    ``-dFx/dxi = (F' xi^2 + F eta_C^2 / s_C) / s_C^2`` (the wheel's pitch balance)."""
    s_c = math.sqrt(xi * xi + eta_c * eta_c)
    if not (normal > 0.0 and s_c > 0.0):
        return 0.0, shear_modulus * a * b * c11
    force, slope = _translational(friction * normal, a, b, shear_modulus, c11, c22, xi, eta, s_c)
    return -force * xi / s_c, (slope * xi * xi + force * eta_c * eta_c / s_c) / (s_c * s_c)


def polach_forces(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """:func:`polach` over arrays (broadcast); returns ``(Fx, Fy)`` as float arrays [N]."""
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in
                                   (normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi)))
    fx = np.empty(arrays[0].shape)
    fy = np.empty(arrays[0].shape)
    for index in np.ndindex(fx.shape):
        fx[index], fy[index] = polach(*(float(v[index]) for v in arrays))
    return fx, fy


# --------------------------------------------------------------------------- FASTSIM

#: Strips across and elements along each strip of :func:`fastsim`.
FASTSIM_GRID = (3, 5)


def _fastsim_factors(strips: int, elements: int) -> tuple[float, float]:
    """Ratios of the discrete no-slip forces of the grid to the exact ones, for the
    translational creepages (sum over strips of (1 - y^2) against 4/3) and for spin
    (sum of (1 - y^2)^1.5 against 3 pi / 8, times the midpoint rule's 1 + 1/(2 n^2) along a strip)."""
    eta = -1.0 + (np.arange(strips) + 0.5) * 2.0 / strips
    weight = 2.0 / strips
    translation = float(np.sum(1.0 - eta**2) * weight / (4.0 / 3.0))
    spin = float(np.sum((1.0 - eta**2) ** 1.5) * weight / (3.0 * math.pi / 8.0)) * (1.0 + 0.5 / elements**2)
    return translation, spin




def _fastsim_grid(strips: int, elements: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Constants of a grid in the unit circle: each strip's centre ``y / b`` and
    ``sqrt(1 - (y/b)^2)`` (its half-length over ``a``), and each element's share of the
    strip's parabolic pressure peak, ``1 - (x_centre / half)^2``."""
    eta = -1.0 + (np.arange(strips) + 0.5) * 2.0 / strips
    centre = 1.0 - (2.0 * np.arange(elements) + 1.0) / elements
    return eta, np.sqrt(1.0 - eta**2), 1.0 - centre**2


_FACTORS = _fastsim_factors(*FASTSIM_GRID)
_GRID = _fastsim_grid(*FASTSIM_GRID)


@kernel
def _fastsim(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi, strip_y, strip_root, shape, k_t,
             k_s):
    if not normal > 0.0:
        return 0.0, 0.0
    strips = strip_y.size
    elements = shape.size
    # flexibilities of the simplified theory, scaled so that the grid's no-slip forces
    # are Kalker's linear ones exactly
    l1 = 8.0 * a * k_t / (3.0 * shear_modulus * c11)
    l2 = 8.0 * a * k_t / (3.0 * shear_modulus * c22)
    l3 = math.pi * a * math.sqrt(a / b) * k_s / (4.0 * shear_modulus * c23)
    # mu times the peak of the parabolic pressure, whose sum over the grid is N (the grid's
    # midpoint sum of the parabola is k_s times its integral, as for spin)
    peak = friction * 2.0 * normal / (math.pi * a * b * k_s)
    dy = 2.0 * b / strips
    fx = 0.0
    fy = 0.0
    for j in range(strips):
        y = b * strip_y[j]
        root = strip_root[j]
        half = a * root
        dx = 2.0 * half / elements
        # traction at the element centres, marched from the leading edge: the slip is
        # linear in x, so its integral between centres (at their midpoint) is exact;
        # each centre's traction is limited to mu p there (midpoint rule for the force)
        step_x = dx * (xi / l1 - phi * y / l3)
        step_y = dx * (eta / l2 + phi * half / l3)  # the lateral slip's part at x = half
        change = -dx * dx * phi / l3  # the lateral step changes by this per element
        px = -0.5 * step_x
        py = -0.5 * (step_y - 0.25 * dx * dx * phi / l3)
        step_y += change  # the step from the first centre to the second
        limit = peak * root * root
        strip_x = 0.0
        strip_y_sum = 0.0
        for k in range(elements):
            if k > 0:
                px -= step_x
                py -= step_y
                step_y += change
            bound = limit * shape[k]
            size2 = px * px + py * py
            if size2 > bound * bound:
                scale = bound / math.sqrt(size2)
                px *= scale
                py *= scale
            strip_x += px
            strip_y_sum += py
        fx += strip_x * dx * dy
        fy += strip_y_sum * dx * dy
    return fx, fy


@kernel
def fastsim(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi):
    """Tangential forces ``(Fx, Fy)`` [N] on the wheel by Kalker's FASTSIM.

    Kalker's simplified theory (J. J. Kalker, "A fast algorithm for the simplified
    theory of rolling contact", Vehicle System Dynamics 11, 1982, 1-13) with three
    flexibilities ``L1 = 8a / (3 G C11)``, ``L2 = 8a / (3 G C22)``,
    ``L3 = pi a sqrt(a/b) / (4 G C23)`` and the parabolic pressure; the ellipse is cut in
    :data:`FASTSIM_GRID` strips and elements, marched from the leading edge, the traction
    limited to ``mu p``.  The flexibilities are scaled by the grid's discrete no-slip
    integrals, so the linear limit is Kalker's ``-f11 xi``, ``-f22 eta - f23 phi`` to
    rounding.  Arguments as :func:`polach`.
    """
    return _fastsim(normal, friction, a, b, shear_modulus, c11, c22, c23, xi, eta, phi, _GRID[0], _GRID[1], _GRID[2],
                    _FACTORS[0], _FACTORS[1])
