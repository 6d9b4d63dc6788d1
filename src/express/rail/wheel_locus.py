"""The contact locus of a yawed wheel: where a wheel of revolution, its axle turned by the
yaw angle about the vertical, can touch a prismatic rail, and that curve seen in the
rail's cross-section.

A rail that does not change along the track (tangent track) has its surface normal in
the track's cross-section (the ``y-z`` plane) everywhere, so at a contact the wheel's
normal must lie in that plane too.  On each circle of the wheel (profile position
``s``, radius ``R = r0 - z(s)``, axial distance ``Y = h + s`` from the wheelset centre,
``h`` the taping line's half distance) exactly one point near the bottom has that
property: with the wheelset yawed by ``psi`` (about the vertical, then rolled about the
track's longitudinal axis) it is the point turned by ``beta`` ahead of the circle's
lowest point with::

    sin(beta) = tan(psi) z'(s)

(``z'`` the profile's slope, positive where the radius falls toward the field side).
The set of these points is the **contact locus** (the "trace" method of Wang Kaiwen,
1984; semi-analytic searches of this kind are compared in S. Falomi, M. Malvezzi,
E. Meli, A. Rindi, "Determination of wheel-rail contact points: comparison between
classical and neural network based procedures", Meccanica 44, 2009, 661-686; that the
yawed wheelset's contact lies up to 10 mm from the axle's vertical plane and what it
does to the yaw moment: Mathematical Problems in Engineering 2016, article 1901089).
The contact is the locus point of least gap to the
rail, a plane problem in the cross-section: the locus projected on it is the yawed
wheel's **effective profile**.  For the left wheel (``sigma = +1``; the right one is its
mirror image, with the lead's sign reversed) a locus point lies, in the yawed and
unrolled wheelset frame (x forward, y left, z up, from the wheelset centre), at::

    x = cos(psi) R sin(beta) - sin(psi) Y        (the contact's lead)
    y = sin(psi) R sin(beta) + cos(psi) Y
    z = -R cos(beta)

and the roll turns ``(y, z)`` in the cross-section, which the unyawed contact search
already does.  The wheel's normal there passes through the axle (a surface of
revolution), so the normal force has no moment about it.

For a cone of slope ``tan(gamma)`` (``z' = tan(gamma)``) the lead is, exactly,
``x = R tan(psi) tan(gamma) cos(psi) - Y sin(psi)``: to first order in ``psi``,
``x = psi (R tan(gamma) - Y)``.  The effective profile's changes (radius ``R cos(beta)``,
lateral position ``sin(psi) R sin(beta)``) are even in ``psi`` and of second order.

All quantities SI (m, rad).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.interpolate import CubicSpline

from express.base.diagnostics import ArgumentError

__all__ = ["EffectiveProfile", "contact_locus", "effective_profile"]

#: Largest ``|sin(beta)|`` kept: steeper circles have no locus point near their bottom.
_MAX_SIN_BETA = 0.95


class EffectiveProfile(NamedTuple):
    """The yawed left wheel's effective profile on a uniform grid of ``s' = y - h``.

    ``z``, ``dz``, ``ddz``: height, slope and second derivative at ``start + step k``
    [m, -, 1/m] (the profile's convention: radius ``r0 - z``, so ``r0 - z`` is the
    contact's depth below the axle); ``lead``: the contact's lead ``x`` [m] there;
    ``position``: where on the wheel profile the locus point is (``s``) [m].
    """

    start: float
    step: float
    z: np.ndarray
    dz: np.ndarray
    ddz: np.ndarray
    lead: np.ndarray
    position: np.ndarray


def contact_locus(s: np.ndarray, z: np.ndarray, slope: np.ndarray, r0: float, half: float,
                  yaw: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Locus points of the left wheel yawed by ``yaw`` [rad].

    Parameters
    ----------
    s, z, slope : numpy.ndarray, shape (n,)
        Profile positions [m], heights [m] and slopes ``dz/ds`` [-].
    r0, half : float
        Nominal radius and the taping line's distance from the wheelset centre [m].

    Returns
    -------
    lateral, height, lead, kept : numpy.ndarray
        The locus points' ``y - half`` [m], ``r0 + z`` of the module docstring (the
        effective profile's height) [m], their lead ``x`` [m], and the mask of the
        profile points that have a locus point (``|sin(beta)| <= 0.95``).
    """
    sin_beta = math.tan(yaw) * slope
    kept = np.abs(sin_beta) <= _MAX_SIN_BETA
    radius = r0 - z
    axial = half + s
    ahead = radius * sin_beta
    cos_beta = np.sqrt(np.clip(1.0 - sin_beta**2, 0.0, None))
    c, sn = math.cos(yaw), math.sin(yaw)
    lateral = sn * ahead + c * axial - half
    height = r0 - radius * cos_beta
    lead = c * ahead - sn * axial
    return lateral, height, lead, kept


def effective_profile(start: float, step: float, z: np.ndarray, slope: np.ndarray, r0: float, half: float,
                      yaw: float) -> EffectiveProfile:
    """The effective profile of the left wheel (profile tabulated at ``start + step k``)
    yawed by ``yaw`` [rad], resampled on the same step.

    Raises
    ------
    ArgumentError
        When the locus folds over (its lateral position does not increase along the
        profile), which happens only at yaw angles far beyond a wheelset's.
    """
    s = start + step * np.arange(len(z))
    lateral, height, lead, kept = contact_locus(s, z, slope, r0, half, yaw)
    run = _longest_run(kept)
    lateral, height, lead, s = lateral[run], height[run], lead[run], s[run]
    if np.any(np.diff(lateral) <= 0.0):
        raise ArgumentError(f"the contact locus of the wheel yawed by {yaw * 1e3:g} mrad folds over: "
                            "the yaw is too large for this profile")
    grid = step * np.arange(math.ceil(lateral[0] / step - 1e-9), math.floor(lateral[-1] / step + 1e-9) + 1)
    spline = CubicSpline(lateral, height, bc_type="not-a-knot")
    return EffectiveProfile(float(grid[0]), step, spline(grid), spline(grid, 1), spline(grid, 2),
                            np.interp(grid, lateral, lead), np.interp(grid, lateral, s))


def _longest_run(mask: np.ndarray) -> slice:
    """The longest run of ``True`` in ``mask``."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    starts, ends = edges[::2], edges[1::2]
    if not len(starts):
        raise ArgumentError("no point of the wheel profile can touch the rail at this yaw")
    best = int(np.argmax(ends - starts))
    return slice(int(starts[best]), int(ends[best]))
