"""Friction limits proportional to another element's load (issue 31, item 1): a mass on
two vertical springs under gravity, with a friction element along x whose limit is
``mu N``, ``N`` the load in the spring ``W`` (its static share ``m g k1/(k1 + k2)`` and
its dynamic force ``-k1 z``).  Checked against closed forms: the quasi-static stick–slip
threshold ``mu N`` and its lift-off, the friction force at every slipping step equal to
``mu N(t)`` of that step while the load varies, Coulomb's free decay (4 F/k per cycle)
with ``F = mu N``; and the reading errors (exit 2, the file and line)."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from express.analysis.time.integrator import march
from express.analysis.time.simulate import _dense_steps
from express.analysis.time.track_inputs import TrackInputs
from express.base.diagnostics import ModelError
from express.forces.element import ForceSet
from express.forces.friction import friction_elements_of
from express.io import parse_toml_model
from express.numeric.statespace import vehicle_model

MODEL = """
[model]
name = "loaded_slider"
[parameters]
m = "100 kg"
g = "9.81 m/s^2"
k = "40 kN/m"
k1 = "300 kN/m"
k2 = "100 kN/m"
ks = "40 MN/m"
mu = "0.3"
[gravity]
acceleration = "g"
[bodies.M]
mass = "m"
dofs = ["x", "z"]
[grounds.G]
[grounds.W]
[grounds.H]
[points.M1]
body = "M"
offset = [0, 0, 0]
[points.G1]
body = "G"
offset = [0, 0, 0]
[points.W1]
body = "W"
offset = [0, 0, 0]
[points.H1]
body = "H"
offset = [0, 0, 0]
[elements.spring]
from = "M1"
to = "G1"
direction = "x"
stiffness = "k"
[elements.W]
from = "M1"
to = "G1"
direction = "z"
stiffness = "k1"
[elements.W2]
from = "M1"
to = "H1"
direction = "z"
stiffness = "k2"
[elements.slider]
from = "M1"
to = "W1"
direction = "x"
stiffness = "ks"
friction = { mu = "mu", of = "W" }
"""
M, G, K, K1, K2, MU = 100.0, 9.81, 40e3, 300e3, 100e3, 0.3
N0 = M * G * K1 / (K1 + K2)  # the static share of the weight in W [N]
OMEGA_N = math.sqrt(K / M)


def _vehicle():
    return vehicle_model(parse_toml_model(MODEL, "loaded.toml"))


def _run(vehicle, u: np.ndarray, dt: float, x0) -> tuple[np.ndarray, object]:
    """March the inputs ``u`` (G.x, G.z, W.x, H.z) from ``x0`` (x, z, x', z')."""
    empty = np.zeros((u.shape[0], 0))
    inputs = TrackInputs(u, np.gradient(u, dt, axis=0), empty, empty, empty)
    element = friction_elements_of(vehicle, u)
    forces = ForceSet((element,), vehicle.form.size)
    linear = _dense_steps(vehicle, vehicle.state_matrix(1.0), 1.0, dt, inputs, forces.selector())
    states, _ = march(linear, np.asarray(x0, float), forces)
    return states, element


def test_the_load_is_recorded_with_its_static_share_and_is_stuck_in_the_linear_matrices():
    """The term holds mu, the static load of W from the gravity solve (exact: -m g k1/(k1 +
    k2), compression negative) and W's deflection; K has the stuck pre-slip spring."""
    vehicle = _vehicle()
    (term,) = vehicle.equations.element_terms
    assert str(term.values["friction"]) == "mu" and str(term.values["load_static"]) == "-g*k1*m/(k1 + k2)"
    assert term.values["load_g:M.z"] == 1 and term.values["load_h:G.z"] == -1
    assert vehicle.stiffness[0, 0] == K + 40e6
    element = friction_elements_of(vehicle, np.zeros((3, 4)))
    np.testing.assert_allclose(element.limits_at(np.zeros(4), 0), MU * N0, rtol=1e-14)


@pytest.mark.parametrize("lift", [0.0, 0.004, 0.02])
def test_the_stick_slip_threshold_is_mu_times_the_load_and_lift_off_frees_it(lift):
    """Ground H raised by ``lift`` (the mass held at its new equilibrium z = k2 lift/(k1 +
    k2)): W carries N = k1 (m g - k2 lift)/(k1 + k2); pulling the mass along x slowly, the
    friction force stays at mu N once it slips (to 1e-9 of it; achieved ~1e-13), and where
    N < 0 (lift = 20 mm: lift-off) the limit is zero and the mass follows the spring as
    without friction, x = v (t - sin(w t)/w) (to 3e-7 m of its 1 mm swing; achieved 1.4e-7,
    the slipping pre-slip spring fed back explicitly: 5e-5 at 10 times the step)."""
    vehicle = _vehicle()
    dt = 2e-5  # w dt = 0.013 of the pre-slip spring, fed back explicitly while it slips
    t = np.arange(0, 1.0, dt)
    u = np.zeros((t.size, 4))
    u[:, 0] = 0.02 * t  # G.x pulled at 20 mm/s
    u[:, 3] = lift
    z = K2 * lift / (K1 + K2)
    normal = K1 * (M * G - K2 * lift) / (K1 + K2)
    states, element = _run(vehicle, u, dt, [0.0, z, 0.0, 0.0])
    outputs = element.outputs(states, np.zeros(0))
    friction, limit = outputs["friction_slider"], outputs["limit_slider"]
    np.testing.assert_allclose(limit, MU * max(normal, 0.0), rtol=1e-12, atol=1e-9)
    if normal > 0:
        late = t > 0.9
        np.testing.assert_allclose(friction[late], MU * normal, rtol=1e-9)
        assert np.max(np.abs(friction)) <= MU * normal * (1 + 1e-12)
    else:
        assert np.max(np.abs(friction)) < 1e-9
        free = 0.02 * (t - np.sin(OMEGA_N * t) / OMEGA_N)  # no friction: the ramp's closed form
        np.testing.assert_allclose(states[:, 0], free, atol=3e-7)


def test_while_the_load_varies_every_slipping_step_carries_mu_n_of_that_step():
    """The mass bouncing vertically (z0 = 1.5 mm, N(t) = N0 - k1 z(t) between 0.28 and
    1.18 of N0 once it lifts half off) while pulled along x: at every step the friction
    force is within the limit mu max(0, N(t)) of that step, and equal to it wherever the
    slider moved (to 1e-9 of mu N0; achieved 1e-12) — the limit is evaluated from the
    load's current force at every step."""
    vehicle = _vehicle()
    dt = 5e-5
    t = np.arange(0, 0.5, dt)
    u = np.zeros((t.size, 4))
    u[:, 0] = 0.1 * t
    states, element = _run(vehicle, u, dt, [0.0, 0.0025, 0.0, 0.0])
    sliders, friction = element.history_of(states)
    normal = N0 - K1 * states[:, 1]
    limit = MU * np.maximum(normal, 0.0)
    assert normal.min() < 0 < normal.max()  # the load varies through lift-off
    assert np.all(np.abs(friction[:, 0]) <= limit + 1e-9 * MU * N0)
    moved = np.abs(np.diff(sliders[:, 0])) > 0
    np.testing.assert_allclose(np.abs(friction[1:, 0][moved]), limit[1:][moved], atol=1e-9 * MU * N0)


def test_free_decay_falls_4F_over_k_per_cycle_with_F_from_the_load():
    """From x0 = 20 F/k at rest, F = mu N0: the amplitude falls by 4 F/k per cycle
    (Coulomb), to 5e-4 of 4 F/k (achieved 1.5e-4 at dt = T/16000, as with a constant limit
    in tests/test_forces_friction.py: the same element, its limit now from W's load)."""
    vehicle = _vehicle()
    friction = MU * N0
    period = 2 * math.pi / OMEGA_N
    dt = period / 16000
    t = np.arange(0, 5 * period, dt)
    x0 = 20 * friction / K
    states, _ = _run(vehicle, np.zeros((t.size, 4)), dt, [x0, 0.0, 0.0, 0.0])
    x = states[:, 0]
    peaks = [x[(t > (c - 0.25) * period) & (t < (c + 0.25) * period)].max() for c in range(1, 5)]
    np.testing.assert_allclose(-np.diff([x0, *peaks]), 4 * friction / K, rtol=5e-4)


@pytest.mark.parametrize("old, new, message", [
    ('of = "W" }', 'of = "Wx" }', 'friction "of" names no element: "Wx"; did you mean W?'),
    ('of = "W" }', 'of = "slider" }', 'is a friction element'),
    ('mu = "0.3"', 'mu = "-0.3"', "a friction element needs a positive friction coefficient mu"),
    ('mu = "0.3"', 'mu = "0.3 N"', "used as"),
    ('{ mu = "mu", of = "W" }', '{ mu = "mu", of = "W", normal = 3 }', 'unknown key "normal"'),
    ('{ mu = "mu", of = "W" }', '{ of = "W" }', 'needs "mu"'),
])
def test_bad_load_references_are_refused_with_the_line(old, new, message):
    text = MODEL
    assert old in text
    with pytest.raises(ModelError) as error:
        parse_toml_model(text.replace(old, new), "loaded.toml")
    problems = [str(p) for p in error.value.problems]
    assert any(p.startswith("loaded.toml:") and message in p for p in problems), problems


def test_a_damper_or_an_unloaded_element_cannot_carry_the_load(tmp_path):
    """A damper (no stiffness) named as the load, and a spring that carries no static load
    (no [gravity], no preload: the load's sense unknown): exit 2 on the command line with
    the file and line, no traceback."""
    damper = MODEL.replace('of = "W" }', 'of = "D" }') + '[elements.D]\nfrom = "M1"\nto = "G1"\ndirection = "z"\ndamping = "k"\n'
    unloaded = MODEL.replace("[gravity]\nacceleration = \"g\"\n", "")
    for name, text, message in (("damper.toml", damper, "is an element without stiffness"),
                                ("unloaded.toml", unloaded, "carries no static load")):
        path = tmp_path / name
        path.write_text(text)
        run = subprocess.run([sys.executable, "-m", "express", "eigen", str(path), "--json"],
                             capture_output=True, text=True, timeout=300)
        assert run.returncode == 2, run.stderr
        assert f"{name}:" in run.stderr and message in run.stderr and "Traceback" not in run.stderr
        assert not run.stdout
