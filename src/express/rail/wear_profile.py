"""Wear distributed across a wheel profile by Archard's law (issue 37, item 2, first part):
the material a contact removes, spread over the lateral coordinate of the profile.

Archard's law: the volume worn off is ``V = k N s / H`` (``k`` the dimensionless wear
coefficient, ``N`` the normal force, ``s`` the sliding distance, ``H`` the hardness of the
softer body).  A contact patch with semi-axes ``a`` (rolling) and ``b`` (lateral) that
slides with a uniform slip ``gamma`` (the sliding distance per unit rolling distance; in
full slip the creepage's magnitude) removes, per unit rolling distance, ``k N gamma / H``;
a surface point at lateral offset ``t = (y - centre) / b`` from the patch centre passes under
the line load ``q(y) = \\int p dx`` and loses ``k gamma q(y) / H`` per passage, spread over
the wheel's circumference ``2 pi R``.  For the two pressure distributions here:

* ``"hertz"``: ``p = p0 sqrt(1 - x^2/a^2 - y^2/b^2)``, ``q = (3 N / (4 b)) (1 - t^2)``;
* ``"uniform"``: ``p = N / (pi a b)`` on the ellipse, ``q = (2 N / (pi b)) sqrt(1 - t^2)``.

:func:`profile_wear_depth` integrates ``q`` over each cell of a lateral grid exactly (its
antiderivative), so that the volume on the profile equals the patch's to rounding
whatever the grid.  :func:`usfd_profile_wear` spreads the USFD wear rate of a run's
contacts (:mod:`express.rail.wear`) the same way, the mass as a volume of steel.  Sources
and limits: ``docs/wear.md``, "Wear across the profile".
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.base.diagnostics import ArgumentError
from express.rail.wear import wear_rate_of_contact

__all__ = ["PRESSURES", "WHEEL_STEEL_DENSITY", "archard_volume", "profile_wear_depth", "rolled_per_instant",
           "smooth_depth", "spread_volume", "usfd_profile_wear"]

FloatArray = NDArray[np.float64]
#: The pressure distributions of :func:`profile_wear_depth`.
PRESSURES = ("hertz", "uniform")
#: Density of wheel steel [kg/m^3] (carbon steel; an assumption, not a measured R8T value).
WHEEL_STEEL_DENSITY = 7850.0


def archard_volume(coefficient: float, normal: ArrayLike, sliding: ArrayLike, hardness: float) -> FloatArray:
    """Archard's worn volume ``k N s / H`` [m^3] (``normal`` [N], ``sliding`` distance [m],
    ``hardness`` [Pa]; arrays broadcast)."""
    return coefficient * np.asarray(normal, dtype=float) * np.asarray(sliding, dtype=float) / hardness


def _load_fraction(t: FloatArray, pressure: str) -> FloatArray:
    """Share of the normal force on the patch's strips at lateral offsets below ``t``
    (``t = (y - centre) / b``, clipped to [-1, 1]): 0 at -1, 1 at 1."""
    t = np.clip(t, -1.0, 1.0)
    if pressure == "hertz":
        return 0.5 + 0.75 * (t - t**3 / 3.0)
    return 0.5 + (t * np.sqrt(1.0 - t * t) + np.arcsin(t)) / math.pi


def spread_volume(edges: ArrayLike, centre: ArrayLike, semi_b: ArrayLike, volume: ArrayLike, *, radius: float,
                  pressure: str = "hertz") -> FloatArray:
    """Mean depth [m] of each cell of a lateral grid (``edges``, shape (M + 1,), [m],
    increasing) when contacts remove ``volume`` [m^3] each (shape (K,), broadcast with
    ``centre`` and ``semi_b`` [m]) in proportion to their line load (``pressure``, module
    docstring), spread over the circumference ``2 pi radius``; shape (M,)."""
    if pressure not in PRESSURES:
        raise ArgumentError(f"pressure {pressure!r}: use one of {', '.join(PRESSURES)}")
    edges = np.asarray(edges, dtype=float)
    width = np.diff(edges)
    if edges.ndim != 1 or width.size < 1 or not np.all(width > 0):
        raise ArgumentError("edges must be at least two increasing lateral coordinates")
    if not radius > 0:
        raise ArgumentError("the radius must be positive")
    centre, semi_b, volume = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                                   for v in (centre, semi_b, volume)))
    if np.any(semi_b <= 0):
        raise ArgumentError("semi_b must be positive")
    share = np.diff(_load_fraction((edges[None, :] - centre[:, None]) / semi_b[:, None], pressure), axis=1)
    return (volume @ share) / (2.0 * math.pi * radius * width)


def profile_wear_depth(edges: ArrayLike, centre: ArrayLike, semi_b: ArrayLike, normal: ArrayLike, slip: ArrayLike,
                       distance: ArrayLike, *, coefficient: float, hardness: float, radius: float,
                       pressure: str = "hertz") -> FloatArray:
    """Depth worn off each cell of a lateral grid of the wheel profile [m] by contacts,
    by Archard's law.

    Parameters
    ----------
    edges : array_like, shape (M + 1,)
        Cell edges of the lateral profile coordinate [m], increasing.
    centre, semi_b, normal, slip, distance : array_like, shape (K,)
        Per contact (an instant of a run, a wheel): the patch centre on the profile
        coordinate [m], its lateral semi-axis [m], the normal force [N], the slip (sliding
        per unit rolling distance) [-], and the distance rolled with it [m] (broadcast).
    coefficient : float
        Archard's wear coefficient k [-].
    hardness : float
        H [Pa].
    radius : float
        Rolling radius R [m]: the removed volume is spread over ``2 pi R``.
    pressure : {"hertz", "uniform"}
        The pressure distribution across the patch.

    Returns
    -------
    numpy.ndarray, shape (M,)
        Mean depth of each cell [m]; ``sum(depth * width) 2 pi R`` is the Archard volume of
        the contacts' parts inside the grid.
    """
    if not (coefficient >= 0 and hardness > 0):
        raise ArgumentError("the wear coefficient must be >= 0, the hardness > 0")
    normal, slip, distance = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, dtype=float))
                                                   for v in (normal, slip, distance)))
    volume = archard_volume(coefficient, np.maximum(normal, 0.0), np.abs(slip) * distance, hardness)
    return spread_volume(edges, centre, semi_b, volume, radius=radius, pressure=pressure)


def usfd_profile_wear(edges: ArrayLike, centre: ArrayLike, semi_b: ArrayLike, tgamma: ArrayLike, area: ArrayLike,
                      rolled: ArrayLike, *, radius: float, density: float = WHEEL_STEEL_DENSITY,
                      pressure: str = "hertz") -> FloatArray:
    """Depth worn off each cell of a lateral grid of the wheel profile [m] by the USFD
    wear rate of contacts (:func:`express.rail.wear.wear_rate_of_contact`: Tgamma [N],
    patch area [m^2]) over the distances ``rolled`` [m] (all shape (K,), broadcast; the
    patch centres ``centre`` and lateral semi-axes ``semi_b`` [m]): the mass
    ``rate x A x rolled`` [ug] as a volume of steel of ``density`` [kg/m^3], spread by
    :func:`spread_volume`; shape (M,)."""
    if not density > 0:
        raise ArgumentError("the density must be positive")
    area = np.asarray(area, dtype=float)
    mass = wear_rate_of_contact(tgamma, area) * (area * 1e6) * np.asarray(rolled, dtype=float) * 1e-9  # kg
    return spread_volume(edges, centre, np.where(np.asarray(semi_b) > 0, semi_b, 1.0), mass / density,
                         radius=radius, pressure=pressure)


def rolled_per_instant(distance: ArrayLike) -> FloatArray:
    """The distance each instant of a run stands for [m] (trapezoidal weights of the
    distances ``distance``, shape (N,)): half the interval on each side; they sum to the
    run's length."""
    d = np.asarray(distance, dtype=float)
    if d.size < 2:
        raise ArgumentError("a run of at least two instants")
    step = np.diff(d)
    return np.concatenate([[0.5 * step[0]], 0.5 * (step[:-1] + step[1:]), [0.5 * step[-1]]])


def smooth_depth(depth: ArrayLike, spacing: float, width: float) -> FloatArray:
    """``depth`` on uniform cells of ``spacing`` [m] (shape (M,)) convolved with a
    Gaussian of standard deviation ``width`` [m] (truncated at 4 ``width``, its discrete
    weights normalised to 1); what the kernel carries beyond either end of the grid is
    folded back into the cells it came over, so the sum (the volume) is kept to rounding.
    ``width = 0`` returns the depth unchanged; shape (M,)."""
    depth = np.asarray(depth, dtype=float)
    if not (spacing > 0 and width >= 0):
        raise ArgumentError("the spacing must be positive and the smoothing width >= 0")
    half = math.ceil(4.0 * width / spacing)
    if half == 0 or depth.size < 2:
        return depth.copy()
    offsets = np.arange(-half, half + 1) * spacing
    kernel = np.exp(-0.5 * (offsets / width) ** 2)
    kernel /= kernel.sum()
    full = np.convolve(depth, kernel)  # length M + 2 half
    m = depth.size
    out = full[half:half + m].copy()
    for k in range(half):  # fold the overhang back, mirrored about each end
        out[min(half - 1 - k, m - 1)] += full[k]
        out[max(m - 1 - k, 0)] += full[half + m + k]
    return out
