"""How many modes: the ride comfort of a vehicle with flexible bodies against the number
of modes kept (``express ride --modes-convergence``, ``docs/ride.md``).

The modes of every flexible body are ordered by their free-free frequency and kept one
more at a time, from none (the rigid bodies) to all of them.  A mode is *dropped* by
setting its shape values at every point to zero: every coupling of a mass-normalised
mode to the rest of the model (its springs and dampers, the output points) is
proportional to a shape value, so the dropped mode's coordinate is left on its own
(``q'' + 2 zeta w q' + w^2 q = 0``), unexcited and seen by no output.  This is exact
truncation: the same numbers as a model file that keeps only those modes
(``tests/test_modal_analyses.py``), with one derivation of the model for all the steps.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from numpy.typing import ArrayLike

from express.analysis.ride.summaries import PointComfort, point_comfort
from express.analysis.ride.vehicle import ride_response
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel

__all__ = ["ModeCountStep", "mode_count_convergence"]


@dataclass(frozen=True)
class ModeCountStep:
    """The ride comfort with the first ``count`` modes (by frequency) kept.

    Attributes
    ----------
    count : int
        Modes kept (0: every body rigid).
    added : str or None
        The modal coordinate kept from this step on (``CB.vb1``); None for the rigid step.
    label : str
        Words for it (``"car body first vertical bending"``; ``"rigid"``).
    frequency_hz : float
        Its free-free frequency [Hz] (nan for the rigid step).
    comfort : dict of str to PointComfort
        Per output point (``rms`` [m/s^2] per axis, ``n_mv``, ...).
    """

    count: int
    added: str | None
    label: str
    frequency_hz: float
    comfort: dict[str, PointComfort]

    def as_dict(self) -> dict[str, Any]:
        """Plain data (accelerations in m/s^2, frequency in Hz; null for the rigid step's)."""
        return {"modes": self.count, "added": self.added, "label": self.label,
                "frequency_hz": None if math.isnan(self.frequency_hz) else self.frequency_hz,
                "output_points": {name: c.as_dict() for name, c in self.comfort.items()}}


def _label(vehicle: VehicleModel, body: str, mode_name: str) -> str:
    from express.model.modal_body import mode_words

    model = vehicle.model
    label = next((b.label for b in model.bodies if b.id == body), "") if model is not None else ""
    return f"{label or body} {mode_words(mode_name)}"


def mode_count_convergence(vehicle: VehicleModel, spectra: Mapping[str, Any], speed: float | None = None,
                           frequencies: ArrayLike | None = None) -> tuple[ModeCountStep, ...]:
    """The ride comfort (:func:`~express.analysis.ride.summaries.point_comfort`) with 0, 1,
    ..., N of the flexible bodies' modes kept, by frequency (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data, output points and at least one flexible body.
    spectra, speed, frequencies
        As :func:`~express.analysis.ride.vehicle.ride_response`.

    Returns
    -------
    tuple of ModeCountStep
        N + 1 steps, the rigid one first.

    Raises
    ------
    ArgumentError
        A model without flexible bodies, or a mode shape that is not a parameter.
    """
    model = vehicle.model
    flexible = getattr(model, "flexible", ()) if model is not None else ()
    values = vehicle.values
    modes = []
    for body in flexible:
        for mode in body.modes:
            shapes = sorted({getattr(value, "name", "") for _, value in mode.shapes})
            if "" in shapes:
                raise ArgumentError(f"mode {body.body}.{mode.name}: a shape value is not a parameter")
            omega = values[getattr(mode.omega, "name", "")] if hasattr(mode.omega, "name") else float(mode.omega)
            modes.append((omega, f"{body.body}.{mode.name}", body.body, mode.name, shapes))
    if not modes:
        raise ArgumentError("the model has no flexible bodies ([flexible.<body>], docs/model-format.md): "
                            "no modes to count")
    modes.sort(key=lambda entry: (entry[0], entry[1]))
    steps = []
    for count in range(len(modes) + 1):
        dropped = {name: 0.0 for entry in modes[count:] for name in entry[4]}
        changed = vehicle.with_values(dropped) if dropped else vehicle
        comfort = point_comfort(ride_response(changed, spectra, speed, frequencies))
        if count == 0:
            steps.append(ModeCountStep(0, None, "rigid", math.nan, comfort))
        else:
            omega, coordinate, body, name, _ = modes[count - 1]
            steps.append(ModeCountStep(count, coordinate, _label(vehicle, body, name), omega / (2 * math.pi), comfort))
    return tuple(steps)
