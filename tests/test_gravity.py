"""Gravity: static preloads of the full 3-D model and the geometric stiffness they give.

Closed forms of the issue (a body on two vertical springs below its centre; a
pendulum link), the car's roll terms in a model that keeps only lateral DOFs, refusals,
and an independent derivation: the exact potential energy with Cardan rotation
matrices (a coincident element between two bodies acting along its support's turned
axis), whose gradient must vanish at the computed equilibrium and whose Hessian must
be the generated K.
"""

from __future__ import annotations

import dataclasses
import itertools
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.assembly.generator import generate
from express.assembly.gravity import element_length, static_model
from express.assembly.gravity import static_preloads as preloads_of
from express.base.diagnostics import ModelError
from express.io import load_model, parse_toml_model
from express.rail.build import generate_vehicle


def static_preloads(model):
    """The static preloads of ``model`` (its 3-D static equations generated first)."""
    return preloads_of(model, generate(static_model(model)))



ROOT = Path(__file__).resolve().parents[1]
m, g, k, b, h, L, c, kl, J = sp.symbols("m g k b h L c kl J")

TWO_SPRINGS = """
[parameters]
m = 1000.0
k = 1e5
b = 1.0
h = 0.5
g = 9.81
J = 500.0

[gravity]
acceleration = "g"

[bodies.B]
mass = "m"
inertia = ["J", "J", "J"]
dofs = DOFS

[grounds.G]

[points.L]
body = "B"
offset = [0, "b", "-h"]

[points.R]
body = "B"
offset = [0, "-b", "-h"]

[points.GL]
body = "G"
offset = [0, "b", "-h"]

[points.GR]
body = "G"
offset = [0, "-b", "-h"]

[elements.left]
from = "L"
to = "GL"
direction = "z"
stiffness = "k"

[elements.right]
from = "R"
to = "GR"
direction = "z"
stiffness = "k"
"""


@pytest.mark.parametrize("dofs", ['["z", "rx"]', '["y", "z", "rx"]', '["rx"]'])
def test_body_on_two_springs_below_its_centre(dofs):
    """K[rx, rx] = 2 k b^2 - m g h exactly, whatever DOFs the dynamic model keeps."""
    model = parse_toml_model(TWO_SPRINGS.replace("DOFS", dofs), "two.toml")
    eom = generate(model).equations
    roll = eom.dofs.index("B.rx")
    assert sp.expand(eom.K[roll, roll] - (2 * k * b**2 - m * g * h)) == 0
    assert static_preloads(model) == {"left": -m * g / 2, "right": -m * g / 2}
    if "B.z" in eom.dofs:
        assert eom.K[eom.dofs.index("B.z"), eom.dofs.index("B.z")] == 2 * k
    if "B.y" in eom.dofs:  # zero-length vertical springs: no lateral stiffness
        assert all(eom.K[eom.dofs.index("B.y"), j] == 0 for j in range(len(eom.dofs)))


def test_without_gravity_nothing_changes():
    text = TWO_SPRINGS.replace("DOFS", '["z", "rx"]').replace('[gravity]\nacceleration = "g"\n', "")
    eom = generate(parse_toml_model(text, "two.toml")).equations
    assert sp.Matrix([[2 * k, 0], [0, 2 * k * b**2]]) == eom.K


PENDULUM = """
[parameters]
m = 500.0
kl = 1e8
L = 0.8
c = 0.3
g = 9.81
J = 50.0

[gravity]
acceleration = "g"

[bodies.B]
mass = "m"
inertia = ["J", "J", "J"]
dofs = DOFS

[grounds.G]

[points.top]
body = "G"
offset = [0, 0, "c + L"]

[points.pin]
body = "B"
offset = [0, 0, "c"]

[elements.link]
from = "top"
to = "pin"
direction = "z"
stiffness = "kl"
"""


def test_pendulum_link_gives_m_g_over_l():
    model = parse_toml_model(PENDULUM.replace("DOFS", '["y"]'), "pendulum.toml")
    assert element_length(model, model.elements[0]) == L
    assert static_preloads(model) == {"link": g * m}
    assert sp.Matrix([[g * m / L]]) == generate(model).equations.K


def test_pendulum_with_roll():
    """The body hangs from a point c above its centre: the link's string term acts on
    the pin's lateral motion y - c rx, the pin's height change on the roll."""
    model = parse_toml_model(PENDULUM.replace("DOFS", '["y", "rx"]'), "pendulum.toml")
    expected = sp.Matrix([[m * g / L, -m * g * c / L], [-m * g * c / L, m * g * c**2 / L + m * g * c]])
    assert (generate(model).equations.K - expected).applyfunc(sp.simplify) == sp.zeros(2, 2)


def test_a_car_that_keeps_only_lateral_dofs_gets_its_roll_terms():
    """Conventional car (lateral DOFs and roll): the air springs' load m_c g / 4 at
    h2 - hc below the body's centre and the bogies' loads give exactly the -m g h terms;
    the air springs act along their support's (the bogie's) axis, so each bogie also
    takes the couple of the car body's weight on the springs' relative lateral motion:
    with ``V = (m_c g / 2) T.rx du`` per bogie (two springs, each ``-N = m_c g / 4``,
    ``du = CB.y + x CB.rz - (h2 - hc) CB.rx - T.y + (h2 - ht) T.rx`` at the bogie's
    station ``x = +-lT``), written out here; the primary springs act along the
    wheelsets' axes, which do not roll in this model."""
    model = load_model(ROOT / "examples" / "conventional.toml")
    base = generate_vehicle(model).equations
    heavy = generate_vehicle(dataclasses.replace(model, gravity=sp.Symbol("g"))).equations
    assert heavy.dofs == base.dofs
    difference = heavy.K - base.K
    mc, mt, hc, h1, h2, ht, lT = sp.symbols("mc mt hc h1 h2 ht lT")
    expected = {("CB.rx", "CB.rx"): -mc * g * (hc - h2)}
    for bogie, station in (("T1", lT), ("T2", -lT)):
        couple = mc * g / 2
        relative = {"CB.y": 1, "CB.rz": station, "CB.rx": -(h2 - hc), f"{bogie}.y": -1}
        for dof, value in relative.items():
            expected[(f"{bogie}.rx", dof)] = expected[(dof, f"{bogie}.rx")] = couple * value
        # the load on top: -m g h as a point that rolls with the bogie, + 2 N' (h2 - ht)
        # of the support's turning axis; the primary springs' -m g h below it
        expected[(f"{bogie}.rx", f"{bogie}.rx")] = (-mc / 2 * g * (h2 - ht) + 2 * couple * (h2 - ht)
                                                    - (mc / 2 + mt) * g * (ht - h1))
    for i, j in itertools.product(range(len(base.dofs)), repeat=2):
        want = expected.get((base.dofs[i], base.dofs[j]), 0)
        assert sp.expand(difference[i, j] - want) == 0, (base.dofs[i], base.dofs[j], difference[i, j])


BODY_ON_BOGIE = """
[parameters]
g = 9.81

[gravity]
acceleration = "g"

[bodies.A]
mass = 30000.0
inertia = [50000.0, 1e6, 1e6]
dofs = ["y", "z", "rx"]
position = [0, 0, 1.8]

[bodies.B]
mass = 3000.0
inertia = [2000.0, 2000.0, 3000.0]
dofs = ["y", "z", "rx"]
position = [0, 0, 0.6]

[grounds.G]

[points]
AL = { body = "A", offset = [0, 1.0, -0.9] }
AR = { body = "A", offset = [0, -1.0, -0.9] }
AS = { body = "A", offset = [0, 0, -0.9] }
BL = { body = "B", offset = [0, 1.0, 0.3] }
BR = { body = "B", offset = [0, -1.0, 0.3] }
BS = { body = "B", offset = [0, 0, 0.3] }
BGL = { body = "B", offset = [0, 0.75, -0.6] }
BGR = { body = "B", offset = [0, -0.75, -0.6] }
BGS = { body = "B", offset = [0, 0, -0.6] }
GL = { body = "G", offset = [0, 0.75, 0] }
GR = { body = "G", offset = [0, -0.75, 0] }
GS = { body = "G", offset = [0, 0, 0] }

[elements]
sL = { from = "AL", to = "BL", direction = "z", stiffness = 4e5 }
sR = { from = "AR", to = "BR", direction = "z", stiffness = 4e5 }
sy = { from = "AS", to = "BS", direction = "y", stiffness = 3e5 }
gL = { from = "BGL", to = "GL", direction = "z", stiffness = 2e6 }
gR = { from = "BGR", to = "GR", direction = "z", stiffness = 2e6 }
gy = { from = "BGS", to = "GS", direction = "y", stiffness = 5e6 }
"""


def test_the_roll_moment_on_the_ground_is_that_of_the_loads():
    """A car body on two air springs on a bogie on two 'wheels' (springs to the ground at
    rail level): pushed sideways by ``m a`` on each body (a cant deficiency), the ground's
    roll moment about rail level equals ``sum m a h`` plus the weights' moment at the
    displaced centres, ``sum m g y``, to rounding.  It needs the air springs' couple
    ``N d`` (their ends shifted by ``d``) on the bogie: a track-fixed axis left it out
    (measured: 101.2 kN m against 130.6, the residual ``N d``)."""
    model = parse_toml_model(BODY_ON_BOGIE, "car.toml")
    eom = generate(model).equations
    number = {g: 9.81}
    stiffness = np.array(eom.K.subs(number), dtype=float)
    mass = {"A": 30000.0, "B": 3000.0}
    height = {"A": 1.8, "B": 0.6}
    accel = 1.0  # m/s^2 to the left
    force = np.zeros(len(eom.dofs))
    for body in mass:
        force[eom.dofs.index(f"{body}.y")] = mass[body] * accel
    q = np.linalg.solve(stiffness, force)
    y, z, rx = ({b: q[eom.dofs.index(f"{b}.{d}")] for b in mass} for d in ("y", "z", "rx"))
    load = (mass["A"] + mass["B"]) * 9.81 / 2  # each wheel's preload
    moment = 0.0  # the ground's forces on B about the rail-level axis, M = y F_z - z F_y
    for side in (1.0, -1.0):
        lateral = y["B"] + 0.6 * rx["B"]  # the wheel point, 0.6 m below B's centre
        change = -2e6 * (z["B"] + side * 0.75 * rx["B"])  # its change of the upward force
        moment += side * 0.75 * change + lateral * load
    loads = sum(mass[b] * (accel * height[b] + 9.81 * y[b]) for b in mass)
    assert moment == pytest.approx(loads, rel=1e-9)
    assert abs(9.81 * mass["A"] * (y["A"] + 0.9 * rx["A"] - y["B"] + 0.3 * rx["B"])) > 0.1 * loads  # N d is not small


def test_unsupported_weight_is_refused():
    text = TWO_SPRINGS.replace("DOFS", '["z"]').replace('direction = "z"', 'direction = "y"')
    with pytest.raises(ModelError) as error:
        generate(parse_toml_model(text, "two.toml"))
    message = str(error.value.problems[0])
    line = TWO_SPRINGS.splitlines().index("[bodies.B]") + 1
    assert message.startswith(f"two.toml:{line}: body B: gravity: no element carries its weight"), message


def test_gravity_section_is_checked():
    with pytest.raises(ModelError) as error:
        parse_toml_model(TWO_SPRINGS.replace("DOFS", '["z"]').replace('acceleration = "g"', 'accel = "g"'), "two.toml")
    messages = " ".join(str(p) for p in error.value.problems)
    assert 'unknown key "accel"' in messages and 'missing "acceleration"' in messages
    line = TWO_SPRINGS.splitlines().index("[gravity]") + 1
    assert f"two.toml:{line}: gravity" in messages


# ------------------------------------------------------------ independent derivation

SYSTEM = """
[parameters]
g = 9.81

[gravity]
acceleration = "g"

[bodies.A]
mass = 3000.0
inertia = [2500.0, 4000.0, 3500.0]
dofs = ["x", "y", "z", "rx", "ry", "rz"]
position = [0.3, 0.0, 1.6]

[bodies.B]
mass = 800.0
inertia = [300.0, 500.0, 450.0]
dofs = ["x", "y", "z", "rx", "ry", "rz"]
position = [0.0, 0.1, 0.6]

[bodies.C]
mass = 120.0
inertia = [8.0, 9.0, 10.0]
dofs = ["y", "z", "rx"]
position = [0.3, 0.0, 0.2]

[grounds.G]
"""


def _independent_system():
    """Three bodies: B on four unequal vertical springs (and lateral, longitudinal ones)
    on the ground, A on B by three vertical springs, a lateral link and a longitudinal
    spring, C hanging under A by a vertical link (a pendulum) with a lateral spring."""
    lines = [SYSTEM]
    count = itertools.count()

    def element(s_body, s_offset, t_body, t_offset, axis, stiffness):
        i = next(count)
        lines.append(f'[points.S{i}]\nbody = "{s_body}"\noffset = {[round(float(v), 12) for v in s_offset]}\n')
        lines.append(f'[points.T{i}]\nbody = "{t_body}"\noffset = {[round(float(v), 12) for v in t_offset]}\n')
        lines.append(f'[elements.E{i}]\nfrom = "S{i}"\nto = "T{i}"\ndirection = "{axis}"\nstiffness = {stiffness}\n')

    b_pos, a_pos = np.array([0.0, 0.1, 0.6]), np.array([0.3, 0.0, 1.6])
    for (x, y), kz in zip([(1.2, 0.9), (1.2, -0.9), (-1.2, 0.9), (-1.2, -0.9)], [1.1e6, 0.9e6, 1.0e6, 1.3e6], strict=True):
        offset = (x, y, -0.2)
        ground = tuple(b_pos + np.array(offset))
        element("B", offset, "G", ground, "z", kz)
        element("B", offset, "G", ground, "y", 4e5)
        element("B", offset, "G", ground, "x", 6e5)
    for (x, y), kz in zip([(0.5, 1.0), (0.4, -1.0), (-0.9, 0.2)], [3e5, 4e5, 2.5e5], strict=True):
        offset = (x, y, -0.6)
        on_b = tuple(a_pos + np.array(offset) - b_pos)
        element("A", offset, "B", on_b, "z", kz)
        element("A", offset, "B", on_b, "x", 2e5)
    # lateral link (Panhard rod) 0.8 m long along y: A at (0, 0.5, -0.7), B 0.8 m to the right
    element("A", (0.0, 0.5, -0.7), "B", tuple(a_pos + np.array([0.0, 0.5 - 0.8, -0.7]) - b_pos), "y", 5e6)
    # pendulum: C hangs from A by a link 0.5 m long, pinned 0.1 m above C's centre
    c_pos = np.array([0.3, 0.0, 0.2])
    element("A", tuple(c_pos + np.array([0.0, 0.0, 0.6]) - a_pos), "C", (0.0, 0.0, 0.1), "z", 2e7)
    element("A", tuple(c_pos + np.array([0.0, 0.0, 0.1]) - a_pos), "C", (0.0, 0.0, 0.1), "y", 1e4)
    return "\n".join(lines)


def _cardan(rx, ry, rz):
    """R = Rz Ry Rx with cos and sin to second order (all the Hessian at 0 needs)."""
    cx, cy, cz = (1 - a**2 / 2 for a in (rx, ry, rz))
    sx, sy, sz = rx, ry, rz
    return (sp.Matrix([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]]) * sp.Matrix([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
            * sp.Matrix([[1, 0, 0], [0, cx, -sx], [0, sx, cx]]))


def test_generated_stiffness_is_the_hessian_of_the_exact_potential():
    model = parse_toml_model(_independent_system(), "system.toml")
    preloads = static_preloads(model)
    values = model.values()
    number = {s: values[s.name] for s in [g]}
    coordinates = {}
    position = {}
    for body in model.bodies:
        q = {d: (sp.Symbol(f"{body.id}_{d}") if d in body.dofs else sp.S.Zero) for d in ("x", "y", "z", "rx", "ry", "rz")}
        coordinates.update({f"{body.id}.{d}": q[d] for d in body.dofs})
        centre = sp.Matrix([float(v) for v in body.position]) + sp.Matrix([q["x"], q["y"], q["z"]])
        position[body.id] = (centre, _cardan(q["rx"], q["ry"], q["rz"]))

    def where(point_id):
        point = model.point(point_id)
        offset = sp.Matrix([float(v) for v in point.offset])
        if point.host not in position:
            return offset
        centre, rotation = position[point.host]
        return centre + rotation * offset

    symbols = list(coordinates.values())
    t = sp.Symbol("t")

    def orders(expression):
        """Terms of degree 0, 1 and 2 in the coordinates of a polynomial."""
        poly = sp.Poly(sp.expand(expression.xreplace({s: t * s for s in symbols})), t)
        return [poly.coeff_monomial(t**d) for d in range(3)]

    energy = sum(float(body.mass) * number[g] * position[body.id][0][2] for body in model.bodies)
    for element in model.elements:
        d = where(element.s_end) - where(element.t_end)
        length = float(element_length(model, element))
        hosts = [model.point(end).host for end in (element.s_end, element.t_end)]
        if length == 0 and all(host in position for host in hosts):
            # coincident ends on two bodies: the axis is the lower body's (the support)
            support = min(hosts, key=lambda host: float(model.body(host).position[2]))
            axis = position[support][1][:, element.direction]
            _, first, second = orders(axis.dot(d))
        elif length == 0:
            _, first, second = orders(d[element.direction])
        else:  # sign(L) sqrt(P0 + P1 + P2) to second order
            p0, p1, p2 = orders(sum(component**2 for component in d))
            root = sp.sqrt(p0)
            first = np.sign(length) * p1 / (2 * root)
            second = np.sign(length) * (p2 / (2 * root) - p1**2 / (8 * root**3))
        stretch = first + second
        force = float(preloads.get(element.id, sp.S.Zero).subs(number))
        energy += force * stretch + float(element.stiffness) / 2 * first**2
    energy = sp.expand(energy)
    zero = dict.fromkeys(symbols, 0)
    gradient = [float(sp.diff(energy, s).subs(zero)) for s in symbols]
    assert max(abs(x) for x in gradient) < 1e-6 * 3000 * 9.81  # the computed equilibrium
    eom = generate(model).equations
    stiffness = np.array(eom.K.subs(number), dtype=float)
    assert len(preloads) == 8  # the seven vertical springs and the pendulum link
    for i, j in itertools.product(range(len(eom.dofs)), repeat=2):
        exact = float(sp.diff(energy, coordinates[eom.dofs[i]], coordinates[eom.dofs[j]]).subs(zero))
        assert stiffness[i, j] == pytest.approx(exact, rel=1e-9, abs=1e-6 * np.abs(stiffness).max()), (
            eom.dofs[i], eom.dofs[j])
