"""The elements' forces as outputs of the linear model (express.export.element_forces):
closed forms of a mass on a Kelvin-Voigt and on a Maxwell element to a moving ground, the
energy identities ``sum F^2 / k = q^T K q`` and ``sum F^2 / c = q'^T C q'`` on the
bundled vehicles (line, series, rotational, friction and characteristic elements, pins),
the track-driven plant against the exact delayed response, and the refusals."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from express.base.diagnostics import ArgumentError
from express.export.element_forces import element_force_rows
from express.export.linear_system import to_control
from express.export.track_system import track_response, track_system
from express.io import load_model, parse_toml_model
from express.numeric.statespace import load_vehicle, vehicle_model

ONE_MASS = """
[parameters]
m = 100.0
k = "10 kN/m"
c = "{c}"

[bodies.B]
mass = "m"
inertia = [1, 1, 1]
dofs = ["y"]

[grounds.G]

[points.P]
body = "B"

[points.Q]
body = "G"

[elements.E]
from = "P"
to = "Q"
direction = "y"
stiffness = "k"
damping = "c"
{kind}
"""

M, K = 100.0, 1.0e4


def _frequency_response(plant, w: float) -> np.ndarray:
    """``C (iw - A)^-1 B + D`` of a python-control state space, shape (outputs, inputs)."""
    a, b, c, d = (np.asarray(x) for x in (plant.A, plant.B, plant.C, plant.D))
    return c @ np.linalg.solve(1j * w * np.eye(a.shape[0]) - a, b) + d


@pytest.mark.parametrize("kind, c", [("", 300.0), ("", 0.0), ("series = true", 300.0), ("series = true", 0.0)])
def test_a_mass_on_an_element_to_a_moving_ground_has_the_closed_form_force(kind, c):
    """``F / u = Z m w^2 / (Z - m w^2)``, ``Z = k + i w c`` (Kelvin-Voigt) or
    ``k i w c / (k + i w c)`` (Maxwell), ``F = k delta + c delta'`` with ``delta = y - u``;
    the damper's ``u'`` enters as the input ``G.y_dot``; a Maxwell element without damping
    passes no force (to 1e-12 relative; achieved 1e-15)."""
    vehicle = vehicle_model(parse_toml_model(ONE_MASS.format(c=c, kind=kind), "one.toml"))
    plant = to_control(vehicle, 1.0, outputs=["force_E", "B.y"])
    rates = c != 0 and not kind
    assert plant.input_labels == (["G_y", "G_y_dot"] if rates else ["G_y"])
    for w in (3.0, 7.0, 40.0):  # off the resonance at 10 rad/s
        z = K + 1j * w * c if not kind else K * 1j * w * c / (K + 1j * w * c)
        h = _frequency_response(plant, w)
        force = h[0, 0] + (1j * w * h[0, 1] if rates else 0)
        assert force == pytest.approx(z * M * w**2 / (z - M * w**2), rel=1e-12)
        assert h[1, 0] + (1j * w * h[1, 1] if rates else 0) == pytest.approx(z / (z - M * w**2), rel=1e-12)


def _without_gravity(name: str):
    """The vehicle without rail terms, and its ``K`` without gravity's geometric stiffness.
    The Y25's friction limits follow the static loads, whose sense needs ``[gravity]``:
    there the side bearers' preload (its geometric stiffness) is set to zero and ``K`` is linear in ``g`` near it (the coils' tangents at the static state stay
    on their segments), so ``K(0) = K(g) - (K(g) - K(0.99 g)) / 0.01``."""
    model = load_model(f"examples/{name}.toml")
    if name != "y25-wagon":
        vehicle = vehicle_model(dataclasses.replace(model, gravity=None), with_rail=False)
        return vehicle, vehicle.stiffness
    vehicle = vehicle_model(model, with_rail=False).with_values({"Psb": 0.0})  # no side bearers' preload
    lighter = vehicle.with_values({"g": 0.99 * vehicle.values["g"]})
    return vehicle, vehicle.stiffness - (vehicle.stiffness - lighter.stiffness) / 0.01


@pytest.mark.parametrize("name", ["coach-blowoff", "forced-steering", "y25-wagon", "manchester"])
def test_the_forces_hold_the_energy_of_k_and_c(name):
    """Without rail terms and gravity ``K`` and ``C`` are the elements' sums, so for any
    state ``sum F^2 / k = q^T K q`` (positions only) and ``sum F^2 / c = q'^T C q'``
    (velocities only, the parallel dampers; a series element carries no force at rest)
    (to 1e-10 relative; achieved about 1e-15).  Line, series, rotational, friction and
    characteristic elements and eliminated pins are among them."""
    vehicle, stiffness = _without_gravity(name)
    model = vehicle.model
    ids = [e.id for e in model.elements if not e.clearance and e.id not in _pin_elements(model)]
    rows = element_force_rows(vehicle, [f"force_{i}" for i in ids])
    values = {e.id: e for e in model.elements}
    k = np.array([_number(values[i].stiffness, vehicle) for i in ids])
    c = np.array([_number(values[i].damping, vehicle) for i in ids])
    generator = np.random.default_rng(7)
    n, size = vehicle.n, vehicle.form.size
    positions = np.concatenate([generator.normal(size=n) * 1e-3, np.zeros(size - n)])
    forces = rows.state @ positions
    springs = k != 0
    energy = positions[:n] @ stiffness @ positions[:n]
    assert np.all(forces[~springs] == 0)
    assert np.sum(forces[springs] ** 2 / k[springs]) == pytest.approx(energy, rel=1e-10)
    velocities = np.concatenate([np.zeros(n), generator.normal(size=size - n) * 1e-2])
    forces = rows.state @ velocities
    rate = vehicle.form.velocity @ velocities
    parallel = (c != 0) & np.array([not values[i].series for i in ids])
    assert np.sum(forces[parallel] ** 2 / c[parallel]) == pytest.approx(rate @ vehicle.damping(30.0) @ rate, rel=1e-10)


def _pin_elements(model) -> set[str]:
    from express.assembly.pins import pin_elements

    return {element.id for _, element in pin_elements(model)}


def _number(expression, vehicle) -> float:
    from express.base.expressions import expression_value

    return expression_value(expression, vehicle.values)


def test_a_force_output_of_the_track_plant_converges_to_the_exact_response():
    """A primary lateral and a secondary lateral spring-damper of the Manchester car
    driven by the alignment, the wheelsets' delays Padé approximants of order 10: within
    5e-9 of the exact delayed response (:func:`track_response`) up to 2 Hz (achieved
    5.9e-10).  Their dampers read the curvature's rate, never the alignment's (which acts
    through the contact)."""
    car = load_vehicle("examples/manchester.toml")
    outputs = ["force_T1_FL_py", "force_T1_syL"]
    frequencies = np.array([0.2, 0.5, 1.0, 2.0])
    exact = track_response(car, 40.0, frequencies, outputs=outputs)
    system = track_system(car, 40.0, outputs=outputs, pade_order=10)
    assert system.inputs == ("alignment",) and system.outputs == tuple(outputs)
    eye = np.eye(system.A.shape[0])
    pade = np.array([system.C @ np.linalg.solve(2j * np.pi * f * eye - system.A, system.B)[:, 0] + system.D[:, 0]
                     for f in frequencies])
    assert np.abs(pade - exact).max() < 5e-9 * np.abs(exact).max()
    rows = element_force_rows(car, outputs)
    alignment = [car.inputs.index(name) for name in car.layout.irregularity]
    assert np.any(rows.rates) and not np.any(rows.rates[:, alignment])  # the curvature's rate only


def test_what_is_no_force_of_the_state_is_refused_at_once():
    stop = "stop"
    text = ONE_MASS.format(c=0, kind="") + '[elements.stop]\nfrom = "P"\nto = "Q"\ndirection = "y"\nstiffness = "1e6"\ngap = "0.02"\n'
    vehicle = vehicle_model(parse_toml_model(text, "stop.toml"))
    with pytest.raises(ArgumentError) as error:
        element_force_rows(vehicle, ["force_nothing", f"force_{stop}"])
    assert "'force_nothing': no such element" in str(error.value)
    assert f"'force_{stop}': a clearance element (bump stop) is left out of the linear model" in str(error.value)
    pinned = load_vehicle("examples/forced-steering.toml")
    pin = sorted(_pin_elements(pinned.model))[0]
    with pytest.raises(ArgumentError, match="the element of a pinned joint carries a reaction"):
        to_control(pinned, 30.0, outputs=[f"force_{pin}"])
