"""The numerical linear model at one speed, and its hand-off to other tools.

A vehicle's equations ``M q'' + C(v) q' + K q = P(v) u + Pd u'`` become the state space
``x' = A x + B u + Bd u'`` (``x = [q; q']``).  Tools such as python-control and
``scipy.signal`` have no input-rate term, so :func:`linear_system` removes it exactly
with the usual change of state ``z = x - Bd u``::

    z' = A z + (B + A Bd) u,        x = z + Bd u

(``Bd`` only acts on the velocity rows, so the outputs ``x`` are the physical
displacements and velocities).  The result is a standard ``(A, B, C, D)`` with
``C = I`` and ``D = Bd``; its poles are the vehicle's eigenvalues.

Examples
--------
>>> from express.numeric.statespace import load_vehicle
>>> system = linear_system(load_vehicle("examples/conventional.toml"), 30.0)
>>> system.A.shape, system.B.shape, system.D.shape
((40, 40), (40, 22), (40, 22))
>>> system.outputs[:2]
('CB.x', 'CB.y')
"""

from __future__ import annotations

from typing import Any

import numpy as np

from express.export.plant import LinearSystem, check_speed, linear_system
from express.numeric.statespace import VehicleModel

__all__ = ["LinearSystem", "linear_system", "numeric_matrices", "to_control", "to_scipy"]


def _chosen(vehicle: VehicleModel, speed: float, outputs, track: bool, pade_order: int) -> LinearSystem:
    """:func:`linear_system` with the named ``outputs``, or driven by the track
    (:func:`express.export.track_system.track_system`).  An element's force that reads
    an input's rate (:mod:`express.export.element_forces`) adds that rate as an input,
    ``<input>_dot``, after the inputs."""
    from express.export.track_system import output_rows, track_system

    if track:
        return track_system(vehicle, speed, outputs=outputs, pade_order=pade_order)
    system = linear_system(vehicle, speed)
    if outputs is None:
        return system
    rows = output_rows(vehicle, outputs)
    c, d = rows.state @ system.C, rows.state @ system.D + rows.inputs
    rates = [j for j in range(rows.rates.shape[1]) if np.any(rows.rates[:, j])]
    b = np.hstack([system.B, np.zeros((system.B.shape[0], len(rates)))])
    d = np.hstack([d, rows.rates[:, rates]])
    inputs = system.inputs + tuple(f"{system.inputs[j]}_dot" for j in rates)
    return LinearSystem(system.A, b, c, d, system.states, inputs, rows.names, system.speed)


def to_control(vehicle: VehicleModel, speed: float, *, outputs=None, track: bool = False, pade_order: int = 6) -> Any:
    """A python-control ``StateSpace`` of the vehicle at ``speed`` [m/s], with named
    states, inputs and outputs (needs python-control).

    python-control does not allow ``.`` in signal names, so ``W1.yR`` becomes ``W1_yR``.

    Parameters
    ----------
    vehicle : VehicleModel
    speed : float
        [m/s].
    outputs : sequence of str, optional
        The outputs by name (:func:`express.export.track_system.output_rows`: a DOF, its
        rate ``W1.y_dot``, an output point, an element's force ``force_<element>``
        [N; N m]); every DOF and rate by default.  A force that reads an input's rate
        (a damper across stations in a curve) adds the rate as an input, ``<input>_dot``
        (:mod:`express.export.element_forces`).
    track : bool
        Driven by the track's alignment at the leading wheelset (one input), each
        wheelset's transport delay a Padé approximant
        (:func:`express.export.track_system.track_system`); else every model input.
    pade_order : int
        The approximants' order with ``track``.
    """
    import control

    system = _chosen(vehicle, speed, outputs, track, pade_order)

    def names(items: tuple[str, ...]) -> list[str]:
        return [item.replace(".", "_") for item in items]

    return control.ss(
        system.A, system.B, system.C, system.D,
        states=names(system.states), inputs=names(system.inputs), outputs=names(system.outputs),
    )


def to_scipy(vehicle: VehicleModel, speed: float, *, outputs=None, track: bool = False, pade_order: int = 6) -> Any:
    """A ``scipy.signal.StateSpace`` of the vehicle at ``speed`` [m/s] (names in
    :func:`linear_system`).

    Parameters
    ----------
    vehicle : VehicleModel
    speed : float
        [m/s].
    outputs, track, pade_order
        As :func:`to_control`.
    """
    from scipy import signal

    system = _chosen(vehicle, speed, outputs, track, pade_order)
    return signal.StateSpace(system.A, system.B, system.C, system.D)


def numeric_matrices(vehicle: VehicleModel, speed: float) -> dict[str, Any]:
    """Every numerical matrix at ``speed`` [m/s], for ``.mat``/``.npz`` files.

    Keys: ``M, C, K, P, Pd`` (the vehicle's equations), ``A, B, Bd`` (state space with
    input rates), ``speed`` [m/s], ``dofs`` and ``inputs`` (names).
    """
    speed = check_speed(speed)
    return {  # A as in linear_system, without its B + A Bd product and identity C (a long train's are dense)
        "M": vehicle.mass,
        "C": vehicle.damping(speed),
        "K": vehicle.stiffness,
        "P": vehicle.forcing(speed),
        "Pd": vehicle.forcing_rate(speed),
        "A": vehicle.state_matrix(speed),
        "B": vehicle.input_matrix(speed),
        "Bd": vehicle.input_rate_matrix(speed),
        "speed": np.array(float(speed)),
        "dofs": np.array(vehicle.dofs, dtype=str),
        "inputs": np.array(vehicle.inputs, dtype=str),
    }
