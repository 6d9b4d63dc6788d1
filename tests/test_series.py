"""Series spring-damper (Maxwell) elements: the damper stroke as a first-order coordinate.

The element's spring deflects by ``delta - s`` and its damper by ``s`` (the stroke, a
massless coordinate ``<element>.stroke``): energy ``k/2 (delta - s)^2``, dissipation
``c/2 s'^2``.  Checks: the closed form of the issue (mass, parallel spring, series
element: ``m c s^3 + m k s^2 + (k0 + k) c s + k0 k``), the limits (a stiff bush is the
plain damper, a stiff damper the plain spring), the state-space form against a direct
solution of the descriptor system, critical speed and simulation of a car whose yaw
dampers have bush stiffness.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

from express.assembly.first_order import state_form
from express.assembly.generator import generate
from express.base.diagnostics import ModelError
from express.io import load_model, parse_toml_model
from express.model.records import Element, ElementKind, Parameter
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]

m, k0, k, c = sp.symbols("m k0 k c")

MAXWELL = """
[parameters]
m = 1000.0
k0 = "100 kN/m"
k = "400 kN/m"
c = "20 kN*s/m"

[bodies.B]
mass = "m"
dofs = ["x"]

[grounds.G]

[points.P]
body = "B"

[points.Q]
body = "G"

[elements.spring]
from = "P"
to = "Q"
direction = "x"
stiffness = "k0"

[elements.maxwell]
from = "P"
to = "Q"
direction = "x"
stiffness = "k"
damping = "c"
series = true
"""


def assert_same_values(actual, expected, rtol):
    """The same multiset of complex numbers (each matched to its nearest)."""
    actual, expected = list(np.asarray(actual)), list(np.asarray(expected))
    assert len(actual) == len(expected), (actual, expected)
    scale = max(abs(x) for x in expected)
    for value in expected:
        nearest = min(range(len(actual)), key=lambda i: abs(actual[i] - value))
        assert abs(actual[nearest] - value) <= rtol * scale, (value, actual)
        actual.pop(nearest)


def test_maxwell_matrices_are_the_energy_forms():
    eom = generate(parse_toml_model(MAXWELL, "maxwell.toml")).equations
    assert eom.dofs == ("B.x", "maxwell.stroke")
    assert sp.Matrix([[m, 0], [0, 0]]) == eom.M
    assert sp.Matrix([[0, 0], [0, c]]) == eom.C
    assert sp.Matrix([[k0 + k, -k], [-k, k]]) == eom.K
    # ground motion u = G.x: the spring k0 and the series spring pull on B through u
    assert eom.inputs == ("G.x",)
    assert eom.matrices["P"] == sp.Matrix([[k0 + k], [-k]])
    assert eom.matrices["Pd"] == sp.Matrix([[0], [0]])
    s = sp.symbols("s")
    determinant = sp.expand((eom.M * s**2 + eom.C * s + eom.K).det())
    assert sp.expand(determinant - (m * c * s**3 + m * k * s**2 + (k0 + k) * c * s + k0 * k)) == 0


def test_maxwell_eigenvalues_are_the_roots_of_the_closed_form():
    model = parse_toml_model(MAXWELL, "maxwell.toml")
    vehicle = vehicle_model(model)
    values = {"m": 1000.0, "k0": 1e5, "k": 4e5, "c": 2e4}
    roots = np.roots([values["m"] * values["c"], values["m"] * values["k"],
                      (values["k0"] + values["k"]) * values["c"], values["k0"] * values["k"]])
    eigenvalues = vehicle.eigenvalues(1.0)
    assert eigenvalues.shape == (3,)  # x, x', stroke
    assert_same_values(eigenvalues, roots, rtol=1e-10)
    assert vehicle.state_matrix(1.0).shape == (3, 3)
    assert vehicle.form.first_order.tolist() == [1]


@pytest.mark.parametrize("bush, damper, expected", [
    (1e12, 1e4, "damper"),     # a rigid bush: the plain damper c
    (4e5, 1e12, "spring"),     # a rigid damper: the plain spring k
])
def test_limits_are_the_plain_elements(bush, damper, expected):
    mass, k_parallel = 1000.0, 1e5
    model = parse_toml_model(MAXWELL, "maxwell.toml")
    model = dataclasses.replace(model, parameters={
        **model.parameters, "k": Parameter("k", bush), "c": Parameter("c", damper)})
    eigenvalues = vehicle_model(model).eigenvalues(1.0)
    if expected == "damper":
        plain = np.roots([mass, damper, k_parallel])
    else:
        plain = np.roots([mass, 0.0, k_parallel + bush])
    if expected == "damper":  # the stroke mode is fast (-k/c): drop it
        kept = eigenvalues[np.argsort(np.abs(eigenvalues))][:2]
    else:  # the stroke mode is a slow creep (-k/c): keep the oscillation
        kept = eigenvalues[np.abs(eigenvalues.imag) > 0]
    assert_same_values(kept, plain, rtol=1e-5)


def test_state_form_solves_the_descriptor_system():
    """Random M (with massless coordinates), C, K: the state form reproduces every
    solution of ``M q'' + C q' + K q = P u + Pd u' + f``: its eigenvalues are the finite
    generalized eigenvalues of the pencil, and its response to a sinusoid is the
    direct solution of the frequency-domain equations."""
    rng = np.random.default_rng(3)
    n, first, inputs = 6, [1, 4], 2
    a = rng.normal(size=(n, n))
    mass = a @ a.T + n * np.eye(n)
    mass[first, :] = 0.0
    mass[:, first] = 0.0
    b = rng.normal(size=(n, n))
    damping = b @ b.T + np.eye(n)
    stiffness = rng.normal(size=(n, n))
    stiffness = stiffness @ stiffness.T
    forcing, rate = rng.normal(size=(n, inputs)), rng.normal(size=(n, inputs))
    zeros_c, zeros_p = np.zeros((n, n)), np.zeros((n, inputs))
    form = state_form(mass, damping, zeros_c, stiffness, forcing, zeros_p, rate)
    assert form.size == 2 * n - len(first)
    # eigenvalues: det(M s^2 + C s + K) has degree 2 (n - 2) + 2 = 2n - 2
    pencil_a = np.block([[np.zeros((n, n)), np.eye(n)], [-stiffness, -damping]])
    pencil_b = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), mass]])
    generalized = scipy.linalg.eigvals(pencil_a, pencil_b)
    finite = generalized[np.isfinite(generalized)]
    finite = finite[np.abs(finite) < 1e8]
    ours = np.linalg.eigvals(form.state_matrix(1.0))
    assert_same_values(ours, finite, rtol=1e-8)
    # frequency response: (jw I - A)^-1 (B + jw Bd) vs (-w^2 M + jw C + K)^-1 (P + jw Pd)
    for w in (0.3, 2.0, 15.0):
        s = 1j * w
        state = np.linalg.solve(s * np.eye(form.size) - form.state_matrix(1.0), form.input_matrix(1.0) + s * form.bd)
        direct = np.linalg.solve(mass * s**2 + damping * s + stiffness, forcing + s * rate)
        np.testing.assert_allclose(state[:n], direct, rtol=1e-9, atol=1e-12)
        # velocities of every coordinate
        velocity = form.velocity @ state + form.velocity_input + s * form.velocity_rate
        np.testing.assert_allclose(velocity, s * direct, rtol=1e-9, atol=1e-12)
        # a generalized force f enters through G
        force = np.linalg.solve(s * np.eye(form.size) - form.state_matrix(1.0), form.force)
        np.testing.assert_allclose(force[:n], np.linalg.inv(mass * s**2 + damping * s + stiffness), rtol=1e-9, atol=1e-12)


def test_without_first_order_coordinates_the_state_matrix_is_unchanged():
    vehicle = vehicle_model(load_model(ROOT / "examples" / "conventional.toml"))
    n = vehicle.n
    minv = np.linalg.inv(vehicle.mass)
    expected = np.zeros((2 * n, 2 * n))
    expected[:n, n:] = np.eye(n)
    expected[n:, :n] = -(minv @ vehicle.stiffness)
    expected[n:, n:] = -(minv @ vehicle.damping_base + (minv @ vehicle.damping_creep) / 30.0)
    assert np.array_equal(vehicle.state_matrix(30.0), expected)


@pytest.mark.parametrize("what, old, new", [
    ("damping", 'damping = "c"', "damping = 0"),
    ("stiffness", 'stiffness = "k"\n', "stiffness = 0\n"),
])
def test_series_element_needs_both_values(what, old, new):
    assert old in MAXWELL
    text = MAXWELL.replace(old, new)
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "maxwell.toml")
    line = MAXWELL.splitlines().index("[elements.maxwell]") + 1
    assert f"maxwell.toml:{line}: TSD maxwell: a series (Maxwell) element needs a nonzero {what}" in [
        str(p) for p in error.value.problems
    ]


def test_series_must_be_a_boolean():
    with pytest.raises(ModelError) as error:
        parse_toml_model(MAXWELL.replace("series = true", 'series = "yes"'), "maxwell.toml")
    assert "series must be true or false" in str(error.value.problems[0])


# ------------------------------------------------------------------ a car with bushes


def with_series_yaw_dampers(model, bush: float):
    """The conventional car with its yaw dampers (``cyaw`` in parallel with ``kx2``)
    split off as series elements of bush stiffness ``bush`` [N/m]."""
    elements = []
    for element in model.elements:
        if element.id.endswith(("_sxL", "_sxR")):
            elements.append(dataclasses.replace(element, damping=sp.S.Zero))
            elements.append(Element(f"{element.id}_yaw", sp.Symbol("kbush"), element.damping, element.s_end,
                                    element.t_end, element.direction, "yaw damper with bush", element.line,
                                    kind=ElementKind.SERIES))
        else:
            elements.append(element)
    parameters = {**model.parameters, "kbush": Parameter("kbush", bush, "N/m")}
    return dataclasses.replace(model, elements=tuple(elements), parameters=parameters)


@pytest.fixture(scope="module")
def conventional():
    return load_model(ROOT / "examples" / "conventional.toml")


def test_a_rigid_bush_gives_the_parallel_damper_critical_speed(conventional):
    from express.analysis.stability.stability import critical_speed

    plain = critical_speed(vehicle_model(conventional))
    rigid = vehicle_model(with_series_yaw_dampers(conventional, 1e11))
    assert rigid.n == vehicle_model(conventional).n + 4
    assert rigid.state_matrix(30.0).shape == (2 * rigid.n - 4,) * 2
    stiff = critical_speed(rigid)
    assert stiff.speed == pytest.approx(plain.speed, abs=0.2 / 3.6)
    soft = critical_speed(vehicle_model(with_series_yaw_dampers(conventional, 5e6)))
    # a bush of 5 MN/m lets the bogie yaw without stroking the damper: a real change
    assert abs(soft.speed - plain.speed) > 1.0


@pytest.mark.slow
def test_simulation_with_series_yaw_dampers_matches_a_reference_integration(conventional):
    from scipy.integrate import solve_ivp

    from express.analysis.time.simulate import continuous_rhs, simulate
    from express.rail.track import paper_curve

    vehicle = vehicle_model(with_series_yaw_dampers(conventional, 5e6))
    track = paper_curve()
    result = simulate(vehicle, track, end=150.0, progress=False)
    assert result.q.shape == (result.time.size, vehicle.n)
    assert result.q_dot.shape == result.q.shape
    stroke = vehicle.dof_index("T1_sxL_yaw.stroke")
    assert np.max(np.abs(result.q[:, stroke])) > 1e-5  # the damper works in the curve
    rhs = continuous_rhs(vehicle, track)
    reference = solve_ivp(rhs, (0.0, float(result.time[-1])), np.zeros(vehicle.form.size), method="Radau",
                          rtol=1e-7, atol=1e-10, t_eval=result.time)
    assert reference.success
    q = reference.y.T[:, : vehicle.n]
    peak = np.max(np.abs(q), axis=0)
    scale = np.maximum(peak, 1e-6)  # x DOFs stay at round-off level
    assert np.max(np.abs(result.q - q) / scale) < 0.02
    # q' of the stroke (a first-order coordinate) agrees with differentiating q
    slope = np.gradient(result.q[:, stroke], result.time)
    assert np.max(np.abs(result.q_dot[50:-50, stroke] - slope[50:-50])) < 0.05 * np.max(np.abs(slope))
