"""The vehicle's standard state space at one speed (``z' = A z + B u``, ``y = C z + D u``),
the input rates removed exactly (:mod:`express.export.linear_system` says how); the one
definition that the exports and the control plant
(:mod:`express.export.track_system`) build on."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.numeric.statespace import VehicleModel

__all__ = ["LinearSystem", "check_speed", "linear_system"]


@dataclass(frozen=True)
class LinearSystem:
    """A standard state space ``z' = A z + B u``, ``y = C z + D u`` with names.

    Attributes
    ----------
    A, B, C, D : numpy.ndarray
        Shapes (s, s), (s, m), (p, s), (p, m): (2n, 2n), (2n, m), (2n, 2n), (2n, m) for
        every DOF and rate out and every model input in.
    states, inputs, outputs : tuple of str
        Names: outputs are the DOFs then their rates (``W1.y``, ..., ``W1.y_dot``);
        the states carry the same names (the state equals the output when ``u = 0``).
    speed : float
        Speed the matrices were evaluated at [m/s].
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    speed: float


def linear_system(vehicle: VehicleModel, speed: float) -> LinearSystem:
    """The vehicle's linear model at ``speed`` [m/s] with the input rates removed.

    Raises
    ------
    ValueError
        If ``speed`` is not a positive finite number.
    """
    check_speed(speed)
    a = vehicle.state_matrix(speed)
    b = vehicle.input_matrix(speed)
    bd = vehicle.input_rate_matrix(speed)
    # state [q; q_D'] (express.assembly.first_order): series elements' strokes have no rate state
    names = tuple(vehicle.dofs) + tuple(f"{vehicle.dofs[i]}_dot" for i in vehicle.form.massive)
    return LinearSystem(
        A=a,
        B=b + a @ bd,
        C=np.eye(a.shape[0]),
        D=bd.copy(),
        states=names,
        inputs=tuple(vehicle.inputs),
        outputs=names,
        speed=float(speed),
    )


def check_speed(speed: float) -> None:
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"speed {speed!r}: must be a positive number of m/s")
