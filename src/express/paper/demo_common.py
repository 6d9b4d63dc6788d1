"""Pieces shared by the demo's figure modules: the two cars, steady means, and writing a
figure with its data (through :mod:`express.io.output`, whole or not at all)."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from express.numeric.statespace import VehicleModel

__all__ = ["Cars", "steady_mean", "write_figure", "write_table"]


@dataclass(frozen=True)
class Cars:
    """The two cars the paper compares: with forced steering and with conventional bogies."""

    steered: VehicleModel
    conventional: VehicleModel

    def items(self) -> Iterator[tuple[str, VehicleModel]]:
        """``("steered", car), ("conventional", car)``."""
        yield "steered", self.steered
        yield "conventional", self.conventional

    def with_values(self, changes: Mapping[str, float]) -> Cars:
        """Both cars with ``changes`` applied where the car has the parameter (SI)."""

        def changed(car: VehicleModel) -> VehicleModel:
            own = {k: v for k, v in changes.items() if k in car.values}
            return car.with_values(own) if own else car

        return Cars(changed(self.steered), changed(self.conventional))


def steady_mean(values: np.ndarray, distance: np.ndarray, window: tuple[float, float]) -> float:
    """Mean of ``values`` where ``window[0] <= distance <= window[1]``."""
    inside = (distance >= window[0]) & (distance <= window[1])
    if not inside.any():
        raise ValueError(f"no sample in the window {window[0]:g}-{window[1]:g} m")
    return float(np.mean(values[inside]))


def write_figure(figure: Any, stem: Path) -> list[Path]:
    """Write ``figure`` as ``stem.png`` and ``stem.svg``; returns the paths."""
    from express.analysis.plots import save_figure

    return save_figure(figure, [stem.with_suffix(".png"), stem.with_suffix(".svg")])


def write_table(path: Path, columns: Mapping[str, Any]) -> Path:
    """Write ``columns`` (names carry their units, values SI) as CSV; returns ``path``.
    A figure's data may have no value at a point (no critical speed below the scan's
    top, a range not checked): nan is written as an empty cell; an inf is refused
    (``docs/reliability.md``)."""
    from express.io.output import write_text
    from express.io.text_formats import csv_text

    write_text(path, csv_text(columns, markers=list(columns)))
    return path
