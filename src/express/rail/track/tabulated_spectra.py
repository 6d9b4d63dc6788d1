"""A user's track spectrum: a table of PSD against wavenumber, linear in between.

This module owns :class:`TabulatedSpectrum` (a :class:`~express.rail.track.spectra.TrackSpectrum`
read from a table in rad/m or cycles per metre, with its exact band variance) and
:func:`table_problems`, every problem of such a table at once. The published spectra
and their registry are :mod:`express.rail.track.spectra`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from express.base.diagnostics import ArgumentError
from express.rail.track._common import FloatArray
from express.rail.track.spectra import COMPONENTS, TrackSpectrum

__all__ = ["TabulatedSpectrum", "table_problems"]


@dataclass(frozen=True)
class TabulatedSpectrum(TrackSpectrum):
    """A user's spectrum: a table of PSD against wavenumber, linear in between.

    ``S`` is the piecewise-linear interpolation of the table and zero outside it, so the
    band variance is exact (trapezoids). :meth:`from_table` reads a table in rad/m or in
    cycles per metre.

    Parameters
    ----------
    name : str
        Label.
    wavenumbers : tuple of float
        Omega [rad/m], >= 0, strictly increasing, at least two.
    values : tuple of float
        S [m^2/(rad/m)] (or the component's unit squared per rad/m), >= 0, finite.
    component : str
        One of :data:`COMPONENTS`; default ``"alignment"``.

    Raises
    ------
    ArgumentError
        Naming every problem of the table.
    """

    name: str
    wavenumbers: tuple[float, ...]
    values: tuple[float, ...]
    component: str = "alignment"  # type: ignore[misc]  # per table, not per class

    def __post_init__(self) -> None:
        problems = table_problems(self.wavenumbers, self.values, self.component)
        if problems:
            raise ArgumentError(f"{self.name}: " + "; ".join(problems))
        object.__setattr__(self, "wavenumbers", tuple(float(x) for x in self.wavenumbers))
        object.__setattr__(self, "values", tuple(float(x) for x in self.values))

    @classmethod
    def from_table(cls, name: str, frequencies: ArrayLike, values: ArrayLike, unit: str = "rad/m",
                   component: str = "alignment") -> TabulatedSpectrum:
        """From a table in ``unit`` ``"rad/m"`` (Omega, S(Omega)) or ``"1/m"`` (n, G(n)).

        A table per cycle/m is converted by ``Omega = 2 pi n``, ``S = G / (2 pi)``.
        """
        f = np.asarray(frequencies, dtype=float).ravel()
        g = np.asarray(values, dtype=float).ravel()
        if unit == "1/m":
            f, g = 2 * np.pi * f, g / (2 * np.pi)
        elif unit != "rad/m":
            raise ArgumentError(f"{name}: unit must be 'rad/m' or '1/m', got {unit!r}")
        return cls(name, tuple(f), tuple(g), component)

    def psd(self, omega: ArrayLike) -> FloatArray:
        """One-sided PSD at wavenumbers ``omega`` [rad/m]; zero outside the table."""
        return np.interp(np.asarray(omega, dtype=float), self.wavenumbers, self.values, left=0.0, right=0.0)

    def primitive(self, omega: FloatArray) -> FloatArray:
        """Antiderivative (zero below the table), exact for the linear pieces."""
        x, v = np.asarray(self.wavenumbers), np.asarray(self.values)
        cumulative = np.concatenate([[0.0], np.cumsum(np.diff(x) * (v[:-1] + v[1:]) / 2)])
        w = np.clip(np.asarray(omega, dtype=float), x[0], x[-1])
        i = np.clip(np.searchsorted(x, w, side="right") - 1, 0, x.size - 2)
        d = w - x[i]
        slope = (v[i + 1] - v[i]) / (x[i + 1] - x[i])
        return cumulative[i] + v[i] * d + 0.5 * slope * d**2


def table_problems(wavenumbers: ArrayLike, values: ArrayLike, component: str = "alignment") -> list[str]:
    """Every problem of a PSD table (empty if none): shapes, order, signs, component."""
    problems = []
    try:
        x = np.asarray(wavenumbers, dtype=float)
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return ["the table must hold numbers"]
    if x.ndim != 1 or v.ndim != 1 or x.size != v.size or x.size < 2:
        problems.append(f"need two columns of equal length >= 2, got {x.size} wavenumbers and {v.size} values")
    else:
        if not np.all(np.isfinite(x)) or np.any(x < 0):
            problems.append("wavenumbers must be finite and >= 0")
        elif np.any(np.diff(x) <= 0):
            i = int(np.argmax(np.diff(x) <= 0))
            problems.append(f"wavenumbers must increase strictly (row {i + 2}: {x[i + 1]!r} after {x[i]!r})")
        if not np.all(np.isfinite(v)):
            problems.append("PSD values must be finite")
        elif np.any(v < 0):
            i = int(np.argmax(v < 0))
            problems.append(f"PSD values must be >= 0 (row {i + 1}: {v[i]!r})")
    if component not in COMPONENTS:
        problems.append(f"unknown component {component!r} (known: {', '.join(COMPONENTS)})")
    return problems
