"""Substructures: the bundled cars written with a bogie substructure give the same
matrices as the flat description; the Python API gives the same model as the TOML
file; bad instances are refused with file:line, exit status 2 and no output."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import sympy as sp

from express.base.diagnostics import ModelError
from express.io import load_model, parse_toml_model
from express.model.records import Body, ConnectionPoint, Element, Ground
from express.model.substructures import Instance, Substructure, instantiate, with_instances
from express.rail.build import generate_vehicle

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))
import make_vehicles  # noqa: E402


def _same_equations(a, b) -> None:
    assert a.dofs == b.dofs and a.inputs == b.inputs and a.eliminated == b.eliminated
    assert a.parameters == b.parameters and a.values == b.values
    assert list(a.matrices) == list(b.matrices)
    for key in a.matrices:
        assert a.matrices[key] == b.matrices[key], key


@pytest.mark.parametrize("name, steered", [("forced-steering", True), ("conventional", False)])
@pytest.mark.parametrize("keep_virtual, with_rail", [(False, True), (True, False)])
def test_bundled_cars_give_the_matrices_of_the_flat_description(name, steered, keep_virtual, with_rail):
    """The flat writer (every item spelled out, as the files were before substructures)
    and the bundled file (car on one screen plus the bogie substructure)."""
    bundled = load_model(ROOT / "examples" / f"{name}.toml")
    assert "[instances.front]" in (ROOT / "examples" / f"{name}.toml").read_text()
    flat = parse_toml_model(make_vehicles.vehicle_toml(steered), "flat.toml")
    _same_equations(
        generate_vehicle(flat, keep_virtual=keep_virtual, with_rail=with_rail).equations,
        generate_vehicle(bundled, keep_virtual=keep_virtual, with_rail=with_rail).equations,
    )
    assert [b.id for b in bundled.bodies] == [b.id for b in flat.bodies]


def test_bundled_files_are_what_the_script_writes():
    for name, text in (("forced-steering", make_vehicles.car_toml(True)), ("conventional", make_vehicles.car_toml(False)),
                       ("forced-steering-yaw-bush", make_vehicles.car_toml(True, yaw_bush=True)),
                       ("conventional-yaw-bush", make_vehicles.car_toml(False, yaw_bush=True))):
        assert (ROOT / "examples" / f"{name}.toml").read_text(encoding="utf-8") == text, name


def test_the_whole_car_fits_on_one_screen():
    """Everything above the bogie substructure but the parameter table and the rail data."""
    text = (ROOT / "examples" / "forced-steering.toml").read_text()
    car = text[text.index("[bodies.CB]"): text.index("[rail]")]
    assert len(car.splitlines()) <= 45


# ------------------------------------------------------------------ Python API

AXLE = Substructure(
    "axle",
    parameters=("k",),
    connectors=("seat",),
    bodies=(Body("W", sp.Symbol("m"), (sp.S.Zero,) * 3, ("y",), (sp.Symbol("d"), sp.S.Zero, sp.S.Zero)),),
    grounds=(Ground("rail"),),
    points=(ConnectionPoint("box", "W", (sp.S.Zero,) * 3), ConnectionPoint("track", "rail", (sp.S.Zero, sp.S.One, sp.S.Zero))),
    elements=(Element("spring", sp.Symbol("k"), sp.S.Zero, "seat", "box", 1),
              Element("contact", sp.Symbol("kc"), sp.S.Zero, "box", "track", 1)),
)

AXLES_TOML = """
[bodies.F]
mass = "M"
dofs = ["y"]

[points.F_seat]
body = "F"

[substructures.axle]
parameters = ["k"]
connectors = ["seat"]

[substructures.axle.bodies.W]
mass = "m"
dofs = ["y"]
position = ["d", 0, 0]

[substructures.axle.grounds.rail]

[substructures.axle.points]
box = { body = "W" }
track = { body = "rail", offset = [0, 1, 0] }

[substructures.axle.elements]
spring = { from = "seat", to = "box", direction = "y", stiffness = "k" }
contact = { from = "box", to = "track", direction = "y", stiffness = "kc" }

[instances.one]
substructure = "axle"
prefix = "A_"
station = "s"
parameters = { k = "k1" }
connect = { seat = "F_seat" }

[instances.two]
substructure = "axle"
prefix = "B_"
station = "-s"
parameters = { k = "2*k1" }
connect = { seat = "F_seat" }
rename = { W = "Wrear" }
"""


def test_python_api_and_toml_agree():
    model = parse_toml_model(AXLES_TOML, "axles.toml")
    base = parse_toml_model(AXLES_TOML[: AXLES_TOML.index("[substructures.axle]")], "axles.toml")
    s, k1 = sp.symbols("s k1")
    built = with_instances(base, [AXLE], [
        Instance("one", "axle", prefix="A_", station=s, parameters={"k": k1}, connect={"seat": "F_seat"}),
        Instance("two", "axle", prefix="B_", station=-s, parameters={"k": 2 * k1}, connect={"seat": "F_seat"},
                 rename={"W": "Wrear"}),
    ])
    assert [b.id for b in model.bodies] == ["F", "A_W", "Wrear"] == [b.id for b in built.bodies]
    assert [g.id for g in model.grounds] == ["A_rail", "B_rail"]
    assert model.body("A_W").position[0] == sp.Symbol("d") + s
    assert model.point("B_track").offset == (-s, 1, 0)  # a ground point moves with the station
    _same_equations(generate_vehicle(model).equations, generate_vehicle(built).equations)
    eom = generate_vehicle(model).equations
    k1, kc = sp.symbols("k1 kc")
    assert sp.Matrix([[3 * k1, -k1, -2 * k1], [-k1, k1 + kc, 0], [-2 * k1, 0, 2 * k1 + kc]]) == eom.K
    assert eom.inputs == ("A_rail.y", "B_rail.y")


@pytest.mark.parametrize("change, message", [
    ("parameters = { k = \"k1\" }\n", 'substructure axle needs parameter "k"'),
    ("connect = { seat = \"F_seat\" }\n", 'substructure axle needs a model point for connector "seat"'),
])
def test_a_missing_mapping_is_refused_with_the_instance_line(change, message):
    text = AXLES_TOML.replace(change, "", 1)
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "axles.toml")
    line = text.splitlines().index("[instances.one]") + 1
    problems = [str(p) for p in error.value.problems]
    assert any(p.startswith(f"axles.toml:{line}: instance one: {message}") for p in problems), problems


@pytest.mark.parametrize("old, new, message", [
    ('substructure = "axle"\nprefix = "A_"', 'substructure = "axel"\nprefix = "A_"', 'unknown substructure "axel"'),
    ('parameters = { k = "k1" }', 'parameters = { k = "k1", q = 1 }', 'has no parameter "q"'),
    ('connect = { seat = "F_seat" }\n\n[instances.two]', 'connect = { seat = "F_seat", other = "F_seat" }\n\n[instances.two]',
     'has no connector "other"'),
    ('rename = { W = "Wrear" }', 'rename = { V = "Wrear" }', 'rename: substructure axle has no item "V"'),
])
def test_bad_instances_are_refused(old, new, message):
    assert old in AXLES_TOML
    with pytest.raises(ModelError) as error:
        parse_toml_model(AXLES_TOML.replace(old, new, 1), "axles.toml")
    problems = [str(p) for p in error.value.problems]
    assert any(message in p and p.startswith("axles.toml:") and p.split(":")[1].isdigit() for p in problems), problems


def test_every_problem_at_once():
    text = AXLES_TOML.replace('parameters = { k = "k1" }\n', "", 1).replace('parameters = { k = "2*k1" }\n', "", 1)
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "axles.toml")
    assert sum('needs parameter "k"' in str(p) for p in error.value.problems) == 2


def test_substructure_points_must_be_on_its_own_bodies():
    text = AXLES_TOML.replace('box = { body = "W" }', 'box = { body = "F" }')
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "axles.toml")
    assert any('(box of substructure' in p.item and 'is on "F"' in p.message for p in error.value.problems)


def test_problems_in_a_substructure_name_each_item_by_its_full_name():
    """A bad template element, instantiated twice: every problem names it as the model does
    (``A_contact``), with its local name after, never by its local name alone."""
    text = (AXLES_TOML.replace('direction = "y", stiffness = "kc"', 'direction = "q", stiffness = "kc +"')
            .replace('to = "box", direction = "y"', 'to = "bx", direction = "y"'))
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "axles.toml")
    items = sorted({(p.line, p.item) for p in error.value.problems})
    assert items == [
        (25, "TSD A_spring"),
        (25, "TSD A_spring (spring of substructure axle)"),
        (25, "TSD B_spring"),
        (25, "TSD B_spring (spring of substructure axle)"),
        (26, "TSD A_contact, B_contact (contact of substructure axle)"),
    ]
    assert all(p.item.split()[1].startswith(("A_", "B_")) for p in error.value.problems)  # no local name alone
    assert sum("got 'q'" in p.message for p in error.value.problems) == 1  # the template's problem, once
    assert sum('T_End "bx"' in p.message for p in error.value.problems) == 4  # per instance


def test_instantiate_reports_unknown_element_ends():
    bad = Substructure("s", elements=(Element("e", sp.S.One, sp.S.Zero, "nowhere", "nothing", 0),))
    _, problems = instantiate(bad, Instance("i", "s", prefix="I_"), "m.toml")
    assert [str(p) for p in problems] == [
        'm.toml: TSD I_e (e of substructure s): S_End "nowhere" is neither one of its substructure\'s points nor a connector',
        'm.toml: TSD I_e (e of substructure s): T_End "nothing" is neither one of its substructure\'s points nor a connector',
    ]


def test_a_bad_substructure_exits_2_without_output(tmp_path, capsys):
    from express.cli import main

    model = tmp_path / "axles.toml"
    model.write_text(AXLES_TOML.replace('parameters = { k = "k1" }\n', "", 1) + "\n[parameters]\nM = 1\nm = 1\nkc = 1\nk1 = 1\ns = 1\nd = 0\n")
    output = tmp_path / "out.json"
    status = main(["generate", str(model), "--format", "json", "-o", str(output)])
    assert status == 2
    assert not output.exists()
    err = capsys.readouterr().err
    assert f"{model}:" in err and 'needs parameter "k"' in err
