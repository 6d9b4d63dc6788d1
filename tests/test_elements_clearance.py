"""Clearance elements (bump stops): reading, the one warning of the linear analyses,
the force law, and the nonlinear simulation against a reference integration."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.forces.bump_stops import clearance_force, clearances_of
from express.assembly.generator import generate
from express.base.diagnostics import ModelError
from express.io import load_model, parse_toml_model
from express.model.records import Element, ElementKind, Parameter
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]

STOP = """
[parameters]
m = 100.0
k = "10 kN/m"
ks = "1 MN/m"
gap = "20 mm"

[bodies.B]
mass = "m"
inertia = [0, 0, 5]
dofs = ["y", "rz"]

[grounds.G]

[points.P]
body = "B"
offset = [0.5, 0, 0]

[points.Q]
body = "G"

[elements.spring]
from = "P"
to = "Q"
direction = "y"
stiffness = "k"

[elements.stop]
from = "P"
to = "Q"
direction = "y"
stiffness = "ks"
gap = "gap"
progressive = "1e9"
"""


def test_a_clearance_element_is_left_out_of_the_matrices_with_one_warning():
    model = parse_toml_model(STOP, "stop.toml")
    result = generate(model)
    k = sp.Symbol("k")
    assert sp.Matrix([[k, k / 2], [k / 2, k / 4]]) == result.equations.K
    assert len(result.warnings) == 1
    line = STOP.splitlines().index("[elements.stop]") + 1
    assert str(result.warnings[0]).startswith(f"stop.toml:{line}: TSD stop: clearance elements")
    (term,) = result.equations.clearances
    assert term.element == "stop"
    assert term.gradient == {"B.y": 1, "B.rz": sp.Rational(1, 2)}
    assert term.inputs == {"G.y": -1}
    assert term.gap == sp.Symbol("gap") and term.stiffness == sp.Symbol("ks")


def test_several_stops_one_warning():
    text = STOP + STOP[STOP.index("[elements.stop]"):].replace("[elements.stop]", "[elements.stop2]")
    warnings = generate(parse_toml_model(text, "stop.toml")).warnings
    assert len(warnings) == 1 and "TSD stop, stop2:" in str(warnings[0])


def test_numbers_of_the_clearances():
    model = parse_toml_model(STOP, "stop.toml")
    data = clearances_of(generate(model).equations, model.values())
    assert data.names == ("stop",)
    np.testing.assert_array_equal(data.gradient, [[1.0, 0.5]])
    np.testing.assert_array_equal(data.inputs, [[-1.0]])
    assert (data.gap[0], data.stiffness[0], data.progressive[0]) == (0.02, 1e6, 1e9)


@pytest.mark.parametrize("delta, expected", [
    (0.0, 0.0), (0.0199, 0.0), (-0.02, 0.0),
    (0.03, 1e6 * 0.01 + 1e9 * 0.01**3), (-0.05, -(1e6 * 0.03 + 1e9 * 0.03**3)),
])
def test_force_law(delta, expected):
    assert clearance_force(np.array(delta), 0.02, 1e6, 1e9) == pytest.approx(expected, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("old, new, message", [
    ('gap = "gap"', "gap = -0.01", "gap must be >= 0, got -0.01"),
    ('gap = "20 mm"', 'gap = "-20 mm"', "gap must be >= 0, got -0.02"),
    ('gap = "gap"\n', "", "progressive stiffness needs a gap"),
    ('gap = "gap"', 'gap = "gap"\nseries = true\ndamping = 1', "cannot be a series element"),
])
def test_bad_clearances_are_refused_with_the_line(old, new, message):
    assert old in STOP
    with pytest.raises(ModelError) as error:
        parse_toml_model(STOP.replace(old, new), "stop.toml")
    problems = [str(p) for p in error.value.problems]
    assert any(p.startswith("stop.toml:") and "TSD stop" in p and message in p for p in problems), problems
    assert all(p.split(":")[1].isdigit() for p in problems), problems


# ------------------------------------------------------------- a car with bump stops


def with_lateral_bump_stops(model, gap: float):
    """The conventional car with a secondary lateral bump stop at each bogie, on the
    lateral damper's CPs (car body - bogie frame, at the air-spring height)."""
    dampers = {e.id: e for e in model.elements}
    stops = [
        Element(f"T{t}_stop", sp.Symbol("kstop"), sp.S.Zero, dampers[f"T{t}_dy"].s_end, dampers[f"T{t}_dy"].t_end, 1,
                "lateral bump stop", None, kind=ElementKind.CLEARANCE, gap=sp.Symbol("ystop"),
                progressive=sp.Symbol("kstop3"))
        for t in (1, 2)
    ]
    parameters = {
        **model.parameters,
        "kstop": Parameter("kstop", 1e6, "N/m"),
        "kstop3": Parameter("kstop3", 1e10, "N/m^3"),
        "ystop": Parameter("ystop", gap, "m"),
    }
    return dataclasses.replace(model, elements=model.elements + tuple(stops), parameters=parameters)


@pytest.fixture(scope="module")
def conventional():
    return load_model(ROOT / "examples" / "conventional.toml")


@pytest.fixture(scope="module")
def runs(conventional):
    from express.analysis.time.simulate import simulate
    from express.rail.track import paper_curve

    track = paper_curve()
    plain = vehicle_model(conventional)
    stopped = vehicle_model(with_lateral_bump_stops(conventional, 0.02))
    return {
        "track": track,
        "plain": simulate(plain, track, end=250.0, progress=False),
        "stopped_vehicle": stopped,
        "stopped": simulate(stopped, track, end=250.0, progress=False),
        "wide": simulate(vehicle_model(with_lateral_bump_stops(conventional, 1.0)), track, end=250.0, progress=False),
    }


def _relative_lateral(result, vehicle, q=None):
    """Car body - bogie 1 lateral displacement at the stop (its deflection: the DOFs'
    part and the curvature inputs' part, the track turning between the stations)."""
    from express.analysis.time.simulate import track_inputs
    from express.rail.track import paper_curve

    data = clearances_of(vehicle.equations, vehicle.values)
    u = track_inputs(vehicle, paper_curve(), result.distance, result.speed).u
    return (result.q if q is None else q) @ data.gradient[0] + u @ data.inputs[0]


def test_linear_analyses_ignore_the_stops(conventional):
    plain = vehicle_model(conventional)
    stopped = vehicle_model(with_lateral_bump_stops(conventional, 0.03))
    assert np.array_equal(plain.state_matrix(30.0), stopped.state_matrix(30.0))


def test_stops_limit_the_car_body_in_the_curve(runs):
    stopped, vehicle = runs["stopped"], runs["stopped_vehicle"]
    free = np.max(np.abs(_relative_lateral(runs["plain"], vehicle)))
    limited = np.max(np.abs(_relative_lateral(stopped, vehicle)))
    assert free > 0.03  # the secondary suspension alone lets the body out by over 3 cm
    assert 0.02 < limited < 0.5 * free  # the stop engages and holds it near its gap
    delta = _relative_lateral(stopped, vehicle)
    expected = clearance_force(delta, 0.02, 1e6, 1e10)
    np.testing.assert_allclose(stopped.outputs["stop_T1_stop"], expected, rtol=1e-12, atol=1e-9)
    assert np.max(np.abs(expected)) > 1e4
    assert stopped.options["clearances"] is True


def test_a_stop_that_is_never_reached_changes_nothing(runs):
    np.testing.assert_allclose(runs["wide"].q, runs["plain"].q, rtol=0, atol=1e-12)
    assert np.all(runs["wide"].outputs["stop_T1_stop"] == 0.0)


@pytest.mark.slow
def test_march_with_stops_matches_a_reference_integration(runs):
    from scipy.integrate import solve_ivp

    from express.analysis.time.simulate import continuous_rhs

    vehicle, result = runs["stopped_vehicle"], runs["stopped"]
    rhs = continuous_rhs(vehicle, runs["track"])
    reference = solve_ivp(rhs, (0.0, float(result.time[-1])), np.zeros(vehicle.form.size), method="LSODA",
                          rtol=1e-8, atol=1e-11, t_eval=result.time)
    assert reference.success, reference.message
    delta = _relative_lateral(result, vehicle, reference.y.T[:, : vehicle.n])
    ours = _relative_lateral(result, vehicle)
    assert np.max(np.abs(ours - delta)) < 0.01 * np.max(np.abs(delta))
