"""EN 14363's bogie-frame criterion of instability: the lateral acceleration of the bogie
frame over each wheelset, band-pass filtered around its own frequency, as a sliding rms.

The simplified measuring method of EN 14363 (and UIC 515 / 518) judges stability from
the lateral acceleration ``ÿ+`` of the bogie frame above each wheelset: filtered
``f0 ± 2 Hz`` around the frequency of its largest peak and taken as a sliding rms over
100 m of track (the same processing as the ``ΣY`` criterion,
:func:`express.analysis.curving.instability.instability_rms`), against

    ÿ+_lim,rms = (12 - m+ / 5) / 2   [m/s^2],   m+ the bogie's mass [t]

as the limit is commonly cited (the standard is not public to us and was not read here;
``docs/curving.md`` says so).  For an 8 t bogie: 5.2 m/s^2.

A **bogie frame** here is a body, not a wheelset, tied by elements directly to two or more
wheelsets (the primary suspension); ``m+`` is its mass plus those wheelsets'.  Over the
wheelset at station ``x_w`` the frame's lateral motion is ``y + (x_w - x_f) psi`` (its
lateral and yaw coordinates, ``x_f`` its station), whose acceleration is taken from the
run's velocities by central differences (:func:`numpy.gradient` in time).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from express.analysis.curving.instability import HALF_WIDTH, WINDOW, instability_rms
from express.model.parameters import expression_value

__all__ = ["BogieFrame", "bogie_frame_criteria", "bogie_frame_limit", "bogie_frames", "frame_accelerations"]


@dataclass(frozen=True)
class BogieFrame:
    """A bogie frame of a model (module docstring).

    Attributes
    ----------
    body : str
        Its body.
    mass : float
        ``m+`` [kg]: the frame's mass and its wheelsets'.
    wheelsets : tuple of str
        The wheelsets it carries, in the model's order.
    offsets : tuple of float
        Each wheelset's station less the frame's [m].
    """

    body: str
    mass: float
    wheelsets: tuple[str, ...]
    offsets: tuple[float, ...]


def bogie_frame_limit(mass: float) -> float:
    """``(12 - m+/5) / 2`` [m/s^2] for a bogie of ``mass`` [kg] (module docstring).

    >>> bogie_frame_limit(8000.0)
    5.2
    """
    return 0.5 * (12.0 - mass / 1000.0 / 5.0)


def bogie_frames(vehicle: Any) -> tuple[BogieFrame, ...]:
    """The bogie frames of ``vehicle`` (a body tied by elements to two or more wheelsets
    that has lateral and yaw coordinates); empty without rail data."""
    model = vehicle.model
    if model is None or not vehicle.wheelsets:
        return ()
    wheelsets = {w.name: w for w in vehicle.wheelsets}
    host = {p.id: p.host for p in model.points}
    tied: dict[str, list[str]] = {}
    for element in model.elements:
        ends = {host[end] for end in (element.s_end, element.t_end) if end in host}
        for body in ends - set(wheelsets):
            for wheelset in sorted(ends & set(wheelsets)):
                if wheelset not in tied.setdefault(body, []):
                    tied[body].append(wheelset)
    values = model.values()
    bodies = {b.id: b for b in model.bodies}
    frames = []
    for body, carried in tied.items():
        frame = bodies.get(body)
        if frame is None or len(carried) < 2 or f"{body}.y" not in vehicle.dofs or f"{body}.rz" not in vehicle.dofs:
            continue
        order = [w.name for w in vehicle.wheelsets if w.name in carried]
        station = float(expression_value(frame.position[0], values))
        mass = float(expression_value(frame.mass, values)) + sum(
            float(expression_value(bodies[w].mass, values)) for w in order if w in bodies)
        frames.append(BogieFrame(body, mass, tuple(order), tuple(wheelsets[w].station - station for w in order)))
    return tuple(frames)


def frame_accelerations(vehicle: Any, result: Any, frame: BogieFrame) -> np.ndarray:
    """The frame's lateral acceleration over each of its wheelsets [m/s^2], shape (N, k)."""
    y, psi = vehicle.dofs.index(f"{frame.body}.y"), vehicle.dofs.index(f"{frame.body}.rz")
    velocity = result.q_dot[:, [y]] + result.q_dot[:, [psi]] * np.asarray(frame.offsets)[None, :]
    return np.gradient(velocity, result.time, axis=0)


def bogie_frame_criteria(vehicle: Any, result: Any) -> list[tuple[str, str, float, float]]:
    """``(name, quantity, value, limit)`` of every bogie frame over every wheelset of a
    run at least 100 m long: the filtered sliding rms of ``ÿ+`` against its limit."""
    found = []
    for frame in bogie_frames(vehicle):
        accelerations = frame_accelerations(vehicle, result, frame)
        for k, wheelset in enumerate(frame.wheelsets):
            rms = instability_rms(result.distance, float(result.speed), accelerations[:, k])
            if rms is None:
                continue
            found.append((f"ay_{frame.body}_{wheelset}_rms",
                          f"bogie frame {frame.body} lateral acceleration over {wheelset}, rms over {WINDOW:g} m "
                          f"({rms.frequency:.2f} ± {HALF_WIDTH:g} Hz), against (12 - m+/5)/2 "
                          f"(m+ {frame.mass / 1000:.2f} t; instability)",
                          rms.largest, bogie_frame_limit(frame.mass)))
    return found
