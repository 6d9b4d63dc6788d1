"""Where a vehicle's rail inputs are: the stations and the names of the input groups.

Records only, with no SymPy: a numerical vehicle read back from the derivation cache
(:mod:`express.numeric.facts`) holds them without the symbolic model.
:func:`express.rail.build.rail_layout` builds them from a model,
:func:`express.rail.curve.stations` the stations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["RailLayout", "Station"]


@dataclass(frozen=True)
class Station:
    """A station along the vehicle where curvature and cant are sampled.

    Attributes
    ----------
    name : str
        The first body at this station; inputs are ``<name>.rho`` and ``<name>.S``.
    position : sympy.Expr or float
        Distance ahead of the vehicle origin [m]: an expression of the parameters, or
        its value [m] in a vehicle read back from the derivation cache.
    bodies : tuple of str
        Every body at this station.
    """

    name: str
    position: Any
    bodies: tuple[str, ...]

    @property
    def curvature_input(self) -> str:
        return f"{self.name}.rho"

    @property
    def cant_input(self) -> str:
        return f"{self.name}.S"


@dataclass(frozen=True)
class RailLayout:
    """Where the rail inputs are and what they mean.

    Attributes
    ----------
    wheelsets : tuple of str
        Wheelset body ids, front to back as listed in the model.
    stations : tuple of Station
        Stations that carry curvature and cant inputs.
    irregularity, flange, curvature, cant : tuple of str
        Input names of each group, in order.
    """

    wheelsets: tuple[str, ...]
    stations: tuple[Station, ...]
    irregularity: tuple[str, ...]
    flange: tuple[str, ...]
    curvature: tuple[str, ...]
    cant: tuple[str, ...]

    @property
    def inputs(self) -> tuple[str, ...]:
        """All rail inputs in the paper's order."""
        return self.irregularity + self.flange + self.curvature + self.cant
