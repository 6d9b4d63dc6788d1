"""The options of every critical-speed search, in SI, with their one set of defaults: the
linear search (:func:`express.analysis.stability.stability.critical_speed`), the study's fast search,
the sensitivities, the commands and the report. Light to import (the command line's defaults)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from express.base.diagnostics import ArgumentError
from express.base.units import KMH

__all__ = ["CHECKS", "CriticalOptions", "SearchCheck"]

#: How the study's fast search confirms a crossing (``analysis/study/critical.py``).
SearchCheck = Literal["grid", "local"]
CHECKS: tuple[SearchCheck, ...] = ("grid", "local")


@dataclass(frozen=True)
class CriticalOptions:
    """Options of the critical-speed search, in SI (those of ``express critical-speed``).

    Attributes
    ----------
    v_min, v_max : float
        Speed range scanned [m/s], ``0 < v_min < v_max`` (defaults 1 and 150 m/s, that is
        3.6 and 540 km/h).
    tolerance : float
        Width of the final bisection bracket [m/s] (default 0.1 km/h); 0 asks the study's
        search for the exact crossing instead of the bracket midpoint (the linear search
        of :func:`~express.analysis.stability.stability.critical_speed` needs it positive).
    threshold : float
        A real part counts as positive only above this [1/s].
    points : int
        Speeds of the geometric grid (>= 2).
    check : {"grid", "local"}
        How the study's fast search confirms a crossing (``analysis/study/critical.py``).

    Examples
    --------
    >>> options = CriticalOptions(v_max=200 * KMH)
    >>> round(options.v_min * 3.6, 6), round(options.tolerance * 3.6, 6)
    (3.6, 0.1)
    """

    v_min: float = 3.6 * KMH
    v_max: float = 540 * KMH
    tolerance: float = 0.1 * KMH
    threshold: float = 1e-6
    points: int = 40
    check: SearchCheck = "grid"

    def __post_init__(self) -> None:
        if not (0 < self.v_min < self.v_max and math.isfinite(self.v_max)):
            raise ArgumentError(f"need 0 < v_min < v_max, got v_min={self.v_min}, v_max={self.v_max}")
        if not (self.tolerance >= 0 and math.isfinite(self.tolerance)):
            raise ArgumentError(f"tolerance must be >= 0, got {self.tolerance}")
        if self.points < 2:
            raise ArgumentError(f"points must be at least 2, got {self.points}")
        if self.check not in CHECKS:
            raise ArgumentError(f'check must be "grid" or "local", got {self.check!r}')

    @property
    def grid(self):
        """The scanned speeds [m/s]: ``points`` spaced geometrically from ``v_min`` to
        ``v_max`` (numpy.ndarray, shape (points,))."""
        import numpy as np

        return np.geomspace(self.v_min, self.v_max, self.points)

    @property
    def tolerance_kmh(self) -> float:
        """:attr:`tolerance` [km/h]."""
        return self.tolerance / KMH
