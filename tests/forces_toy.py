"""A toy force element written outside the package (a spring from one coordinate to the
ground), for tests/test_forces.py: run in a process of its own with its own Numba cache."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.extending import overload

from express.analysis.time.force_elements import run_forces
from express.analysis.time.integrator import march
from express.analysis.time.simulate import _dense_steps
from express.analysis.time.track_inputs import track_inputs
from express.forces.element import ForceElement, ForceSet
from express.forces.law import force_law
from express.numeric.statespace import load_vehicle
from express.rail.track import paper_curve

ROOT = Path(__file__).resolve().parents[1]
class GroundSpringLaw(NamedTuple):
    """A toy element: a linear spring from coordinate ``place`` to the ground."""

    first: int
    place: int
    stiffness: float


@njit
def _ground_spring(x, law, z):
    z[law.first] = -law.stiffness * x[law.place]


@overload(force_law)
def _ground_spring_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is GroundSpringLaw:
        return lambda x, k, law, z, record, commit: _ground_spring(x, law, z)
    return None


@dataclasses.dataclass
class GroundSpring(ForceElement):
    """The element: reads and acts on one coordinate."""

    vehicle: object
    place: int
    stiffness: float
    kind = "ground spring"

    @property
    def names(self):
        return ("ground spring",)

    @property
    def reads(self):
        return np.array([self.place])

    def directions(self):
        return self.vehicle.form.force[:, [self.place]]

    def law(self, first):
        return GroundSpringLaw(first, self.place, self.stiffness)

    def forces(self, x, k):
        return np.array([-self.stiffness * x[self.place]])

    def slopes(self, x, k, forces):
        row = np.zeros((1, x.size))
        row[0, self.place] = -self.stiffness
        return row


def gaps() -> tuple[float, float]:
    """The largest difference of the body's lateral displacement between the spring as a
    force element and the spring in A, relative to the largest displacement, at dt = 2 ms
    and 1 ms."""
    vehicle = load_vehicle(ROOT / "examples" / "conventional.toml")
    track = paper_curve()
    speed = 60 / 3.6
    body = vehicle.dof_index("CB.y")
    stiffness = 2e5

    def gap(dt: float) -> float:
        distance = np.arange(0.0, 150.0 + 1e-9, speed * dt)
        inputs = track_inputs(vehicle, track, distance, speed)
        base = run_forces(vehicle, inputs, speed, tables=None, flange=False, saturation=False, clearances=False).forces
        forces = ForceSet((*base.elements, GroundSpring(vehicle, body, stiffness)), vehicle.form.size)
        a = vehicle.state_matrix(speed)
        linear = _dense_steps(vehicle, a, speed, dt, inputs, forces.selector())
        states, _ = march(linear, np.zeros(a.shape[0]), forces)
        stiff_a = a - stiffness * np.outer(vehicle.form.force[:, body], np.eye(a.shape[0])[body])
        exact = _dense_steps(vehicle, stiff_a, speed, dt, inputs, base.selector())
        reference, _ = march(exact, np.zeros(a.shape[0]), base)
        return float(np.max(np.abs(states[:, body] - reference[:, body])) / np.max(np.abs(reference[:, body])))

    return gap(0.002), gap(0.001)
