"""Precomputed tables of a track layout, for vectorized evaluation.

This module owns the numbers a :class:`~express.rail.track.geometry.Track` computes
once from its segments: per-segment start/end curvature and cant with the ramp shape
(:class:`SegmentTables`, which also evaluates the exact heading) and the centreline
points every 10 m or less (:class:`CentrelineTable`). Pure NumPy, no segment classes:
:mod:`express.rail.track.geometry` turns segments into the per-segment arrays.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from express.rail.track._common import FloatArray

__all__ = ["CONSTANT", "LINEAR", "RAMP_CODES", "SINE", "CentrelineTable", "SegmentTables", "ramp"]

#: Ramp codes of :attr:`SegmentTables.shape`: constant (straight, curve), linear, sine.
CONSTANT, LINEAR, SINE = 0, 1, 2
#: Ramp code of each transition shape.
RAMP_CODES = {"linear": LINEAR, "sine": SINE}

# Gauss-Legendre rule used to integrate the heading into the centreline.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
#: Longest piece of track integrated with one Gauss-Legendre rule [m].
_PIECE = 10.0


def ramp(shape: np.ndarray, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Ramp f(u), its derivative f'(u) and its integral F(u) = int_0^u f, per shape code."""
    lin, sine = shape == LINEAR, shape == SINE
    f = np.where(lin, u, np.where(sine, 0.5 * (1 - np.cos(np.pi * u)), 0.0))
    df = np.where(lin, 1.0, np.where(sine, 0.5 * np.pi * np.sin(np.pi * u), 0.0))
    big_f = np.where(lin, 0.5 * u**2, np.where(sine, 0.5 * u - np.sin(np.pi * u) / (2 * np.pi), 0.0))
    return f, df, big_f


@dataclass(frozen=True, eq=False)
class SegmentTables:
    """Per-segment arrays of a layout of n segments, for vectorized evaluation.

    Attributes
    ----------
    starts : ndarray, shape (n + 1,)
        Distances of the joints [m], from 0 to the length.
    lengths : ndarray, shape (n,)
        Segment lengths [m].
    shape : ndarray of int, shape (n,)
        Ramp code: 0 constant, 1 linear, 2 sine.
    rho0, rho1 : ndarray, shape (n,)
        Signed curvature at the start and end of each segment [1/m].
    cant0, cant1 : ndarray, shape (n,)
        Signed cant at the start and end of each segment [m].
    heading0 : ndarray, shape (n + 1,)
        Heading at the joints [rad] (exact integral of the curvature).
    """

    starts: FloatArray
    lengths: FloatArray
    shape: np.ndarray
    rho0: FloatArray
    rho1: FloatArray
    cant0: FloatArray
    cant1: FloatArray
    heading0: FloatArray

    @classmethod
    def build(cls, lengths: FloatArray, shape: np.ndarray, rho0: FloatArray, rho1: FloatArray,
              cant0: FloatArray, cant1: FloatArray) -> SegmentTables:
        """Tables from the per-segment values (each of shape (n,)): joints and headings.

        The heading at each joint is the exact integral of the curvature,
        ``sum L (rho0 + (rho1 - rho0) F(1))`` with F the integral of the ramp.
        """
        n = lengths.size
        heading = np.zeros(n + 1)
        if n:
            _, _, big_f = ramp(shape, np.ones(n))
            heading[1:] = np.cumsum(lengths * (rho0 + (rho1 - rho0) * big_f))
        starts = np.concatenate([[0.0], np.cumsum(lengths)])
        return cls(starts, lengths, shape, rho0, rho1, cant0, cant1, heading)

    @property
    def count(self) -> int:
        """Number of segments n."""
        return int(self.lengths.size)

    @property
    def length(self) -> float:
        """Total length [m]."""
        return float(self.starts[-1])

    def locate(self, s: FloatArray) -> tuple[np.ndarray, FloatArray, np.ndarray]:
        """Segment index, local coordinate u in [0, 1] and inside-mask for each s [m]."""
        inside = (s >= 0.0) & (s < self.length)
        k = np.clip(np.searchsorted(self.starts, s, side="right") - 1, 0, max(self.count - 1, 0))
        if self.count == 0:
            return k, np.zeros_like(s), inside
        u = np.clip((s - self.starts[k]) / self.lengths[k], 0.0, 1.0)
        return k, u, inside

    def heading_inside(self, s: FloatArray) -> FloatArray:
        """Heading [rad] for 0 <= s <= length (s clipped to that range), exact."""
        if self.count == 0:
            return np.zeros_like(s)
        k, u, _ = self.locate(np.clip(s, 0.0, self.length))
        _, _, big_f = ramp(self.shape[k], u)
        rho0, rho1 = self.rho0[k], self.rho1[k]
        return self.heading0[k] + self.lengths[k] * (rho0 * u + (rho1 - rho0) * big_f)

    def integrate_tangent(self, a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Integral of (cos, sin)(heading) from a to b [m], both in one smooth piece."""
        half = 0.5 * (b - a)
        t = (0.5 * (a + b))[..., None] + half[..., None] * _GL_X
        th = self.heading_inside(t)
        return half * (np.cos(th) @ _GL_W), half * (np.sin(th) @ _GL_W)


@dataclass(frozen=True, eq=False)
class CentrelineTable:
    """Centreline points (X, Y) [m] at knots at most 10 m apart inside each segment.

    Attributes
    ----------
    knots : ndarray, shape (m,)
        Distances s of the knots [m], from 0 to the length.
    x, y : ndarray, shape (m,)
        Plane coordinates of the centreline there [m].
    """

    knots: FloatArray
    x: FloatArray
    y: FloatArray

    @classmethod
    def build(cls, tables: SegmentTables) -> CentrelineTable:
        """Integrate the heading of ``tables`` piece by piece (16-point Gauss-Legendre)."""
        knots = [np.zeros(1)]
        for a, length in zip(tables.starts[:-1], tables.lengths, strict=True):
            m = max(1, math.ceil(length / _PIECE))
            knots.append(a + length * np.arange(1, m + 1) / m)
        knots_arr = np.concatenate(knots)
        x = np.zeros(knots_arr.size)
        y = np.zeros(knots_arr.size)
        if knots_arr.size > 1:
            dx, dy = tables.integrate_tangent(knots_arr[:-1], knots_arr[1:])
            x[1:], y[1:] = np.cumsum(dx), np.cumsum(dy)
        return cls(knots_arr, x, y)
