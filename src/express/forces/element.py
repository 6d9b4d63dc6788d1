"""The interface of a nonlinear force element, and the stacked set the analyses see.

The state equation with nonlinear forces is

    x' = A x + e(t) + G z(x, t)

with ``A`` and ``e`` the linear state space (:mod:`express.numeric.statespace`) and ``z``
the forces of the elements, stacked; ``G`` holds, column by column, where each force acts.
An element (:class:`ForceElement`) owns a block of ``z`` and of the columns of ``G``; the
march, the steady-curving solver and the nonlinear critical speed use only
:class:`ForceSet`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from express.forces.law import NoForces

__all__ = ["ForceElement", "ForceSet", "sparse_rows"]


def sparse_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The few nonzero terms of each row of ``rows`` (n_rows, N), for a compiled law:
    ``(places, coefficients)``, each (n_rows, width), padded with zeros (place 0, factor
    0), so that ``row . x = sum coefficients[r, :] x[places[r, :]]``."""
    width = max([1] + [int(np.count_nonzero(row)) for row in rows])
    places = np.zeros((rows.shape[0], width), dtype=np.int64)
    coefficients = np.zeros((rows.shape[0], width))
    for r, row in enumerate(rows):
        nonzero = np.flatnonzero(row)
        places[r, : nonzero.size], coefficients[r, : nonzero.size] = nonzero, row[nonzero]
    return places, coefficients


class ForceElement(ABC):
    """One kind of nonlinear force, evaluated at one vehicle's numbers along one run.

    A subclass says, for its block of forces:

    - ``names``: the name of every force of the block (``z`` rows), and their ``units``;
    - :meth:`directions`: where they act, the block's columns of ``G``, shape (N, width);
    - :attr:`reads`: the state coordinates the forces depend on;
    - :attr:`states`: its internal states (0: none; friction sliders will have some);
    - :meth:`law`: its typed parameters as the NamedTuple that selects its compiled law
      (:func:`express.forces.law.force_law`), placed at ``first`` in the stack;
    - :meth:`forces`: the same forces evaluated in NumPy (the steady-state solver);
    - :meth:`slopes`: its linearisation ``dz/dx`` at a state (the tangent);
    - :meth:`outputs`: the time histories it reports, with :meth:`output_units`.
    """

    #: What the element is, for messages and ``options``.
    kind: str = ""
    #: Number of internal states of the element.
    states: int = 0

    @property
    @abstractmethod
    def names(self) -> tuple[str, ...]:
        """The name of every force of the block, in order."""

    @property
    def width(self) -> int:
        """Number of forces of the block."""
        return len(self.names)

    @property
    @abstractmethod
    def reads(self) -> np.ndarray:
        """Indices of the state coordinates the forces depend on (int array)."""

    @abstractmethod
    def directions(self) -> np.ndarray:
        """Where the forces act: the block's columns of ``G``, shape (N, width)."""

    @abstractmethod
    def law(self, first: int) -> NamedTuple:
        """The compiled law's parameters, writing ``z[first : first + width]``."""

    @abstractmethod
    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        """The block of ``z`` at state ``x`` (shape (N,)) and step ``k``, shape (width,)."""

    @abstractmethod
    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        """``dz/dx`` of the block at ``x`` (whose forces are ``forces``), shape (width, N)."""

    def resolved_step(self, mass: np.ndarray) -> float | None:
        """The largest time step [s] that resolves what the element feeds back explicitly
        (its stiffest linearisation), given the mass matrix (n, n); None: no limit."""
        return None

    def record_shape(self) -> tuple[int, ...] | None:
        """The shape of what the compiled law records per step, or None (nothing)."""
        return None

    def outputs(self, states: np.ndarray, history: np.ndarray) -> dict[str, np.ndarray]:
        """Time histories of the element's outputs from the march's ``states``
        (steps + 1, N) and records ``history`` [SI]; none by default."""
        return {}

    def output_units(self) -> dict[str, str]:
        """SI unit of every output of :meth:`outputs`."""
        return {}


@dataclass(frozen=True)
class ForceSet:
    """The nonlinear force elements of a run, stacked in order.

    Attributes
    ----------
    elements : tuple of ForceElement
    size : int
        N, the length of the state.
    """

    elements: tuple[ForceElement, ...]
    size: int

    @property
    def width(self) -> int:
        """Length of ``z``."""
        return sum(element.width for element in self.elements)

    @property
    def names(self) -> tuple[str, ...]:
        """The name of every force of ``z``."""
        return tuple(name for element in self.elements for name in element.names)

    def _firsts(self) -> list[int]:
        return list(np.cumsum([0] + [element.width for element in self.elements])[:-1])

    def selector(self) -> np.ndarray:
        """``G``, shape (N, width)."""
        blocks = [element.directions() for element in self.elements]
        return np.column_stack(blocks) if blocks else np.zeros((self.size, 0))

    def laws(self) -> tuple[Any, ...]:
        """The compiled laws of the stack, each at its place (never empty)."""
        laws = tuple(element.law(int(first)) for element, first in zip(self.elements, self._firsts(), strict=True))
        return laws or (NoForces(0),)

    def resolved_step(self, mass: np.ndarray) -> float | None:
        """The smallest :meth:`ForceElement.resolved_step` of the stack [s], None if none."""
        steps = [s for s in (e.resolved_step(mass) for e in self.elements) if s is not None]
        return min(steps) if steps else None

    def history(self, steps: int) -> np.ndarray:
        """Zeroed records of the march, shape (steps + 1, ...) of the one recording element
        (empty trailing axes when none records)."""
        shapes = [s for s in (e.record_shape() for e in self.elements) if s is not None]
        if len(shapes) > 1:
            raise ValueError("only one element of a set may record (the march keeps one history)")
        return np.zeros((steps + 1, *(shapes[0] if shapes else (0, 0))))

    def forces(self, x: np.ndarray, k: int = 0) -> np.ndarray:
        """``z`` at state ``x`` and step ``k`` (NumPy), shape (width,)."""
        blocks = [element.forces(x, k) for element in self.elements]
        return np.concatenate(blocks) if blocks else np.zeros(0)

    def slopes(self, x: np.ndarray, k: int = 0, forces: np.ndarray | None = None) -> np.ndarray:
        """``dz/dx`` at ``x``, shape (width, N) (``forces``: ``z`` at ``x``, if known)."""
        z = self.forces(x, k) if forces is None else forces
        blocks, first = [], 0
        for element in self.elements:
            blocks.append(element.slopes(x, k, z[first:first + element.width]))
            first += element.width
        return np.vstack(blocks) if blocks else np.zeros((0, x.size))

    def outputs(self, states: np.ndarray, history: np.ndarray) -> dict[str, np.ndarray]:
        """Every element's outputs (:meth:`ForceElement.outputs`)."""
        found: dict[str, np.ndarray] = {}
        for element in self.elements:
            found.update(element.outputs(states, history))
        return found

    def output_units(self) -> dict[str, str]:
        """SI unit of every output of :meth:`outputs`."""
        found: dict[str, str] = {}
        for element in self.elements:
            found.update(element.output_units())
        return found

    def of_kind(self, kind: type) -> Sequence[ForceElement]:
        """The elements of the class ``kind``."""
        return [element for element in self.elements if isinstance(element, kind)]
