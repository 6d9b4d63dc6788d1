"""The parameter graph (express.model.parameters) and the unit checks (express.model.parameter_units)."""

from __future__ import annotations

import ast
import math
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from express.base.diagnostics import ModelError
from express.base.expressions import parse_expression
from express.base.units import DIMENSIONS, KMH
from express.io import load_model, model_to_toml, parse_toml_model
from express.model.parameters import (
    CommandLineText,
    display_value,
    evaluation_order,
    expression_value,
    override_values,
    quantity_value,
    units_map,
    with_values,
)
from express.model.parameters import with_values as model_with_values
from express.model.records import Derivation, Parameter
from express.numeric.statespace import load_vehicle, vehicle_model
from express.rail.contact import creep_coefficients

ROOT = Path(__file__).resolve().parents[1]
FORCED = ROOT / "examples" / "forced-steering.toml"
FORCED_TEXT = FORCED.read_text(encoding="utf-8")
G = 9.81

SMALL = """
[parameters]
m = "20 kg"
J = "0.5 kg*m^2"
l = "0.3 m"
k = "5 kN/m"
kr = "2 kN*m/rad"
c = "1 kN*s/m"
{extra}

[bodies.B1]
mass = "m"
inertia = [0, "J", 0]
dofs = ["x", "ry"]

[bodies.B2]
mass = "m"
inertia = [0, "J", 0]
dofs = ["x", "ry"]

[grounds.G1]

[points.C1]
body = "B1"
offset = [0, 0, "l"]

[points.C2]
body = "G1"
offset = [0, 0, 0]

[points.C3]
body = "B2"
offset = [0, 0, 0]

[elements.T1]
from = "C1"
to = "C2"
direction = "x"
stiffness = "k"
damping = "c"

[elements.T2]
from = "C1"
to = "C3"
direction = "ry"
stiffness = "kr"
"""


def small(extra: str = "", **replace: str) -> str:
    text = SMALL.replace("{extra}", extra)
    for old, new in replace.items():
        text = text.replace(old.replace("_", " "), new)
    return text


def line_of(text: str, needle: str) -> int:
    return next(n for n, line in enumerate(text.splitlines(), 1) if needle in line)


def forced(*replacements: tuple[str, str]) -> str:
    text = FORCED_TEXT
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


@pytest.fixture(scope="module")
def steered():
    return load_model(FORCED)


@pytest.fixture(scope="module")
def steered_vehicle():
    return load_vehicle(FORCED)


# ----------------------------------------------------------------------------- graph


def test_bundled_vehicle_derives_the_wheel_load_from_the_masses(steered):
    p = steered.parameters
    assert p["P0"].expression == parse_expression("(mc + 2*mt + 4*mw)*g/8")
    assert p["P0"].value == pytest.approx((30000 + 2 * 2600 + 4 * 1400) * G / 8, rel=1e-15)
    expected = creep_coefficients(p["P0"].value, 0.43, 0.3, 206e9, 0.3)
    assert p["f1"].value == expected.f11 and p["f2"].value == expected.f22
    assert p["f1"].derived_by == "rail.creep" and not p["f1"].is_primary


def test_changing_a_mass_reevaluates_wheel_load_and_creep_coefficients(steered):
    """Done-when of issue 10: f1 for mc = 60 t is f1(30 t) (P0'/P0)^(2/3) (same radii:
    the Hertz semi-axes go as N^(1/3), Kalker's f11 = G a b C11 as N^(2/3))."""
    heavy = with_values(steered, {"mc": "60 t"})
    p0, p1 = steered.parameters["P0"].value, heavy.parameters["P0"].value
    assert p1 == pytest.approx((60000 + 2 * 2600 + 4 * 1400) * G / 8, rel=1e-15)
    for name in ("f1", "f2"):
        scaled = steered.parameters[name].value * (p1 / p0) ** (2 / 3)
        assert heavy.parameters[name].value == pytest.approx(scaled, rel=1e-6)
    assert heavy.parameters["mc"].unit == "kg"  # the unit written stays for display


@pytest.mark.parametrize("change", [{"mc": "60 t"}, {"mc": 60000.0}, {"mc": "60000"}])
def test_every_override_path_reevaluates_dependents(steered, steered_vehicle, change):
    """--set (load_vehicle), VehicleModel.with_values and express.model.parameters.with_values agree."""
    expected = with_values(steered, {"mc": 60000.0})
    wheel_load = expected.parameters["P0"].value
    f1 = expected.parameters["f1"].value
    by_model = model_with_values(steered, change)
    by_vehicle = steered_vehicle.with_values(change)
    by_loader = load_vehicle(FORCED, change)
    assert by_model.parameters["P0"].value == wheel_load
    for vehicle in (by_vehicle, by_loader):
        assert all(w.wheel_load == wheel_load and w.f1 == f1 for w in vehicle.wheelsets)
        assert vehicle.values["f2"] == expected.parameters["f2"].value
    # the creep damping (the 1/v part of C) of a wheelset's lateral motion is 2 f2 / v
    w1 = steered_vehicle.dof_index("W1.y")
    ratio = by_vehicle.damping_creep[w1, w1] / steered_vehicle.damping_creep[w1, w1]
    assert ratio == pytest.approx(expected.parameters["f2"].value / steered.parameters["f2"].value, rel=1e-12)


def test_giving_a_derived_parameter_a_value_makes_it_given(steered):
    fixed = with_values(steered, {"P0": "60 kN"})
    assert fixed.parameters["P0"].value == 60000.0 and fixed.parameters["P0"].is_primary
    assert fixed.parameters["f1"].value == creep_coefficients(60000.0, 0.43, 0.3, 206e9, 0.3).f11
    heavier = with_values(fixed, {"mc": "60 t"})
    assert heavier.parameters["P0"].value == 60000.0  # no longer follows the masses


def test_evaluation_order_lists_expressions_and_the_kalker_node(steered):
    order = evaluation_order(steered)
    names = [step.name if isinstance(step, Parameter) else step.item for step in order]
    assert names.index("P0") < names.index("rail.creep")
    kalker = next(step for step in order if isinstance(step, Derivation))
    assert kalker.kind == "kalker"
    assert kalker.input("wheel_load") == sp.Symbol("P0") and kalker.output("f11") == "f1"
    assert [step.expression for step in order if isinstance(step, Parameter)] == [parse_expression("(mc + 2*mt + 4*mw)*g/8")]


@pytest.mark.parametrize(
    ("extra", "values"),
    [
        ('a = "2*b"\nb = "l + 1"', {"a": 2.6, "b": 1.3}),
        ('b = "l + 1"\na = "2*b"', {"a": 2.6, "b": 1.3}),
        ('a = "k/2"', {"a": 2500.0}),
        ('a = "m*l^2/12"', {"a": 20 * 0.09 / 12}),
        ('a = "(l - 0.1)^-1"', {"a": 5.0}),
    ],
)
def test_derived_values(extra, values):
    model = parse_toml_model(small(extra), "s.toml")
    for name, value in values.items():
        assert model.parameters[name].value == pytest.approx(value, rel=1e-14)


def test_override_reaches_a_chain_of_dependents():
    model = parse_toml_model(small('a = "2*b"\nb = "l + 1"'), "s.toml")
    changed = with_values(model, {"l": "500 mm"})
    assert changed.parameters["b"].value == pytest.approx(1.5) and changed.parameters["a"].value == pytest.approx(3.0)


@pytest.mark.parametrize(
    ("extra", "first", "chain"),
    [
        ('a = "b + l"\nb = "2*a"', "a", ["a (line", "uses b (line", "uses a (line"]),
        ('a = "a*2"', "a", ["a (line", "uses a (line"]),
        ('a = "b"\nb = "d"\nd = "a/2"', "a", ["uses b", "uses d", "uses a"]),
    ],
)
def test_a_cycle_is_refused_naming_it(extra, first, chain):
    text = small(extra)
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "s.toml")
    problem = next(p for p in info.value.problems if "circular" in p.message)
    assert problem.item == f"parameter {first}" and problem.line == line_of(text, f"{first} =")
    assert str(problem).startswith(f"s.toml:{problem.line}: parameter {first}: circular definition: ")
    position = 0
    for piece in chain:
        position = problem.message.index(piece, position)


def test_a_cycle_through_the_kalker_node_is_refused():
    text = forced(('P0 = "(mc + 2*mt + 4*mw)*g/8"', 'P0 = "f1/100"'))
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "f.toml")
    message = " ".join(p.message for p in info.value.problems)
    assert "circular definition" in message and "rail.creep (line" in message and "P0 (line" in message


def test_undefined_name_in_a_definition():
    text = small('a = "l*lXX"')
    with pytest.raises(ModelError, match=r"s.toml:\d+: parameter a: undefined name lXX where a number is required"):
        parse_toml_model(text, "s.toml")


def test_an_undefined_name_in_an_element_carries_file_and_line():
    """Symbolic names are allowed on reading; numbers refuse them naming the item."""
    text = small().replace('stiffness = "k"', 'stiffness = "kXX"')
    model = parse_toml_model(text, "s.toml")
    with pytest.raises(ModelError) as info:
        vehicle_model(model)
    problem = info.value.problems[0]
    assert (problem.file, problem.item, problem.line) == ("s.toml", "TSD T1", line_of(text, "[elements.T1]"))
    assert "undefined name kXX" in problem.message


def test_contact_data_out_of_range_is_a_model_error(steered):
    with pytest.raises(ModelError, match=r"rail\.creep"):
        with_values(steered, {"nu": 0.7})


def test_division_by_zero_in_a_definition_is_reported():
    with pytest.raises(ModelError, match=r"parameter a: .*finite"):
        parse_toml_model(small('z = 0\na = "l/z"'), "s.toml")


# ----------------------------------------------------------------------------- units

# (what is wrong, replacements in the forced-steering file, line needle, item, message)
UNIT_MISTAKES = [
    ("height in kg (issue 10)", [('hc = { value = 1.6, unit = "m" }', 'hc = "1.8 kg"')], "hc =",
     "parameter hc", "used as a length (body CB position) but has unit kg"),
    ("mass in metres", [('mt = { value = 2600.0, unit = "kg" }', 'mt = "2.6 m"')], "mt =",
     "parameter mt", "used as a mass (body T1 mass) but has unit m"),
    ("inertia in kg", [('Icx = { value = 53000.0, unit = "kg*m^2" }', 'Icx = "53 t"')], "Icx =",
     "parameter Icx", "used as an inertia (body CB inertia Ix) but has unit t"),
    ("stiffness N*m/rad for a translational element",
     [('kx2 = { value = 150000.0, unit = "N/m" }', 'kx2 = "150 kN*m/rad"')], "kx2 =",
     "parameter kx2", "used as a stiffness (TSD T1_sxL stiffness) but has unit kN*m/rad"),
    ("damping given as a stiffness", [('cy2 = { value = 30000.0, unit = "N*s/m" }', 'cy2 = "30 kN/m"')], "cy2 =",
     "parameter cy2", "used as a damping (TSD T1_dy damping) but has unit kN/m"),
    ("speed given as a length", [('v = "120 km/h"', 'v = "120 km"')], "v =",
     "parameter v", "used as a speed (rail speed) but has unit km"),
    ("conicity as an angle", [('Gamma = { value = 0.1, unit = "1" }', 'Gamma = "6 deg"')], "Gamma =",
     "parameter Gamma", "used as a pure number (wheelset W1 conicity) but has the angle unit deg"),
    ("wheel load as a mass", [('P0 = "(mc + 2*mt + 4*mw)*g/8"', 'P0 = "5.1 t"')], "P0 =",
     "parameter P0", "used as a force (wheelset W1 wheel_load) but has unit t"),
    ("wheel load without gravity", [('P0 = "(mc + 2*mt + 4*mw)*g/8"', 'P0 = "(mc + 2*mt + 4*mw)/8"')], "P0 =",
     "parameter P0", "its expression mc/8 + mt/4 + mw/2 is a mass (kg)"),
    ("a length added to a mass", [('P0 = "(mc + 2*mt + 4*mw)*g/8"', 'P0 = "(a + mc)*g/8"')], "P0 =",
     "parameter P0", '"g*(a + mc)/8" adds a length (m) (a) and a mass (kg) (mc)'),
    ("Young's modulus in metres", [('Emod = { value = 206, unit = "GPa" }', 'Emod = "206 m"')], "Emod =",
     "parameter Emod", "used as a pressure (rail.creep youngs_modulus) but has unit m"),
    ("gravity as a speed", [('g = { value = 9.81, unit = "m/s^2" }', 'g = "9.81 m/s"')], "g =",
     "parameter g", "used as an acceleration"),
    ("rail stiffness as a rotational stiffness", [('kR = { value = 20000000.0, unit = "N/m" }', 'kR = "20 MN*m/rad"')],
     "kR =", "parameter kR", "used as a stiffness (wheelset W1 rail_stiffness) but has unit MN*m/rad"),
]


@pytest.mark.parametrize(("what", "replacements", "needle", "item", "message"), UNIT_MISTAKES, ids=[m[0] for m in UNIT_MISTAKES])
def test_unit_mistakes_are_refused_with_file_and_line(what, replacements, needle, item, message):
    text = forced(*replacements)
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "bad.toml")
    matching = [p for p in info.value.problems if p.item == item and message in p.message]
    assert matching, "\n".join(str(p) for p in info.value.problems)
    assert matching[0].line == line_of(text, needle) and matching[0].file == "bad.toml"


def test_issue_example_is_one_line():
    text = forced(('hc = { value = 1.6, unit = "m" }', 'hc = "1.8 kg"'))
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "bad.toml")
    assert [str(p) for p in info.value.problems] == [
        f"bad.toml:{line_of(text, 'hc =')}: parameter hc: used as a length (body CB position) but has unit kg"
    ]


def test_every_unit_mistake_is_reported_at_once():
    replacements = [r[0] for _, rs, *_ in UNIT_MISTAKES[:8] for r in [rs]]
    with pytest.raises(ModelError) as info:
        parse_toml_model(forced(*replacements), "bad.toml")
    items = {p.item for p in info.value.problems}
    assert {"parameter hc", "parameter mt", "parameter Icx", "parameter kx2", "parameter cy2", "parameter v",
            "parameter Gamma", "parameter P0"} <= items


@pytest.mark.parametrize(
    ("extra", "replace", "item", "message"),
    [
        ("", {'kr = "2 kN*m/rad"': 'kr = "2 kN/m"'}, "parameter kr",
         "used as a rotational stiffness (TSD T2 stiffness) but has unit kN/m"),
        ("", {'k = "5 kN/m"': 'k = "5 kN*m/rad"'}, "parameter k", "used as a stiffness (TSD T1 stiffness)"),
        ("", {'stiffness = "k"': 'stiffness = "k*l"'}, "TSD T1", 'stiffness "k*l" is a force (N), expected a stiffness'),
        ("x = 3", {'mass = "m"': 'mass = "x"', 'offset = [0, 0, "l"]': 'offset = [0, 0, "x"]'}, "parameter x",
         "used as a length (CP C1 offset) and is used as a mass (body B1 mass, line"),
        ('kh = "k/2"', {'kr = "2 kN*m/rad"': 'kr = "kh"'}, "parameter kr",
         "used as a rotational stiffness (TSD T2 stiffness, line 42) but its expression kh is a stiffness (N/m)"),
    ],
)
def test_unit_mistakes_in_a_small_model(extra, replace, item, message):
    text = SMALL.replace("{extra}", extra)
    for old, new in replace.items():
        text = text.replace(old, new, 1)
    with pytest.raises(ModelError) as info:
        parse_toml_model(text, "s.toml")
    assert any(p.item == item and message in p.message for p in info.value.problems), [str(p) for p in info.value.problems]


@pytest.mark.parametrize(
    ("extra", "replace"),
    [
        ('kh = "k/2"', {'stiffness = "k"': 'stiffness = "kh"'}),  # kLU/2 stays N/m
        ("k = 5000", {'k = "5 kN/m"': ""}),  # a bare number is SI and takes its use's dimension
        ('l2 = "l + 0.1"', {'offset = [0, 0, "l"]': 'offset = [0, 0, "l2"]'}),  # a number in a sum
        ('kr2 = "k*l^2"', {'stiffness = "kr"': 'stiffness = "kr2"'}),  # N/m * m^2 = N*m (per rad)
        ('w = "(k/m)^(1/1)"', {}),  # unused: no constraint
    ],
)
def test_consistent_units_are_accepted(extra, replace):
    text = SMALL.replace("{extra}", extra)
    for old, new in replace.items():
        text = text.replace(old, new, 1)
    parse_toml_model(text, "s.toml")


def test_dimensions_are_settled(steered):
    p = steered.parameters
    assert p["P0"].dimension == DIMENSIONS["force"] and p["f1"].dimension == DIMENSIONS["force"]
    assert p["v"].dimension == DIMENSIONS["speed"] and p["Gamma"].dimension == DIMENSIONS["dimensionless"]
    assert p["kLU"].dimension == DIMENSIONS["stiffness"]


# ----------------------------------------------------------------------------- overrides


@pytest.mark.parametrize(
    ("changes", "fragment"),
    [
        ({"gamma": 0.05}, "no such parameter in the model; did you mean Gamma?"),
        ({"kLX": 1.0}, "did you mean kLU?"),
        ({"ky1": "4 s"}, '"4 s": unit s is a time (s), expected a stiffness (N/m)'),
        ({"v": "1 km^400"}, "too large"),
        ({"mc": "heavy"}, "not a number"),
        ({"mc": math.inf}, "not a finite number"),
        ({"mc": True}, "expected a number"),
    ],
)
def test_bad_overrides_are_refused(steered, changes, fragment):
    with pytest.raises(ModelError) as info:
        override_values(steered, changes)
    assert fragment in str(info.value)
    name = next(iter(changes))
    assert info.value.problems[0].item == f"parameter {name}"


def test_all_bad_overrides_at_once(steered):
    with pytest.raises(ModelError) as info:
        with_values(steered, {"gamma": 0.1, "ky1": "4 s", "mc": "30 t"})
    assert [p.item for p in info.value.problems] == ["parameter gamma", "parameter ky1"]


@pytest.mark.parametrize(
    ("name", "value", "si"),
    [
        ("v", "100", 100.0),  # a bare speed is SI in the library (issue 35 item 7)
        ("v", CommandLineText("100"), 100 * KMH),  # typed on the command line: km/h (rail usage, as --speed)
        ("v", "27.8 m/s", 27.8),
        ("v", "100 km/h", 100 * KMH),
        ("v", 27.8, 27.8),  # a float is SI
        ("mc", "60 t", 60000.0),
        ("mc", "60000", 60000.0),
        ("kLU", "0.1 MN/m", 1e5),
        ("Gamma", "1/20", 0.05),
        ("hc", "1800 mm", 1.8),
    ],
)
def test_override_values(steered, name, value, si):
    assert override_values(steered, {name: value})[name] == pytest.approx(si, rel=1e-15)


def test_quantity_value_rule():
    assert quantity_value(CommandLineText("100"), DIMENSIONS["speed"]) == pytest.approx(100 / 3.6)
    assert quantity_value("100", DIMENSIONS["speed"]) == 100.0  # the library: SI
    assert quantity_value("100") == 100.0
    assert quantity_value("2 kN/m", DIMENSIONS["stiffness"]) == 2000.0


def test_symbolic_model_accepts_values_for_its_names():
    model = load_model(ROOT / "examples" / "lever.exp")
    valued = with_values(model, {"m": 20.0, "J1": 1.0, "J2": 0.5})
    assert valued.parameters["m"].value == 20.0
    with pytest.raises(ModelError, match="did you mean m"):
        with_values(model, {"mm": 1.0})


# ----------------------------------------------------------------------------- evaluator


@pytest.mark.parametrize(
    ("text", "values", "expected"),
    [
        ("2*a - 0.3", {"a": 1.0}, 1.7),
        ("(mc + 2*mt)*g/8", {"mc": 30000.0, "mt": 2600.0, "g": 9.81}, (30000.0 + 5200.0) * 9.81 / 8),
        ("a^-2", {"a": 2.0}, 0.25),
        ("-b", {"b": 0.5}, -0.5),
        ("7", {}, 7.0),
    ],
)
def test_expression_value(text, values, expected):
    assert expression_value(parse_expression(text), values) == pytest.approx(expected, rel=1e-15)


@pytest.mark.parametrize(
    ("text", "values", "error"),
    [
        ("a + b", {"a": 1.0}, KeyError),
        ("1/a", {"a": 0.0}, ValueError),
        ("a^64", {"a": 1e300}, ValueError),
        ("a*a", {"a": 1e300}, ValueError),
    ],
)
def test_expression_value_errors(text, values, error):
    with pytest.raises(error):
        expression_value(parse_expression(text), values)


# ----------------------------------------------------------------------------- display, writer, layers


def test_values_shown_in_the_unit_written(steered):
    p = steered.parameters
    assert display_value(p["cy2"]) == "30000 N*s/m"
    assert display_value(p["Emod"]) == "206 GPa"
    assert display_value(p["v"]) == "120 km/h"
    assert display_value(p["P0"]) == "50031 N"  # derived: the SI unit of its dimension
    units = units_map(steered)
    assert units["P0"] == "N" and units["f1"] == "N" and units["v"] == "km/h"


def test_toml_writer_keeps_the_graph(steered, tmp_path):
    text = model_to_toml(steered)
    assert 'P0 = "g*(mc + 2*mt + 4*mw)/8"' in text
    assert 'mc = { value = 30000.0, unit = "kg" }' in text
    assert 'v = { value = 120.0, unit = "km/h" }' in text or 'v = 33.33' in text
    block = text.split("[parameters]", 1)[1].split("\n[", 1)[0]
    assert "\nP0 =" in block and "\nf1 =" not in block  # f1 is computed by [rail.creep] on loading
    again = parse_toml_model(text, "again.toml")
    for name, parameter in steered.parameters.items():
        assert again.parameters[name].value == parameter.value, name
    heavy = with_values(again, {"mc": "60 t"})
    assert heavy.parameters["f1"].value == with_values(steered, {"mc": "60 t"}).parameters["f1"].value


def test_repr_is_one_line(steered, steered_vehicle):
    for text in (repr(steered), repr(steered_vehicle)):
        assert "\n" not in text and len(text) < 250
    assert repr(steered).startswith("<Model 'forced_steering'") and "3 derived" in repr(steered)
    assert "24 DOFs" in repr(steered_vehicle) and "120 km/h" in repr(steered_vehicle)


LOWER = ["model.py", "parameters.py", "parameter_units.py", "units.py", "expressions.py", "io"]


def _imports(path: Path) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module:
            found.add("." * node.level + node.module)
        elif isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
    return found


@pytest.mark.parametrize("where", LOWER)
def test_reader_and_model_layers_do_not_import_rail(where):
    base = ROOT / "src" / "express" / where
    for path in [base] if base.is_file() else sorted(base.glob("*.py")):
        rail = [m for m in _imports(path) if "rail" in m.split(".") or "statespace" in m]
        assert not rail, (path, rail)


def test_importing_the_reader_does_not_import_rail_or_pint():
    code = "import sys, express.io, express.model.parameters; print(sorted(m for m in sys.modules if m.startswith(('express.rail', 'pint'))))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


# ----------------------------------------------------------------------------- the command line


def _simulate_json(capsys, *extra: str) -> dict:
    import json

    from express.cli import main

    track = ROOT / "examples" / "tracks" / "straight_sinusoid.toml"
    status = main(["simulate", str(FORCED), "--track", str(track), "--json", *extra])
    out = capsys.readouterr().out
    assert status == 0
    return json.loads(out)


@pytest.mark.slow
def test_set_a_mass_on_the_command_line_changes_the_wheel_load(capsys):
    """Issue 10's first complaint: ``--set mc=60000`` kept P0 = 50.03 kN (and f1, f2)."""
    heavy = _simulate_json(capsys, "--set", "mc=60000")
    p0 = (60000 + 2 * 2600 + 4 * 1400) * G / 8
    for k in range(1, 5):
        assert heavy["max_abs"][f"YQ{k}"] == pytest.approx(heavy["max_abs"][f"Y{k}"] / p0, rel=1e-9)
    again = _simulate_json(capsys, "--set", "mc=60 t")
    assert again["max_abs"] == heavy["max_abs"]


@pytest.mark.slow
def test_set_refuses_a_unit_of_the_wrong_dimension(capsys):
    from express.cli import main

    status = main(["eigen", str(FORCED), "--set", "ky1=4 s", "--speed", "100"])
    err = capsys.readouterr().err
    assert status == 2
    assert "parameter ky1" in err and "expected a stiffness (N/m)" in err and "Traceback" not in err


def test_a_reading_infers_the_dimensions_once(monkeypatch):
    """The reader checks the parameters and then resolves the same model: the inference
    (2.8 s on a 100-car train) runs once, and a changed model is inferred anew."""
    from dataclasses import replace as replaced

    from express.io import load_model
    from express.model import parameter_units

    runs: list[int] = []
    original = parameter_units._Inference.run
    monkeypatch.setattr(parameter_units._Inference, "run", lambda self, sites: runs.append(1) or original(self, sites))
    monkeypatch.setattr(parameter_units, "_LAST", [])
    model = load_model(Path(__file__).resolve().parents[1] / "examples" / "forced-steering.toml")
    assert len(runs) == 1
    dims, _ = parameter_units.infer_dimensions(model)
    dims["mc"] = None  # the caller's copy: the remembered result is unchanged
    assert parameter_units.infer_dimensions(model)[0]["mc"] is not None and len(runs) == 2
    assert parameter_units.infer_dimensions(model)[0]["mc"] is not None and len(runs) == 2
    parameter_units.infer_dimensions(replaced(model, name="other"))
    assert len(runs) == 3


def test_the_library_never_applies_the_command_lines_km_h():
    """Issue 35 item 7: ``with_values({"v": "30"})`` gave 8.33 m/s; a bare speed is SI in
    the library (30 m/s), km/h only as typed after ``--set`` (the command's own rule)."""
    from express.cli import common
    from express.numeric.statespace import vehicle_model

    vehicle = vehicle_model(load_model(ROOT / "examples" / "forced-steering.toml"))
    assert vehicle.with_values({"v": "30"}).speed == 30.0
    assert vehicle.with_values({"v": "30 km/h"}).speed == pytest.approx(30 / 3.6)
    parser = __import__("argparse").ArgumentParser()
    common.add_model_arguments(parser)
    typed = parser.parse_args(["m.toml", "--set", "v=30"]).overrides
    assert vehicle.with_values(typed).speed == pytest.approx(30 / 3.6)


def test_parameter_bounds_are_the_ranges_a_file_is_checked_against():
    """The warm entry's bounds (express.model.parameter_ranges.parameter_bounds): the
    intersection of a parameter's uses, and a value just beyond one is what the file's
    range check refuses."""
    from express.model.parameter_ranges import parameter_bounds

    model = parse_toml_model(FORCED_TEXT, "f.toml")
    bounds = parameter_bounds(model)
    assert bounds["mc"] == (0.0, 1e8, False)
    assert bounds["kx1"] == (-1e15, 1e15, False)
    assert bounds["mu"] == (0.0, 1.0, True)
    assert bounds["Gamma"] == (0.0, 1.0, False)
    primary = [name for name in bounds if model.parameters[name].expression is None]
    assert len(primary) > 30
    for name in primary:
        low, high, _ = bounds[name]
        with pytest.raises(ModelError, match=rf"parameter {name}\b"):
            with_values(model, {name: high * 1.5 + 1.0})
        with pytest.raises(ModelError):  # named, or refused by the derivation it feeds first
            with_values(model, {name: low * 1.5 - 1.0})
