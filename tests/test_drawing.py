"""Model drawings and mode shapes: geometry in numbers, views, modes, animations."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.base.diagnostics import ModelError
from express.drawing.geometry import displaced_geometry, estimated_outline, model_geometry, point_displacement
from express.drawing.modes import animate_mode_shape, figure_mode_shape, mode_shape
from express.drawing.views import figure_model, label_boxes
from express.io import load_model
from express.model.parameters import expression_value
from express.model.topology import classify_bodies
from express.numeric.statespace import load_vehicle

ROOT_EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _evaluator(values):
    def value(expression):
        expression = sp.sympify(expression)
        missing = sorted(s.name for s in expression.free_symbols if s.name not in values)
        if missing:
            raise KeyError(", ".join(missing))
        return float(expression.xreplace({sp.Symbol(k): v for k, v in values.items()}))

    return value


@pytest.fixture(scope="module")
def conventional():
    model = load_model("examples/conventional.toml")
    return model, model_geometry(model, _evaluator(model.values()), classify_bodies(model).role)


def test_points_sit_at_body_position_plus_offset(conventional):
    model, geometry = conventional
    values = model.values()
    for point in model.points[:20]:
        host = model.body(point.host)
        expected = [float(sp.sympify(p + o).subs(values)) for p, o in zip(host.position, point.offset)]
        np.testing.assert_allclose(geometry.points[point.id], expected, atol=1e-12)


@pytest.mark.parametrize(
    ("dofs", "offset", "expected"),
    [
        ({"B.rz": 0.01}, (2.0, 1.0, 0.0), (-0.01, 0.02, 0.0)),  # theta x r
        ({"B.rx": 0.02}, (0.0, 1.0, 0.5), (0.0, -0.01, 0.02)),
        ({"B.y": 0.003, "B.ry": 0.01}, (1.0, 0.0, 0.5), (0.005, 0.003, -0.01)),
    ],
)
def test_point_displacement_is_t_plus_theta_cross_r(dofs, offset, expected):
    np.testing.assert_allclose(point_displacement(offset, dofs, "B"), expected, atol=1e-15)


def test_displaced_geometry_moves_points_with_their_body(conventional):
    _, geometry = conventional
    moved = displaced_geometry(geometry, {"CB.y": 0.1})
    for point, host in geometry.hosts.items():
        shift = np.subtract(moved.points[point], geometry.points[point])
        np.testing.assert_allclose(shift, (0.0, 0.1, 0.0) if host == "CB" else (0.0, 0.0, 0.0), atol=1e-15)


def test_a_model_without_values_cannot_be_drawn_and_every_point_is_named():
    lever = load_model("examples/lever.exp")  # symbolic only: lLU, lLL, b have no value
    with pytest.raises(ModelError) as error:
        model_geometry(lever, _evaluator(lever.values()))
    lines = [str(p) for p in error.value.problems]
    assert len(lines) == 4 and all("cannot be drawn" in line for line in lines)
    assert any(line.startswith("examples/lever.exp:16: CP C1:") and "lLU" in line for line in lines)


def test_the_lever_draws_with_values():
    lever = load_model("examples/lever.exp")
    geometry = model_geometry(lever, _evaluator({"lLU": 0.3, "lLL": 0.06, "b": 0.5}), classify_bodies(lever).role)
    assert geometry.points["C1"] == (0.0, 0.0, 0.3) and geometry.points["C6"] == (0.0, -0.5, 0.0)
    figure = figure_model(geometry)
    assert [axis.get_title() for axis in figure.axes][:3] == ["plan (x forward, y left)", "side (x forward, z up)", "end (y left, z up)"]


def test_views_draw_every_element_and_body(conventional):
    model, geometry = conventional
    figure = figure_model(geometry)
    plan = figure.axes[0]
    (collection,) = plan.collections
    assert len(collection.get_segments()) >= len(model.elements)  # several polylines per symbol
    wheelsets = [b for b in geometry.bodies if b.role == "wheelset"]
    # no levers in this car: every body is its outline, every wheelset its two wheels
    assert len(plan.patches) == len(model.bodies) - len(wheelsets) + 2 * len(wheelsets)
    labels = {text.get_text() for text in plan.texts} | set(figure.texts[-1].get_text().replace(",", " ").split()
                                                             if figure.texts else [])
    assert {body.id for body in model.bodies} <= labels  # on the drawing or in the list under it


def test_outline_from_mass_and_inertia_is_the_uniform_box():
    """A box of 20 x 3 x 2.5 m and 30 t has Ix = m (w^2 + h^2) / 12 ...: back to its sides."""
    m, (length, w, h) = 30000.0, (20.0, 3.0, 2.5)
    inertia = (m * (w**2 + h**2) / 12, m * (length**2 + h**2) / 12, m * (length**2 + w**2) / 12)
    assert estimated_outline(m, inertia) == pytest.approx((length, w, h), rel=1e-12)
    assert estimated_outline(m, (1.0, 0.0, 1.0)) is None  # a wheelset's zero pitch inertia
    assert estimated_outline(m, (1.0, 1.0, 5.0)) is None  # no box has these


def test_wheels_are_circles_of_the_rolling_radius_in_the_side_view(conventional):
    from matplotlib.patches import Circle

    model, geometry = conventional
    side = figure_model(geometry).axes[1]
    circles = [p for p in side.patches if isinstance(p, Circle)]
    r0 = model.parameters["r0"].value
    assert len(circles) == 4 and all(c.radius == pytest.approx(r0) for c in circles)
    body = next(b for b in geometry.bodies if b.id == "CB")
    assert body.outline is not None and 15 < body.outline[0] < 30  # a car body's length [m]


@pytest.mark.parametrize("path", ["examples/conventional.toml", "examples/forced-steering.toml",
                                  "examples/manchester.toml", "tests/data/coach-series-dampers.toml"])
def test_no_two_labels_overlap(path):
    """Measured with the Agg renderer on the laid-out figure: every visible label's box
    is free of every other's, in every view (those without room are listed below)."""
    model = load_model(path)
    values = model.values()
    geometry = model_geometry(model, lambda e: expression_value(e, values), classify_bodies(model).role)
    figure = figure_model(geometry)
    for axis, boxes in label_boxes(figure).items():
        assert boxes, axis.get_title()
        for k, (text, box) in enumerate(boxes):
            for other, second in boxes[k + 1:]:
                assert not box.overlaps(second), (axis.get_title(), text.get_text(), other.get_text())


def test_mode_shape_matches_the_eigen_analysis():
    from express.analysis.stability.stability import eigen_analysis

    vehicle = load_vehicle("examples/conventional.toml")
    result = eigen_analysis(vehicle, vehicle.speed)
    for number in (1, 2, 5):
        mode = mode_shape(vehicle, vehicle.speed, number)
        assert mode.eigenvalue == pytest.approx(result.modes[number - 1].eigenvalue, rel=1e-9)
        assert max(abs(v) for v in mode.phi.values()) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="modes 1 to"):
        mode_shape(vehicle, vehicle.speed, 0)


@pytest.mark.slow
def test_mode_figure_and_animations(conventional):
    _, geometry = conventional
    vehicle = load_vehicle("examples/conventional.toml")
    mode = mode_shape(vehicle, vehicle.speed, 1)
    figure = figure_mode_shape(geometry, mode, "car body lateral")
    assert "mode 1: car body lateral" in figure._suptitle.get_text()
    gif = animate_mode_shape(geometry, mode, ".gif", frames=4)
    assert gif[:4] == b"GIF8"
    html = animate_mode_shape(geometry, mode, ".html", frames=4).decode()
    assert html.startswith("<!DOCTYPE html>") and html.count("data:image/png;base64,") == 5 and "http" not in html


def test_svg_drawing_carries_each_elements_name_and_values_as_a_tooltip(tmp_path):
    from express.cli import main

    out = tmp_path / "coach.svg"
    assert main(["draw", "tests/data/coach-series-dampers.toml", "-o", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    assert ("<title>T1_yawL (yaw damper with bushes, left): stiffness kyaw = 1e+07, damping cyaw = 3e+05, "
            "in series (SI)</title>") in text
    assert "<title>CB: car body, outline 26.98 x 3.26 x 3.26 m (from its mass and inertias)</title>" in text
    again = tmp_path / "again.svg"
    assert main(["draw", "tests/data/coach-series-dampers.toml", "-o", str(again)]) == 0
    assert again.read_bytes() == out.read_bytes()  # deterministic


def test_bump_stops_have_their_own_symbol():
    from express.drawing.views import _symbol

    model = load_model("examples/manchester.toml")
    values = model.values()
    geometry = model_geometry(model, lambda e: expression_value(e, values), classify_bodies(model).role)
    kinds = {element.id: element.kind for element in geometry.elements}
    assert kinds["T1_bump_stop"] == "stop" and kinds["T1_FL_pz"] == "spring-damper"
    lines: list = []
    _symbol(lines, "stop", np.zeros(2), np.array([1.0, 0.0]), 0.05)
    assert len(lines) == 4  # the spring, its end plate, the stop across the gap, the stop's stem


def test_an_outline_in_the_model_file_is_drawn_and_written_back(tmp_path):
    from express.io import parse_toml_model
    from express.io.toml_writer import model_to_toml

    text = (ROOT_EXAMPLES / "manchester.toml").read_text(encoding="utf-8").replace(
        'position = [0, 0, "hc"]', 'position = [0, 0, "hc"]\noutline = [23.0, 2.8, 3.1]', 1)
    model = parse_toml_model(text, "coach.toml")
    values = model.values()
    geometry = model_geometry(model, lambda e: expression_value(e, values), classify_bodies(model).role)
    body = next(b for b in geometry.bodies if b.id == "CB")
    assert body.outline == pytest.approx((23.0, 2.8, 3.1))
    again = parse_toml_model(model_to_toml(model), "again.toml")
    assert again.body("CB").outline == model.body("CB").outline


def _gids(figure) -> set[str]:
    return {str(line.get_gid()) for axis in figure.axes for line in axis.lines if line.get_gid()}


def test_anti_roll_bars_and_pins_have_their_own_symbols():
    model = load_model("examples/manchester.toml")
    values = model.values()
    geometry = model_geometry(model, lambda e: expression_value(e, values), classify_bodies(model).role)
    bars = [e.id for e in geometry.elements if "anti-roll" in e.description]
    assert bars  # the coach has one per bogie
    gids = _gids(figure_model(geometry))
    for bar in bars:  # the U-shaped bar and its two drop links, in each of the three views
        assert f"anti-roll-bar:{bar}" in gids and f"anti-roll-bar:{bar}:drop-link" in gids
    assert not any(g.startswith("pin:") for g in gids)

    steering = load_model("examples/forced-steering.toml")
    values = steering.values()
    geometry = model_geometry(steering, lambda e: expression_value(e, values), classify_bodies(steering).role)
    assert geometry.pins
    gids = _gids(figure_model(geometry))
    assert not any(g.startswith("anti-roll-bar:") for g in gids)  # no roll springs in this car
    for pin, _ in geometry.pins:  # a ring with a filled dot, unlike a connection point's open ring
        assert {f"pin:{pin}", f"pin:{pin}:dot"} <= gids
