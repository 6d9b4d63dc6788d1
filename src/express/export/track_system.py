"""The vehicle as a control-design plant driven by the track (issue 35, item 6): chosen
outputs, the lateral alignment as its one input, and the wheelsets' transport delays.

Each wheelset meets the alignment ``y(t)`` of the leading one ``tau_n = (x_1 - x_n) / v``
later (:func:`express.analysis.frequency.frequency.irregularity_delays`). In the frequency domain
that delay is exact, ``e^{-i w tau_n}`` (:func:`track_response`); a state space cannot
hold it, so :func:`track_system` puts the ``(N, N)`` Padé approximant of each delay in
series with the vehicle (:func:`pade_delay`)::

    e^{-s tau} ~ P(-s tau) / P(s tau),   P(x) = sum_k c_k x^k,
    c_k = (2N - k)! N! / ((2N)! k! (N - k)!)

whose magnitude is exactly 1 at every frequency and whose phase error grows as
``(w tau)^(2N+1)``: state the order and the band it is good for (``docs/analyses.md``,
"Hand-off to control design").

Outputs by name: a DOF (``W1.y``), its rate (``W1.y_dot``), an output point's lateral
displacement (``floor_front``, :attr:`express.numeric.facts.VehicleFacts.outputs`), its
velocity (``floor_front_dot``) or an element's force (``force_<element>``,
:mod:`express.export.element_forces`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from math import factorial

import numpy as np

from express.base.diagnostics import ArgumentError
from express.export.plant import LinearSystem, check_speed, linear_system
from express.numeric.statespace import VehicleModel

__all__ = ["ALIGNMENT", "OutputRows", "output_rows", "pade_delay", "track_response", "track_system"]

#: The name of the track input.
ALIGNMENT = "alignment"


def pade_delay(delay: float, order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(A, B, C, D)`` of the ``(order, order)`` Padé approximant of ``e^{-s delay}``
    (module docstring); no states for a zero delay or order.

    Parameters
    ----------
    delay : float
        [s], >= 0.
    order : int
        N, 0 to 20.
    """
    from scipy.signal import tf2ss

    if not (np.isfinite(delay) and delay >= 0):
        raise ArgumentError(f"delay must be >= 0 s, got {delay!r}")
    if not 0 <= order <= 20:
        raise ArgumentError(f"pade_order must be 0 to 20, got {order!r}")
    if delay == 0 or order == 0:
        return np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), np.ones((1, 1))
    c = [factorial(2 * order - k) * factorial(order) / (factorial(2 * order) * factorial(k) * factorial(order - k))
         for k in range(order + 1)]
    numerator = [c[k] * (-delay) ** k for k in range(order, -1, -1)]  # descending powers of s
    denominator = [c[k] * delay**k for k in range(order, -1, -1)]
    a, b, cc, d = tf2ss(numerator, denominator)
    return a, b, cc, d


@dataclass(frozen=True)
class OutputRows:
    """The named outputs ``y = state @ x + inputs @ u + rates @ u'`` over the state
    ``x = [q; q_D']`` (shape (k, N)), the inputs and their rates (shape (k, m) each):
    only an element's force reads the inputs (:mod:`express.export.element_forces`)."""

    names: tuple[str, ...]
    state: np.ndarray
    inputs: np.ndarray
    rates: np.ndarray


def output_rows(vehicle: VehicleModel, outputs: Sequence[str] | None) -> OutputRows:
    """The rows of the named outputs (module docstring); every DOF and its rate when
    ``outputs`` is None."""
    from express.export.element_forces import FORCE, element_force_rows

    names = tuple(vehicle.dofs) + tuple(f"{vehicle.dofs[i]}_dot" for i in vehicle.form.massive)
    size, m = vehicle.form.size, len(vehicle.inputs)
    if outputs is None:
        return OutputRows(names, np.eye(size), np.zeros((size, m)), np.zeros((size, m)))
    outputs = tuple(outputs)
    forces = [name for name in outputs if name.startswith(FORCE) and name not in vehicle.dofs]
    found = element_force_rows(vehicle, forces) if forces else None
    points = {p.name: np.array(p.row(vehicle.dofs)) for p in vehicle.facts.outputs}
    velocity = {int(i): vehicle.n + j for j, i in enumerate(vehicle.form.massive)}
    state, inputs, rates = np.zeros((len(outputs), size)), np.zeros((len(outputs), m)), np.zeros((len(outputs), m))
    unknown = []
    for r, name in enumerate(outputs):
        base, rate = (name[:-4], True) if name.endswith("_dot") else (name, False)
        if found is not None and name in found.names:
            f = found.names.index(name)
            state[r], inputs[r], rates[r] = found.state[f], found.inputs[f], found.rates[f]
        elif base in vehicle.dofs and (not rate or vehicle.dofs.index(base) in velocity):
            i = vehicle.dofs.index(base)
            state[r, velocity[i] if rate else i] = 1.0
        elif base in points and not (rate and any(points[base][i] and i not in velocity for i in range(vehicle.n))):
            for j in np.flatnonzero(points[base]).tolist():
                state[r, velocity[j] if rate else j] = points[base][j]
        else:
            unknown.append(name)
    if unknown:
        offered = ", ".join([*list(points)[:5], *vehicle.dofs[:5]])
        raise ArgumentError(f"outputs: no such output {', '.join(map(repr, unknown))} (a DOF, its rate 'W1.y_dot', "
                            f"an output point or an element's force 'force_<element>'; e.g. {offered})")
    return OutputRows(outputs, state, inputs, rates)


def _alignment_columns(vehicle: VehicleModel) -> list[int]:
    if vehicle.layout is None or not vehicle.layout.irregularity:
        raise ArgumentError("the model has no rail data (wheelsets): no track input")
    return [list(vehicle.inputs).index(name) for name in vehicle.layout.irregularity]


def track_system(vehicle: VehicleModel, speed: float, *, outputs: Sequence[str] | None = None,
                 pade_order: int = 6) -> LinearSystem:
    """The vehicle at ``speed`` [m/s] driven by the alignment at its leading wheelset, the
    wheelsets' delays as Padé approximants of ``pade_order`` (module docstring).

    Returns
    -------
    LinearSystem
        One input, :data:`ALIGNMENT` [m]; the states are the delays' (``delay{n}_{k}``)
        then the vehicle's.
    """
    from express.analysis.frequency.frequency import irregularity_delays

    speed = check_speed(speed)
    plant = linear_system(vehicle, speed)
    rows = output_rows(vehicle, outputs)
    columns = _alignment_columns(vehicle)
    blocks = [pade_delay(float(tau), pade_order) for tau in irregularity_delays(vehicle, speed)]
    sizes = [block[0].shape[0] for block in blocks]
    k = sum(sizes)
    a_d = np.zeros((k, k))
    b_d = np.zeros((k, 1))
    c_d = np.zeros((len(blocks), k))
    d_d = np.zeros((len(blocks), 1))
    states = []
    start = 0
    for j, ((a, b, c, d), size) in enumerate(zip(blocks, sizes, strict=True)):
        a_d[start:start + size, start:start + size] = a
        b_d[start:start + size] = b
        c_d[j, start:start + size] = c
        d_d[j] = d
        states += [f"delay{j + 1}_{i + 1}" for i in range(size)]
        start += size
    b_plant = plant.B[:, columns]
    # y = R z + (R D + E) u: the alignment acts through the contact, never on an
    # element's end, so no output reads its rate (rows.rates[:, columns] is zero)
    feed = (rows.state @ plant.D + rows.inputs)[:, columns]
    n = plant.A.shape[0]
    a_all = np.block([[a_d, np.zeros((k, n))], [b_plant @ c_d, plant.A]])
    b_all = np.vstack([b_d, b_plant @ d_d])
    c_all = np.hstack([feed @ c_d, rows.state])
    d_all = feed @ d_d
    return LinearSystem(a_all, b_all, c_all, d_all, tuple(states) + plant.states, (ALIGNMENT,), rows.names,
                        float(speed))


def track_response(vehicle: VehicleModel, speed: float, frequencies: Sequence[float], *,
                   outputs: Sequence[str] | None = None) -> np.ndarray:
    """The exact response of the named outputs to a unit alignment ``e^{i w t}`` at the
    leading wheelset, each wheelset delayed by ``e^{-i w tau_n}``: shape (F, n_outputs),
    complex [output unit per m]."""
    from express.analysis.frequency.frequency import irregularity_delays

    speed = check_speed(speed)
    plant = linear_system(vehicle, speed)
    rows = output_rows(vehicle, outputs)
    columns = _alignment_columns(vehicle)
    delays = irregularity_delays(vehicle, speed)
    eye = np.eye(plant.A.shape[0])
    found = []
    for f in np.asarray(frequencies, dtype=float):
        w = 2 * np.pi * f
        drive = np.exp(-1j * w * delays)  # (n_wheelsets,)
        state = np.linalg.solve(1j * w * eye - plant.A, plant.B[:, columns] @ drive)
        found.append(rows.state @ (state + plant.D[:, columns] @ drive) + rows.inputs[:, columns] @ drive)
    return np.array(found)
