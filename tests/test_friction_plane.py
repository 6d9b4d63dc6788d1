"""Friction in a plane (issue 31, item 1): two friction elements, along x and y between
the same points, paired by ``friction = { limit = ..., plane = "<other>" }``: their
sliders stick while the trial force ``k (d - s)`` lies within the circle of the limit and
are returned onto it along the trial force otherwise (exact, no smoothing).  Checked: a
surface driven on a circle carries a friction force of constant magnitude along its
sliding velocity, dissipating ``2 pi A L`` a turn; in pure x motion the pair is the 1-D
element bit for bit (law and march); a plate driven on a circle through springs; the
reading errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.analysis.time.integrator import march
from express.analysis.time.simulate import _dense_steps
from express.analysis.time.track_inputs import TrackInputs
from express.base.diagnostics import ModelError
from express.forces.element import ForceSet
from express.forces.friction import friction_elements_of, plane_mapping, return_mapping
from express.io import parse_toml_model
from express.numeric.statespace import vehicle_model

MODEL = """
[model]
name = "plate"
[parameters]
m = "100 kg"
k = "40 kN/m"
ks = "40 MN/m"
F = "200 N"
[bodies.M]
mass = "m"
dofs = ["x", "y"]
[grounds.G]
[grounds.W]
[points.M1]
body = "M"
offset = [0, 0, 0]
[points.G1]
body = "G"
offset = [0, 0, 0]
[points.W1]
body = "W"
offset = [0, 0, 0]
[elements.kx]
from = "M1"
to = "G1"
direction = "x"
stiffness = "k"
[elements.ky]
from = "M1"
to = "G1"
direction = "y"
stiffness = "k"
[elements.sx]
from = "M1"
to = "W1"
direction = "x"
stiffness = "ks"
friction = { limit = "F", plane = "sy" }
[elements.sy]
from = "M1"
to = "W1"
direction = "y"
stiffness = "ks"
friction = "F"
"""
KS, L = 4e7, 200.0


def test_a_surface_driven_on_a_circle_carries_a_constant_force_along_its_velocity():
    """Deflections on a circle of radius A = 5 mm, 20 000 points a turn: after the first
    quarter |F| = L (1e-12; achieved ~1e-16), F along the deflection's velocity within the
    slider's lag (L/k)/A = 1e-3 rad and half a step's turn (achieved 1.157e-3 = 1e-3 +
    1.57e-4: the chord of a step), and the work of a turn 2 pi A L to 1e-6
    (achieved 6.9e-7: the lag's cosine and the trapezoidal sum)."""
    amplitude = 5e-3
    phase = np.linspace(0, 4 * math.pi, 40_001)
    dx, dy = amplitude * np.cos(phase), amplitude * np.sin(phase)
    sx = sy = 0.0
    forces = []
    for x, y in zip(dx, dy, strict=True):
        sx, sy = plane_mapping(x, y, sx, sy, KS, L)
        forces.append((KS * (x - sx), KS * (y - sy)))
    f = np.array(forces)
    late = phase > math.pi / 2
    np.testing.assert_allclose(np.hypot(f[late, 0], f[late, 1]), L, rtol=1e-12)
    velocity = np.column_stack([-np.sin(phase), np.cos(phase)])
    angle = np.arccos(np.clip(np.sum(f * velocity, axis=1) / L, -1, 1))
    step = phase[1] - phase[0]
    assert np.max(angle[late]) < L / (KS * amplitude) + step / 2 + 1e-6
    turn = phase >= 2 * math.pi
    work = float(np.sum(0.5 * (f[turn][1:] + f[turn][:-1]) * np.diff(np.column_stack([dx, dy])[turn], axis=0)))
    exact = 2 * math.pi * amplitude * L
    assert abs(work / exact - 1) < 1e-6


def test_in_pure_x_motion_the_pair_is_the_one_dimensional_element():
    """y held at zero: the pair's x slider is the 1-D return mapping's, bit for bit."""
    delta = 1e-4 * np.sin(np.linspace(0, 6 * math.pi, 3001))
    s1 = sx = sy = 0.0
    for d in delta:
        s1 = return_mapping(d, s1, KS, L)
        sx, sy = plane_mapping(d, 0.0, sx, sy, KS, L)
        assert sx == s1 and sy == 0.0


def _run(text: str, u: np.ndarray, dt: float):
    vehicle = vehicle_model(parse_toml_model(text, "plate.toml"))
    empty = np.zeros((u.shape[0], 0))
    inputs = TrackInputs(u, np.gradient(u, dt, axis=0), empty, empty, empty)
    element = friction_elements_of(vehicle, u)
    forces = ForceSet((element,), vehicle.form.size)
    linear = _dense_steps(vehicle, vehicle.state_matrix(1.0), 1.0, dt, inputs, forces.selector())
    states, _ = march(linear, np.zeros(vehicle.form.size), forces)
    return states, element, vehicle


def test_the_march_of_the_pair_in_pure_x_is_the_one_dimensional_run_and_on_a_circle_at_the_limit():
    """Base motion through the springs (inputs G.x, G.y): along x only the plate's x is the
    run with two independent 1-D elements to 1e-15 m (the same arithmetic); on a circle
    (G at 20 mm, 1.5 w_n) the resultant friction force never exceeds L and sits on it
    whenever the sliders move (1e-9), where two 1-D elements would reach sqrt(2) L."""
    dt = 1e-4
    t = np.arange(0, 2.0, dt)
    omega = 1.5 * math.sqrt(40e3 / 100)
    u = np.zeros((t.size, 4))  # G.x, G.y, W.x, W.y
    u[:, 0] = 0.02 * np.cos(omega * t)
    pair, _, vehicle = _run(MODEL, u, dt)
    assert vehicle.equations.inputs[:2] == ("G.x", "G.y")
    apart = MODEL.replace('friction = { limit = "F", plane = "sy" }', 'friction = "F"')
    alone, _, _ = _run(apart, u, dt)
    np.testing.assert_allclose(pair[:, 0], alone[:, 0], atol=1e-15, rtol=0)
    u[:, 1] = 0.02 * np.sin(omega * t)
    states, element, _ = _run(MODEL, u, dt)
    sliders, force = element.history_of(states)
    size = np.hypot(force[:, 0], force[:, 1])
    assert np.max(size) <= L * (1 + 1e-9)
    moved = np.hypot(*np.diff(sliders, axis=0).T) > 0
    np.testing.assert_allclose(size[1:][moved], L, rtol=1e-9)
    _, separate_element, _ = _run(apart, u, dt)
    separate = np.hypot(*separate_element.history_of(_run(apart, u, dt)[0])[1].T)
    assert np.max(separate) > 1.3 * L


@pytest.mark.parametrize("old, new, message", [
    ('plane = "sy"', 'plane = "sz"', 'friction "plane" names no element: "sz"'),
    ('plane = "sy"', 'plane = "ky"', 'is not a friction element'),
    ('plane = "sy"', 'plane = "sx"', 'is itself'),
    ('stiffness = "ks"\nfriction = "F"', 'stiffness = "2*ks"\nfriction = "F"', "of another pre-slip stiffness"),
    ('limit = "F", plane', 'limit = "F", mu = 0.3, plane', 'either "limit" or "mu" and "of"'),
])
def test_bad_pairs_are_refused_with_the_line(old, new, message):
    assert old in MODEL
    with pytest.raises(ModelError) as error:
        parse_toml_model(MODEL.replace(old, new), "plate.toml")
    problems = [str(p) for p in error.value.problems]
    assert any(p.startswith("plate.toml:") and message in p for p in problems), problems


def test_a_pair_and_a_load_reference_are_written_back_and_read_the_same():
    """`express convert`'s writer: the plane pair and a limit that follows a load (with a
    rotational radius) round-trip to the same friction elements."""
    from express.io.toml_writer import model_to_toml

    text = MODEL.replace('friction = "F"', 'friction = { mu = "0.3", of = "ky" }')
    model = parse_toml_model(text, "plate.toml")
    again = parse_toml_model(model_to_toml(model), "again.toml")
    for element in ("sx", "sy"):
        first = next(e for e in model.elements if e.id == element)
        second = next(e for e in again.elements if e.id == element)
        assert (second.friction_plane, second.friction_of, second.kind) == (first.friction_plane, first.friction_of,
                                                                            first.kind)
        assert float(second.friction.subs({"F": 200})) == pytest.approx(float(first.friction.subs({"F": 200})))
