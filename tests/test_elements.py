"""Rotational elements (``direction = "rx" | "ry" | "rz"``): closed forms and refusals.

A rotational element acts on the relative rotation ``theta_S - theta_T`` of the bodies
holding its two CPs about its axis; its energy is ``k/2 (theta_S - theta_T)^2`` and its
dissipation ``c/2 (theta_S' - theta_T')^2`` whatever the CPs' offsets.
"""

from __future__ import annotations

import pytest
import sympy as sp

from express.assembly.generator import generate
from express.base.diagnostics import ModelError
from express.io import parse_toml_model

k, c, J1, J2, m, kb, hb, b = sp.symbols("k c J1 J2 m kb hb b")


def _model(text: str, name: str = "rot.toml"):
    return parse_toml_model(text, name)


TWO_BODIES = """
[parameters]
k = 1.0
c = 2.0
J1 = 3.0
J2 = 4.0

[bodies.B1]
inertia = ["J1", 0, 0]
dofs = ["rx"]

[bodies.B2]
inertia = ["J2", 0, 0]
dofs = ["rx"]

[points.C1]
body = "B1"
offset = [1.5, -0.3, 2.0]      # offsets do not matter for a rotational element

[points.C2]
body = "B2"
offset = [-4, 0.7, 0]

[elements.bar]
from = "C1"
to = "C2"
direction = "rx"
stiffness = "k"
damping = "c"
"""


def test_anti_roll_bar_between_two_bodies():
    eom = generate(_model(TWO_BODIES)).equations
    assert eom.dofs == ("B1.rx", "B2.rx")
    assert sp.Matrix([[k, -k], [-k, k]]) == eom.K
    assert sp.Matrix([[c, -c], [-c, c]]) == eom.C
    assert sp.Matrix([[J1, 0], [0, J2]]) == eom.M
    assert eom.inputs == ()


@pytest.mark.parametrize("axis, inertia", [("rx", '["J1", 0, 0]'), ("ry", '[0, "J1", 0]'), ("rz", '[0, 0, "J1"]')])
def test_rotational_spring_to_a_ground_is_driven_by_the_ground_rotation(axis, inertia):
    text = f"""
[bodies.B1]
inertia = {inertia}
dofs = ["{axis}", "x", "y", "z"]

[grounds.G1]

[points.C1]
body = "B1"
offset = [0.4, 0.5, 0.6]

[points.G]
body = "G1"

[elements.pivot]
from = "C1"
to = "G"
direction = "{axis}"
stiffness = "k"
damping = "c"
"""
    eom = generate(_model(text)).equations
    row = eom.dofs.index(f"B1.{axis}")
    expected_k = sp.zeros(4, 4)
    expected_k[row, row] = k
    assert expected_k == eom.K
    assert eom.inputs == (f"G1.{axis}",)
    # M q'' + C q' + K q = P u + Pd u':  k (theta_G - theta) and c (theta_G' - theta')
    assert eom.matrices["P"][row, 0] == k and eom.matrices["Pd"][row, 0] == c
    assert sum(abs(eom.matrices["P"][i, 0]) for i in range(4) if i != row) == 0


def test_rotational_and_translational_elements_add():
    """A body of mass m on two vertical springs kb at +-b plus an anti-roll bar k:
    roll stiffness 2 kb b^2 + k (closed form)."""
    text = """
[bodies.B]
mass = "m"
inertia = ["J1", 0, 0]
dofs = ["z", "rx"]

[grounds.G]

[points.L]
body = "B"
offset = [0, "b", "-hb"]

[points.R]
body = "B"
offset = [0, "-b", "-hb"]

[points.GL]
body = "G"
offset = [0, "b", 0]

[points.GR]
body = "G"
offset = [0, "-b", 0]

[elements.springL]
from = "L"
to = "GL"
direction = "z"
stiffness = "kb"

[elements.springR]
from = "R"
to = "GR"
direction = "z"
stiffness = "kb"

[elements.bar]
from = "L"
to = "GL"
direction = "rx"
stiffness = "k"
"""
    eom = generate(_model(text)).equations
    assert eom.dofs == ("B.z", "B.rx")
    assert sp.Matrix([[2 * kb, 0], [0, 2 * kb * b**2 + k]]) == eom.K


def test_bogie_rotational_stiffness_in_a_vehicle_frame():
    """Secondary yaw stiffness between car body and bogie: k (psi_B - psi_T)^2 / 2."""
    text = TWO_BODIES.replace('"rx"', '"rz"').replace('["J1", 0, 0]', '[0, 0, "J1"]').replace(
        '["J2", 0, 0]', '[0, 0, "J2"]'
    )
    eom = generate(_model(text)).equations
    assert eom.dofs == ("B1.rz", "B2.rz")
    assert sp.Matrix([[k, -k], [-k, k]]) == eom.K


@pytest.mark.parametrize(
    "dofs1, dofs2, missing",
    [('["rz"]', '["rx"]', ["B1", "rx"]), ('["rx"]', '["y"]', ["B2", "rx"]), ('["y"]', '["z"]', ["B1", "B2"])],
)
def test_rotational_element_on_a_body_without_that_rotation_is_refused(dofs1, dofs2, missing):
    first, second = TWO_BODIES.split("[bodies.B2]")
    text = first.replace('dofs = ["rx"]', f"dofs = {dofs1}") + "[bodies.B2]" + second.replace(
        'dofs = ["rx"]', f"dofs = {dofs2}"
    )
    with pytest.raises(ModelError) as error:
        _model(text)
    messages = [str(p) for p in error.value.problems]
    line = TWO_BODIES.splitlines().index("[elements.bar]") + 1
    assert all(f"rot.toml:{line}: TSD bar" in message for message in messages), messages
    assert all(word in " ".join(messages) for word in missing), messages
    assert all("rotational element about rx" in message for message in messages)


def test_unknown_direction_names_the_choices():
    with pytest.raises(ModelError) as error:
        _model(TWO_BODIES.replace('direction = "rx"', 'direction = "rw"'))
    assert "rx, ry or rz" in str(error.value.problems[0])


def test_a_pin_cannot_use_a_rotational_element():
    text = """
[bodies.B1]
mass = 1
inertia = [1, 1, 1]
dofs = ["x", "rx"]

[bodies.B2]
mass = 1
dofs = ["x"]

[points.C1]
body = "B1"

[points.C2]
body = "B2"

[elements.T]
from = "C1"
to = "C2"
direction = "rx"
stiffness = "k"

[pins.P]
virtual = "C1"
non_virtual = "C2"
"""
    with pytest.raises(ModelError) as error:
        _model(text)
    assert any("plain translational element" in str(p) for p in error.value.problems)
