"""Conicity and contact terms from profiles in a model (express.io.toml_contact,
express.rail.profile_contact): the "profiles" derivation node of the parameter graph,
its results, re-evaluation on overrides, the linear terms it adds, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.base.diagnostics import ModelError
from express.io.toml_contact import PROFILE_INPUTS, PROFILE_OUTPUTS
from express.io.toml_model import parse_toml_model
from express.model.parameters import with_values
from express.numeric.statespace import vehicle_model
from express.rail import profile_contact
from express.rail.conicity import conicity_from_profiles
from express.rail.contact_geometry import ContactSetup
from express.rail.contact_tables import contact_tables, linear_contact_parameters
from express.rail.profiles import standard_profile

#: A wheelset held by lateral and longitudinal springs to the ground: the smallest rail
#: vehicle (used by tests/test_nonlinear_critical_speed.py too).
WHEELSET = """
[model]
name = "wheelset"

[parameters]
mw = { value = 1500, unit = "kg" }
Iwz = { value = 700, unit = "kg*m^2" }
ky = { value = 1.0, unit = "MN/m" }
kx = { value = 5.0, unit = "MN/m" }
d = { value = 1.0, unit = "m" }
r0 = { value = 0.46, unit = "m" }
b = { value = 0.75, unit = "m" }
Q = { value = 50, unit = "kN" }
mu = { value = 0.3, unit = "1" }
kR = { value = 20, unit = "MN/m" }
v = { value = 30, unit = "m/s" }
G = { value = 1.5, unit = "m" }
A = { value = 3, unit = "mm" }

[bodies.W1]
mass = "mw"
inertia = [0, 0, "Iwz"]
dofs = ["y", "rz"]
position = [0, 0, "r0"]

[grounds.G1]

[points]
WL = { body = "W1", offset = [0, "d", 0] }
WR = { body = "W1", offset = [0, "-d", 0] }
GL = { body = "G1", offset = [0, "d", 0] }
GR = { body = "G1", offset = [0, "-d", 0] }

[elements]
yL = { from = "GL", to = "WL", direction = "y", stiffness = "ky/2" }
yR = { from = "GR", to = "WR", direction = "y", stiffness = "ky/2" }
xL = { from = "GL", to = "WL", direction = "x", stiffness = "kx" }
xR = { from = "GR", to = "WR", direction = "x", stiffness = "kx" }

[rail]
speed = "v"
cant_base = "G"
wheelsets = ["W1"]

[rail.wheel_rail]
f1 = "Gamma_e_f11"
f2 = "Gamma_e_f22"
conicity = { from = "profiles", wheel = "S1002", rail = "60E1", inclination = "1:40", gauge = "1435 mm", flange_back = "1360 mm", amplitude = "A" }
r0 = "r0"
b = "b"
flange_clearance = 0.007
rail_stiffness = "kR"
friction = "mu"
wheel_load = "Q"
"""


@pytest.fixture(scope="module")
def model():
    return parse_toml_model(WHEELSET, "wheelset.toml")


def test_reader_and_rail_layer_share_one_definition_of_the_node():
    assert profile_contact.INPUTS is PROFILE_INPUTS
    assert profile_contact.OUTPUTS is PROFILE_OUTPUTS


def test_results_of_the_node(model):
    values = model.values()
    # EN 15302 at 3 mm, computed independently from the profiles (the colleague's path)
    tan_gamma, _ = conicity_from_profiles(standard_profile("S1002"), standard_profile("60E1"), 3e-3, ContactSetup())
    assert values["Gamma_e"] == pytest.approx(tan_gamma, abs=2e-3)
    tables = contact_tables(standard_profile("S1002"), standard_profile("60E1"), ContactSetup())
    linear = linear_contact_parameters(tables, 3e-3)
    assert values["Gamma_e_epsilon"] == pytest.approx(linear.epsilon, rel=1e-12)
    assert values["Gamma_e_sigma"] == pytest.approx(linear.sigma, rel=1e-12)
    assert values["Gamma_e_l0"] == pytest.approx(0.7532, abs=1e-4)  # CONTACT: 751.9 mm from the track centre
    # the linearised wheelset's terms (docs/contact.md)
    c2 = math.cos(linear.delta0) ** 2
    lateral = (2 * 50e3 * linear.epsilon / (linear.half_distance * c2)
               - 2 * values["Gamma_e_f23"] * (linear.epsilon / c2 - linear.sigma) / (linear.half_distance * linear.radius))
    assert values["Gamma_e_ky"] == pytest.approx(lateral, rel=1e-12)
    assert 0 < values["Gamma_e_ky"] < 2 * 50e3 * linear.epsilon / linear.half_distance  # spin takes a part
    assert values["Gamma_e_kpsi"] < 0  # the gravitational yaw stiffness destabilises


def test_linear_model_holds_the_terms(model):
    vehicle = vehicle_model(model)
    values = model.values()
    y, psi = vehicle.dof_index("W1.y"), vehicle.dof_index("W1.rz")
    springs = 1e6  # ky
    assert vehicle.stiffness[y, y] == pytest.approx(springs + values["Gamma_e_ky"], rel=1e-12)
    inputs = list(vehicle.inputs)
    assert vehicle.forcing_base[y, inputs.index("W1.yR")] == pytest.approx(values["Gamma_e_ky"], rel=1e-12)
    f2 = values["Gamma_e_f22"]
    assert vehicle.damping_creep[y, y] == pytest.approx(2 * f2 * values["Gamma_e_gy"], rel=1e-12)
    assert vehicle.damping_creep[y, psi] == pytest.approx(2 * values["Gamma_e_f23"], rel=1e-12)
    assert vehicle.stiffness[y, psi] == pytest.approx(-2 * f2 * values["Gamma_e_g"], rel=1e-12)


def test_overrides_re_evaluate_the_node(model):
    smaller = with_values(model, {"A": "1 mm"})
    assert smaller.parameters["Gamma_e"].value == pytest.approx(0.356, abs=2e-3)  # docs/contact.md table
    heavier = with_values(model, {"Q": "60 kN"})
    assert heavier.parameters["Gamma_e"].value == model.parameters["Gamma_e"].value
    ratio = heavier.parameters["Gamma_e_f11"].value / model.parameters["Gamma_e_f11"].value
    assert ratio == pytest.approx(1.2 ** (2 / 3), rel=1e-9)  # a b grows as N^(2/3)
    vehicle = vehicle_model(model).with_values({"A": "2 mm"})
    assert vehicle.wheelsets[0].conicity == pytest.approx(0.221, abs=2e-3)


def test_profile_file_relative_to_the_model(tmp_path):
    wheel = standard_profile("S1002")
    folder = tmp_path / "profiles"
    folder.mkdir()
    (folder / "wheel.csv").write_text("y_mm,z_mm\n" + "".join(f"{a * 1e3:.9f},{b * 1e3:.9f}\n"
                                                              for a, b in zip(wheel.y, wheel.z, strict=True)))
    text = WHEELSET.replace('wheel = "S1002"', 'wheel = "profiles/wheel.csv"')
    path = tmp_path / "model.toml"
    path.write_text(text)
    from express.io import load_model

    loaded = load_model(path)
    assert loaded.parameters["Gamma_e"].value == pytest.approx(parse_toml_model(WHEELSET).parameters["Gamma_e"].value,
                                                               rel=1e-9)
    node = profile_contact.profile_nodes(loaded)["W1"]
    assert dict(node.settings)["wheel"] == "profiles/wheel.csv"


def test_bad_profile_file_names_its_line(tmp_path):
    (tmp_path / "wheel.csv").write_text("y_mm,z_mm\n-70,10\n-60,nan\n0,0\n")
    path = tmp_path / "model.toml"
    path.write_text(WHEELSET.replace('wheel = "S1002"', 'wheel = "wheel.csv"'))
    from express.io import load_model

    with pytest.raises(ModelError) as error:
        load_model(path)
    messages = " ".join(str(p) for p in error.value.problems)
    assert "wheel.csv:3" in messages and "finite" in messages


def test_per_wheelset_node_and_shared_default():
    text = WHEELSET.replace('wheel_load = "Q"', 'wheel_load = "Q"\n\n[rail.wheelset.W1]\n'
                            'conicity = { from = "profiles", wheel = "S1002", rail = "60E1", inclination = "1:20" }')
    loaded = parse_toml_model(text)
    assert "Gamma_e_W1" in loaded.parameters and "Gamma_e" not in loaded.parameters
    assert loaded.parameters["Gamma_e_W1"].value == pytest.approx(0.009, abs=2e-3)  # 1:20, docs/contact.md


@pytest.mark.parametrize("change, mention", [
    ('amplitude = "A" }', 'amplitude = "A", colour = "red" }'),
    ('from = "profiles"', 'from = "table"'),
    ('inclination = "1:40"', 'inclination = "1:x"'),
    ('gauge = "1435 mm"', 'gauge = "1435 kg"'),
    ('wheel = "S1002", ', ''),
])
def test_bad_specifications(change, mention):
    text = WHEELSET.replace(change, mention)
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "wheelset.toml")
    problem = error.value.problems[0]
    assert problem.file == "wheelset.toml" and problem.line is not None
    assert "conicity" in problem.item


def test_every_problem_at_once():
    text = WHEELSET.replace('from = "profiles"', 'from = "table"').replace('gauge = "1435 mm"', 'gauge = "1435 kg"')
    with pytest.raises(ModelError) as error:
        parse_toml_model(text, "wheelset.toml")
    assert len(error.value.problems) >= 2


def test_node_in_the_parameter_graph(model):
    node = profile_contact.profile_nodes(model)["W1"]
    assert node.kind == "profiles" and node.line is not None
    assert dict(node.settings)["wheel"] == "S1002"
    assert {name for _, name, _ in node.outputs} <= set(model.parameters)
    assert all(model.parameters[name].derived_by == node.item for _, name, _ in node.outputs)
    assert np.isfinite([model.parameters[name].value for _, name, _ in node.outputs]).all()
