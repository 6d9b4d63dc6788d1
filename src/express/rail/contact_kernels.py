"""The compiled kernels of the rigid wheelset's contact search.

This module owns the Numba kernels that find, for each lateral displacement ``y``, the
roll at which both wheels touch their rails and each contact's point, radius, angle and
curvatures (:func:`solve_all`), the uniform surface tables they read
(:class:`SurfaceTable`) and the layout of their results (:data:`WHEELSET_RESULTS`,
:data:`CONTACT_RESULTS`). The surfaces, the setup and the table of results are
:mod:`express.rail.contact_geometry`. All quantities are SI (m, rad, 1/m).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = ["CONTACT_RESULTS", "SIDES", "WHEELSET_RESULTS", "SurfaceTable", "solve_all"]


class SurfaceTable(NamedTuple):
    """A surface's uniform table for the compiled kernels: height ``z`` [m], slope ``dz``
    [-] and second derivative ``ddz`` [1/m] at ``start + step * k`` [m]."""

    start: float
    step: float
    z: np.ndarray
    dz: np.ndarray
    ddz: np.ndarray


#: Results of :func:`solve_all` for the wheelset at each ``y``, then for each contact
#: (row 0 left, row 1 right) at each ``y``.
WHEELSET_RESULTS = ("roll", "height")
CONTACT_RESULTS = ("wheel_position", "track_position", "rail_height", "radius", "contact_angle", "wheel_curvature",
                   "rail_curvature", "secondary_gap", "secondary_position")
_ROLL, _HEIGHT = range(len(WHEELSET_RESULTS))
(_WHEEL_POSITION, _TRACK_POSITION, _RAIL_HEIGHT, _RADIUS, _CONTACT_ANGLE, _WHEEL_CURVATURE, _RAIL_CURVATURE,
 _SECONDARY_GAP, _SECONDARY_POSITION) = range(len(CONTACT_RESULTS))
#: ``sigma`` of the left and right side.
SIDES = (1.0, -1.0)


@njit(cache=True)
def _hermite(start, step, z, dz, x):
    """Cubic Hermite value and slope of a uniform table at x (nan outside)."""
    f = (x - start) / step
    k = math.floor(f)
    if k < 0 or k >= len(z) - 1:
        return math.nan, math.nan
    t = f - k
    t2 = t * t
    value = ((1.0 + 2.0 * t) * (1.0 - t) ** 2 * z[k] + t * (1.0 - t) ** 2 * step * dz[k]
             + t2 * (3.0 - 2.0 * t) * z[k + 1] + t2 * (t - 1.0) * step * dz[k + 1])
    slope = ((6.0 * t2 - 6.0 * t) * (z[k] - z[k + 1]) / step
             + (3.0 * t2 - 4.0 * t + 1.0) * dz[k] + (3.0 * t2 - 2.0 * t) * dz[k + 1])
    return value, slope


@njit(cache=True)
def _scan(sigma, y, c, sn, r0, half, wheel, rail, gaps, around, width):
    """Vertical gap at the wheel points (inf off the rail), all of them when ``around`` < 0,
    else the ``width`` either side of index ``around``; index of the smallest."""
    best = math.inf
    best_index = -1
    first, last = 0, len(wheel.z)
    if around >= 0:
        first, last = max(0, around - width), min(len(wheel.z), around + width + 1)
    for i in range(first, last):
        yw = sigma * (half + wheel.start + wheel.step * i)
        zw = -r0 + wheel.z[i]
        height, _ = _hermite(rail.start, rail.step, rail.z, rail.dz, sigma * (y + c * yw - sn * zw))
        if math.isnan(height):
            gaps[i] = math.inf
            continue
        gap = sn * yw + c * zw - height
        gaps[i] = gap
        if gap < best:
            best = gap
            best_index = i
    return best_index


@njit(cache=True)
def _linear(start, step, values, x):
    """Linear interpolation in a uniform table (clamped to its ends)."""
    f = (x - start) / step
    k = min(max(math.floor(f), 0), len(values) - 2)
    t = f - k
    return (1.0 - t) * values[k] + t * values[k + 1]


@njit(cache=True)
def _refine(sigma, y, c, sn, r0, half, wheel, rail, gaps, i):
    """Gap minimum near wheel point i: a parabola through the neighbours, then Newton
    steps on d gap / ds = 0 with the tables' curvatures (near-conformal contacts have a
    flat gap, where the parabola alone is off by a micrometre).

    Returns (wheel position, gap, d gap / d phi, u, rail z)."""
    ws, wh, wz = wheel.start, wheel.step, wheel.z
    t = 0.0
    if 0 < i < len(wz) - 1 and math.isfinite(gaps[i - 1]) and math.isfinite(gaps[i + 1]):
        curvature = gaps[i - 1] - 2.0 * gaps[i] + gaps[i + 1]
        if curvature > 0.0:
            t = min(0.5, max(-0.5, 0.5 * (gaps[i - 1] - gaps[i + 1]) / curvature))
    s = ws + wh * (i + t)
    for _ in range(2):
        zw, dzw = _hermite(ws, wh, wz, wheel.dz, s)
        u = sigma * (y + c * sigma * (half + s) - sn * (-r0 + zw))
        height, rail_slope = _hermite(rail.start, rail.step, rail.z, rail.dz, u)
        if math.isnan(zw) or math.isnan(height):
            break
        ddzw = _linear(ws, wh, wheel.ddz, s)
        du = c - sigma * sn * dzw
        first = (sn * sigma + c * dzw) - rail_slope * du
        second = c * ddzw - _linear(rail.start, rail.step, rail.ddz, u) * du * du + rail_slope * sigma * sn * ddzw
        if not second > 0.0:
            break
        step = first / second
        if abs(s - step - (ws + wh * i)) > wh:
            break
        s -= step
    zw_profile, _ = _hermite(ws, wh, wz, wheel.dz, s)
    if math.isnan(zw_profile):
        zw_profile = wz[i]
        s = ws + wh * i
    yw = sigma * (half + s)
    zw = -r0 + zw_profile
    u = sigma * (y + c * yw - sn * zw)
    height, rail_slope = _hermite(rail.start, rail.step, rail.z, rail.dz, u)
    if math.isnan(height):
        u = sigma * (y + c * sigma * (half + ws + wh * i) - sn * (-r0 + wz[i]))
        height, rail_slope = _hermite(rail.start, rail.step, rail.z, rail.dz, u)
    gap = sn * yw + c * zw - height
    d_gap = (c * yw - sn * zw) - rail_slope * sigma * (-sn * yw - c * zw)
    return s, gap, d_gap, u, height


@njit(cache=True)
def _secondary(gaps, i, primary):
    """Smallest local gap minimum outside the valley of point i: (gap - primary, index)."""
    n = len(gaps)
    lo = i
    while lo > 0 and math.isfinite(gaps[lo - 1]) and gaps[lo - 1] >= gaps[lo]:
        lo -= 1
    hi = i
    while hi < n - 1 and math.isfinite(gaps[hi + 1]) and gaps[hi + 1] >= gaps[hi]:
        hi += 1
    best = math.inf
    best_index = -1
    for j in range(1, n - 1):
        if lo <= j <= hi or not math.isfinite(gaps[j - 1]) or not math.isfinite(gaps[j + 1]):
            continue
        if gaps[j] <= gaps[j - 1] and gaps[j] <= gaps[j + 1] and gaps[j] < best:
            best = gaps[j]
            best_index = j
    return best - primary, best_index


@njit(cache=True)
def _contact_results(sigma, phi, r0, s, u, height, i, gaps, wheel, rail, out, k):
    """The contact's entries of :data:`CONTACT_RESULTS` at ``y[k]`` into ``out`` (one side's rows)."""
    zw, slope = _hermite(wheel.start, wheel.step, wheel.z, wheel.dz, s)
    ddz_w = _linear(wheel.start, wheel.step, wheel.ddz, s)
    ddz_r = _linear(rail.start, rail.step, rail.ddz, u)
    _, rail_slope = _hermite(rail.start, rail.step, rail.z, rail.dz, u)
    gap2, j2 = _secondary(gaps, i, gaps[i])
    out[_WHEEL_POSITION, k] = s
    out[_TRACK_POSITION, k] = u
    out[_RAIL_HEIGHT, k] = height
    out[_RADIUS, k] = r0 - zw
    out[_CONTACT_ANGLE, k] = math.atan(slope) + sigma * phi
    out[_WHEEL_CURVATURE, k] = ddz_w / (1.0 + slope * slope) ** 1.5
    out[_RAIL_CURVATURE, k] = -ddz_r / (1.0 + rail_slope * rail_slope) ** 1.5
    out[_SECONDARY_GAP, k] = gap2
    out[_SECONDARY_POSITION, k] = wheel.start + wheel.step * j2 if j2 >= 0 else math.nan


@njit(cache=True)
def solve_all(ys, r0, half, wheels, rails, wheelset, contacts):
    """Roll and contact of every y (:data:`WHEELSET_RESULTS` into ``wheelset``,
    :data:`CONTACT_RESULTS` into ``contacts``) for the (left, right) :class:`SurfaceTable`
    of ``wheels`` and ``rails``; returns -1, or the index of a y without contact."""
    gaps = np.empty((2, max(len(wheels[0].z), len(wheels[1].z))))
    index = np.full(2, -1)
    position, gap, slope, u, height = np.empty(2), np.empty(2), np.empty(2), np.empty(2), np.empty(2)
    phi = 0.0
    width = 40  # points either side searched while iterating; a full scan confirms
    for k in range(len(ys)):
        y = ys[k]
        lo, hi = -0.3, 0.3
        full = True
        for _ in range(100):
            c, sn = math.cos(phi), math.sin(phi)
            for row in range(2):
                index[row] = _scan(SIDES[row], y, c, sn, r0, half, wheels[row], rails[row],
                                   gaps[row, : len(wheels[row].z)], -1 if full else index[row], width)
            if index[0] < 0 or index[1] < 0:
                if full:
                    return k
                full = True
                continue
            for row in range(2):
                position[row], gap[row], slope[row], u[row], height[row] = _refine(
                    SIDES[row], y, c, sn, r0, half, wheels[row], rails[row], gaps[row, : len(wheels[row].z)],
                    index[row])
            f = gap[0] - gap[1]
            if f > 0.0:
                hi = phi
            else:
                lo = phi
            if abs(f) < 1e-14 or hi - lo < 1e-15:
                if full:
                    break
                full = True  # confirm the minima with a full scan at this roll
                continue
            derivative = slope[0] - slope[1]
            new = phi - f / derivative if derivative > 0.0 else 0.5 * (lo + hi)
            if not lo < new < hi:
                new = 0.5 * (lo + hi)
            phi = new
            full = False
        wheelset[_ROLL, k] = phi
        wheelset[_HEIGHT, k] = -0.5 * (gap[0] + gap[1]) - r0
        for row in range(2):
            _contact_results(SIDES[row], phi, r0, position[row], u[row], height[row], index[row],
                             gaps[row, : len(wheels[row].z)], wheels[row], rails[row], contacts[:, row], k)
    return -1
