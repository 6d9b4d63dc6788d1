"""The curve module's terms against an exact integration of the track geometry."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from express.io import load_model
from express.rail.curve import cant_deficiency_forces, curvature_point_inputs, stations
from express.rail.track import paper_curve

MODEL = load_model("examples/forced-steering.toml")
VALUES = {sp.Symbol(name): value for name, value in MODEL.values().items()}


def _station_position(body: str) -> float:
    """Position of the station holding ``body`` (inputs are named after a station's
    first body)."""
    for station in stations(MODEL):
        if body in station.bodies:
            return float(station.position.subs(VALUES))
    raise KeyError(body)


def _generated_offset(point: str, axis: int, track, s_body: np.ndarray) -> np.ndarray:
    """The generated curvature term of a CP, evaluated along the track with its body's
    station at ``s_body``."""
    terms = curvature_point_inputs(MODEL)[(point, axis)]
    body_station = _station_position(MODEL.point(point).host)
    total = np.zeros_like(s_body)
    for name, coefficient in terms.items():
        station = _station_position(name.split(".")[0])
        total += float(coefficient.subs(VALUES)) * track.curvature(s_body + station - body_station)
    return total


@pytest.mark.parametrize("shape, tolerance", [("sine", 0.004), ("linear", 0.012)])
def test_lateral_term_above_the_bogie_matches_the_exact_geometry(shape, tolerance):
    """The car-body CP above the front bogie centre (lx = lT = 7.2 m): its generated
    lateral term (two-station form) against minus the exact offset of the track
    centreline lT ahead of the car body's tangent, along the whole paper curve.
    The error stays within ``tolerance`` of the steady-curve value lT^2 / (2 R), and
    is several times smaller than the one-station form's."""
    track = paper_curve(shape=shape)
    lead = 7.2 + 1.15  # the leading wheelset is lT + a ahead of the car body
    s = np.linspace(0.0, track.length, 4001) - lead
    generated = _generated_offset("CB_T1L", 1, track, s)
    exact = -np.asarray(track.lateral_offset_exact(s, 7.2))
    steady = 7.2**2 / (2 * 400.0)
    one_station = -track.curvature(s) * 7.2**2 / 2
    error = np.max(np.abs(generated - exact)) / steady
    error_one_station = np.max(np.abs(one_station - exact)) / steady
    assert error < tolerance
    assert error < error_one_station / 2
    mid = np.argmin(np.abs(s - 250.0))  # steady curve: both forms agree with the geometry
    assert generated[mid] == pytest.approx(-steady, rel=1e-3)


def test_longitudinal_term_is_the_turn_of_the_track():
    """The longitudinal term of the steering-beam CP (lx = lT, Y = bL) is Y times the
    turn of the track between the car body and the bogie, ``Y (theta(s + lT) -
    theta(s))``, to within 1 % of its steady value on the sine-ramp curve."""
    track = paper_curve()
    s = np.linspace(-20.0, track.length, 3001)
    generated = _generated_offset("CB_T1_beamL", 0, track, s)
    exact = 1.0 * (np.asarray(track.heading(s + 7.2)) - np.asarray(track.heading(s)))
    steady = 1.0 * 7.2 / 400.0
    assert np.max(np.abs(generated - exact)) < 0.01 * steady


def test_cant_deficiency_of_the_whole_vehicle():
    """Summed over the lateral DOFs, the cant-deficiency force at 120 km/h on
    R = 400 m with 95 mm cant is m_total (v^2/R - g S/G) (towards the outside), with
    m_total the masses that have a lateral DOF: car body, bogie frames, wheelsets."""
    v, radius, cant = 120 / 3.6, 400.0, 0.095
    forces = cant_deficiency_forces(MODEL, sp.Symbol("v"), sp.Symbol("g"), sp.Symbol("G"))
    values = dict(VALUES)
    values[sp.Symbol("v")] = v
    total = 0.0
    for _dof, name, coefficient in forces:
        total += float(coefficient.subs(values)) * (1 / radius if name.endswith(".rho") else cant)
    parameters = MODEL.values()
    mass = parameters["mc"] + 2 * parameters["mt"] + 4 * parameters["mw"]
    expected = -mass * (v**2 / radius - parameters["g"] * cant / parameters["G"])
    assert total == pytest.approx(expected, rel=1e-12)
    assert total < 0  # towards the outside of a left curve


def _pairwise_groups(model) -> list[tuple[str, ...]]:
    """The grouping by comparing every pair of positions (the definition)."""
    groups: list[tuple[sp.Expr, list[str]]] = []
    for body in model.bodies:
        position = sp.sympify(body.position[0])
        for existing, members in groups:
            if sp.expand(existing - position) == 0:
                members.append(body.id)
                break
        else:
            groups.append((position, [body.id]))
    return [tuple(members) for _, members in groups]


@pytest.mark.parametrize(
    "positions, expected",
    [
        (["lT - a - Lc", "-(Lc + a) + lT", "lT"], [("B0", "B1"), ("B2",)]),
        (["3/2", "1.5", "0", "0.0"], [("B0", "B1"), ("B2", "B3")]),
        (["lT", "1.0*lT", "2*lT/2", "lT/2", "0.5*lT"], [("B0", "B1", "B2"), ("B3", "B4")]),
        (["lT + a - a", "lT", "a"], [("B0", "B1"), ("B2",)]),
        (["2*(lT + a)", "2*lT + 2*a", "2*lT + a"], [("B0", "B1"), ("B2",)]),
    ],
)
def test_stations_group_equal_positions_whatever_their_form(positions, expected):
    """Grouped by a dictionary, as by comparing every pair: equal positions written in
    different forms share a station, in file order."""
    import dataclasses

    from express.base.expressions import parse_expression

    body = MODEL.bodies[0]
    bodies = tuple(
        dataclasses.replace(body, id=f"B{i}", position=(parse_expression(text), *body.position[1:]))
        for i, text in enumerate(positions)
    )
    model = dataclasses.replace(MODEL, bodies=bodies)
    assert [s.bodies for s in stations(model)] == expected == _pairwise_groups(model)
    assert [s.name for s in stations(model)] == [group[0] for group in expected]


def test_stations_of_a_train_are_those_of_the_pairwise_definition(tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_vehicles", "examples/make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = tmp_path / "train.toml"
    path.write_text(module.vehicle_toml(True, cars=3), encoding="utf-8")
    train = load_model(path)
    grouped = stations(train)
    assert [s.bodies for s in grouped] == _pairwise_groups(train)
    assert len(grouped) == 3 * len(stations(MODEL))


def test_yaw_term_is_minus_the_turn_of_the_track():
    """The yaw of the car-body CP above the front bogie (lx = lT), seen in the track
    frame at its station, is the car body's less the track's turn over lT:
    ``-(theta(s + lT) - theta(s))``, within 1 % of its steady value along the curve."""
    track = paper_curve()
    s = np.linspace(-20.0, track.length, 3001)
    generated = _generated_offset("CB_T1L", 5, track, s)
    exact = -(np.asarray(track.heading(s + 7.2)) - np.asarray(track.heading(s)))
    assert np.max(np.abs(generated - exact)) < 0.01 * 7.2 / 400.0


def test_a_yaw_element_turns_in_a_curve_as_the_side_bearers_it_stands_for(tmp_path):
    """Issue 31: a rotational rz element between the car body's seat above a bogie and
    the bogie put no moment into a curve (no curvature column), while the same stiffness
    as two longitudinal springs at +-b2 did.  The Manchester car's secondary yaw element
    (kpsi = 2 kb2) against the springs kb2 / b2^2 at each air spring: the same curvature
    columns of P and the same yaw block of K, to the last bit (achieved: equal)."""
    from pathlib import Path

    from express.numeric.statespace import load_vehicle

    text = (Path(__file__).resolve().parents[1] / "examples" / "manchester.toml").read_text()
    element = ('yaw = { from = "seat_S", to = "stop", direction = "rz", stiffness = "2*kb2", '
               'label = "secondary yaw stiffness (both sides)" }')
    assert element in text
    bearers = ('bxL = { from = "seat_L", to = "sL", direction = "x", stiffness = "kb2/b2^2" }\n'
               'bxR = { from = "seat_R", to = "sR", direction = "x", stiffness = "kb2/b2^2" }')
    (tmp_path / "yaw.toml").write_text(text)
    (tmp_path / "bearers.toml").write_text(text.replace(element, bearers))
    yaw, springs = load_vehicle(tmp_path / "yaw.toml"), load_vehicle(tmp_path / "bearers.toml")
    assert yaw.inputs == springs.inputs and yaw.dofs == springs.dofs
    curvature = [j for j, name in enumerate(yaw.inputs) if name.endswith(".rho")]
    p_yaw, p_springs = np.asarray(yaw.forcing(yaw.speed)), np.asarray(springs.forcing(yaw.speed))
    np.testing.assert_array_equal(p_yaw[:, curvature], p_springs[:, curvature])
    front = yaw.dof_index("T1.rz"), yaw.inputs.index("CB.rho")
    assert p_yaw[front] != 0.0  # the car body's curvature turns the bogie against its yaw stiffness
    rz = [i for i, dof in enumerate(yaw.dofs) if dof.endswith(".rz")]
    k_yaw, k_springs = np.asarray(yaw.stiffness), np.asarray(springs.stiffness)
    np.testing.assert_array_equal(k_yaw[np.ix_(rz, rz)], k_springs[np.ix_(rz, rz)])
