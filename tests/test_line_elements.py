"""Elements along any line (``direction = [dx, dy, dz]`` or ``"line"``) and the preload's
geometric stiffness (issue 31, item 3; :mod:`express.assembly.lines`).

Independent checks: the pendulum's closed form ``sqrt(g/L)``; an inclined spring's and
damper's ``k n n^T`` and ``c n n^T`` built here from the ends' offsets with
``u = t + theta x r``; rigid motion gives no force; and the exact potential energy of a
body on chevron springs with a pendulum on an inclined link (exact lengths
``|p_S(q) - p_T(q)|``, Cardan rotations), whose gradient must vanish at the computed
equilibrium and whose Hessian must be the generated K.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp

from cli_support import assert_input_error
from express.assembly.generator import generate
from express.assembly.gravity import static_model
from express.assembly.gravity import static_preloads as preloads_of
from express.base.diagnostics import ModelError
from express.io import parse_toml_model
from express.io.toml_writer import model_to_toml
from test_gravity import _cardan

m, g, length, k, c, a, b = sp.symbols("m g l k c a b")

PENDULUM = """
[parameters]
m = "1000 kg"
l = "0.5 m"
k = "1e9 N/m"
g = "9.81 m/s^2"
{gravity}
[bodies.B]
mass = "m"
inertia = [1, 1, 1]
dofs = ["x", "y", "z"]

[grounds.G]

[points.top]
body = "G"
offset = [0, 0, "l"]

[points.bob]
body = "B"
offset = [0, 0, 0]

[elements.link]
from = "bob"
to = "top"
direction = {direction}
stiffness = "k"
{preload}
"""


@pytest.mark.parametrize(("direction", "gravity", "preload"), [
    ('"line"', '[gravity]\nacceleration = "g"\n', ""),  # the preload from the static equilibrium
    ("[0, 0, -1]", '[gravity]\nacceleration = "g"\n', ""),
    ('"line"', "", 'preload = "m*g"'),  # a given tension, no [gravity]
])
def test_pendulum_on_a_preloaded_link_swings_at_sqrt_g_over_l(direction, gravity, preload):
    model = parse_toml_model(PENDULUM.format(direction=direction, gravity=gravity, preload=preload), "p.toml")
    eom = generate(model).equations
    assert eom.dofs == ("B.x", "B.y", "B.z")
    assert sp.simplify(eom.K - sp.diag(g * m / length, g * m / length, k)) == sp.zeros(3, 3)
    values = model.values()
    stiffness = np.array(eom.K.subs(values), dtype=float)
    mass = np.array(eom.M.subs(values), dtype=float)
    omega = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(mass, stiffness)).real))
    expected = np.sqrt(values["g"] / values["l"])
    assert omega[:2] == pytest.approx([expected, expected], rel=1e-13)  # achieved: < 3e-16


TWO_BODIES = """
[parameters]
k = "2e6 N/m"
c = "3e4 N*s/m"
a = 0.3
b = -0.7

[bodies.A]
mass = 100
inertia = [10, 20, 30]
dofs = ["x", "y", "z", "rx", "ry", "rz"]
position = [0, 0, 1]

[bodies.B]
mass = 200
inertia = [11, 21, 31]
dofs = ["x", "y", "z", "rx", "ry", "rz"]
position = [1, 0, 0]

[points.SA]
body = "A"
offset = [0.4, "a", -0.2]

[points.TB]
body = "B"
offset = [-0.1, 0.5, "b"]

[elements.skew]
from = "SA"
to = "TB"
direction = {direction}
stiffness = "k"
damping = "c"
"""


def _point_rows(position, offset, body_index):
    """du = G q over the 12 DOFs (A then B, x y z rx ry rz): u = t + theta x r."""
    r = sp.Matrix(offset)
    rows = sp.zeros(3, 12)
    for i in range(3):
        rows[i, 6 * body_index + i] = 1
    for j in range(3):  # theta_j e_j x r
        e = sp.zeros(3, 1)
        e[j] = 1
        column = e.cross(r)
        for i in range(3):
            rows[i, 6 * body_index + 3 + j] = column[i]
    return rows


@pytest.mark.parametrize("direction", ['["a", 2, "b"]', "[1, 0, 1]", '"line"'])
def test_inclined_spring_and_damper_are_k_n_nT_and_c_n_nT(direction):
    model = parse_toml_model(TWO_BODIES.format(direction=direction), "two.toml")
    eom = generate(model).equations
    s_offset, t_offset = (sp.Integer(2) / 5, a, -sp.Integer(1) / 5), (-sp.Integer(1) / 10, sp.Integer(1) / 2, b)
    relative = _point_rows((0, 0, 1), s_offset, 0) - _point_rows((1, 0, 0), t_offset, 1)
    if direction == '"line"':  # p_S - p_T from the positions and offsets
        v = sp.Matrix([0 + s_offset[0] - 1 - t_offset[0], s_offset[1] - t_offset[1], 1 + s_offset[2] - t_offset[2]])
    else:
        v = sp.Matrix({'["a", 2, "b"]': [a, 2, b], "[1, 0, 1]": [1, 0, 1]}[direction])
    n = v / sp.sqrt(v.dot(v))
    gradient = n.T * relative  # the deflection n . (u_S - u_T) over q
    for symbolic, value in ((eom.K, k), (eom.C, c)):
        expected = value * gradient.T * gradient
        assert (symbolic - expected).applyfunc(sp.simplify) == sp.zeros(12, 12)
    # a rigid motion of both bodies (the line joins the ends: n . (theta x d) = 0) deflects nothing
    if direction == '"line"':
        rigid = []
        axes = [sp.eye(3)[:, i] for i in range(3)]
        for theta in axes:
            q = []
            for centre in ((0, 0, 1), (1, 0, 0)):
                q += list(sp.Matrix(theta).cross(sp.Matrix(centre))) + list(theta)
            rigid.append(sp.Matrix(q))
        rigid += [sp.Matrix(list(t) + [0, 0, 0] + list(t) + [0, 0, 0]) for t in axes]
        for q in rigid:
            assert (eom.K * q).applyfunc(sp.simplify) == sp.zeros(12, 1)
            assert (eom.C * q).applyfunc(sp.simplify) == sp.zeros(12, 1)


CHEVRON = """
[parameters]
g = 9.81

[gravity]
acceleration = "g"

[bodies.B]
mass = 800.0
inertia = [60.0, 70.0, 90.0]
dofs = ["x", "y", "z", "rx", "ry", "rz"]
position = [0.1, -0.05, 0.6]

[bodies.C]
mass = 150.0
inertia = [8.0, 9.0, 10.0]
dofs = ["x", "y", "z", "rx", "ry", "rz"]
position = [0.2, 0.1, -0.1]

[grounds.G]
"""


def _chevron_system():
    """B on four inclined (chevron) springs and two skew lateral ones on the ground, C
    hung below B on an inclined link and five skew springs: every element along "line"."""
    lines = [CHEVRON]
    count = itertools.count()

    def element(s_body, s_offset, t_body, t_offset, stiffness, damping=0.0):
        i = next(count)
        lines.append(f'[points.S{i}]\nbody = "{s_body}"\noffset = {list(s_offset)}\n')
        lines.append(f'[points.T{i}]\nbody = "{t_body}"\noffset = {list(t_offset)}\n')
        lines.append(f'[elements.E{i}]\nfrom = "S{i}"\nto = "T{i}"\ndirection = "line"\n'
                     f"stiffness = {stiffness}\ndamping = {damping}\n")

    for (x, y), kz in zip([(1.2, 0.9), (1.2, -0.9), (-1.2, 0.9), (-1.2, -0.9)], [1.1e6, 0.9e6, 1.0e6, 1.3e6],
                          strict=True):
        lean = 0.25 if x > 0 else -0.2
        element("B", (x, y, -0.2), "G", (0.1 + x + lean, -0.05 + y + 0.1 * y, 0.0), kz, 1e4)
    element("B", (0.0, 1.0, 0.0), "G", (0.3, 1.9, 0.5), 3e5)
    element("B", (0.5, -1.0, 0.1), "G", (0.4, -1.9, 0.9), 2e5)
    # C's link: from C (0.1 above its centre) up and aside to B
    element("C", (0.0, 0.0, 0.1), "B", (0.25, 0.3, -0.3), 2e7)
    element("C", (0.1, 0.0, 0.0), "B", (0.4, -0.5, -0.5), 1e4)
    element("C", (0.0, 0.1, 0.0), "B", (-0.3, 0.6, -0.6), 2e4)
    element("C", (0.3, -0.2, 0.05), "B", (0.9, -0.1, -0.4), 3e4)
    element("C", (-0.3, 0.2, -0.05), "B", (-0.6, 0.9, -0.2), 2.5e4)
    element("C", (0.2, 0.3, 0.1), "B", (0.5, 0.2, -0.9), 1.5e4)
    return "\n".join(lines)


def test_line_elements_stiffness_is_the_hessian_of_the_exact_potential():
    """Gravity's preloads on lines and their geometric stiffness against the exact
    potential: ``sum m g z + sum (N stretch + k/2 first^2)`` with the exact length."""
    model = parse_toml_model(_chevron_system(), "chevron.toml")
    preloads = preloads_of(model, generate(static_model(model)))
    assert len(preloads) == 12
    coordinates, position = {}, {}
    for body in model.bodies:
        q = {d: sp.Symbol(f"{body.id}_{d}") for d in ("x", "y", "z", "rx", "ry", "rz")}
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
        poly = sp.Poly(sp.expand(expression.xreplace({s: t * s for s in symbols})), t)
        return [poly.coeff_monomial(t**d) for d in range(3)]

    energy = sum(float(body.mass) * 9.81 * position[body.id][0][2] for body in model.bodies)
    for element in model.elements:
        p0, p1, p2 = orders(sum(x**2 for x in where(element.s_end) - where(element.t_end)))
        root = sp.sqrt(p0)
        first, second = p1 / (2 * root), p2 / (2 * root) - p1**2 / (8 * root**3)
        force = float(preloads.get(element.id, sp.S.Zero).subs(model.values()))
        energy += force * (first + second) + float(element.stiffness) / 2 * first**2
    energy = sp.expand(energy)
    zero = dict.fromkeys(symbols, 0)
    gradient = [float(sp.diff(energy, s).subs(zero)) for s in symbols]
    assert max(abs(x) for x in gradient) < 1e-12 * 950 * 9.81  # the computed equilibrium; achieved 1.4e-11 N
    eom = generate(model).equations
    stiffness = np.array(eom.K.subs(model.values()), dtype=float)
    scale = np.abs(stiffness).max()
    worst = 0.0
    for i, j in itertools.product(range(len(eom.dofs)), repeat=2):
        exact = float(sp.diff(energy, coordinates[eom.dofs[i]], coordinates[eom.dofs[j]]).subs(zero))
        worst = max(worst, abs(stiffness[i, j] - exact) / scale)
    print(f"worst {worst:.2e} of {scale:.3e}; gradient {max(abs(x) for x in gradient):.2e}")
    assert worst < 1e-13  # achieved: 2.0e-16 of the largest entry (1.7e7 N/m)


def test_a_line_element_survives_writing_and_reading():
    model = parse_toml_model(TWO_BODIES.format(direction='["a", 2, "b"]'), "two.toml")
    text = model_to_toml(model)
    assert 'direction = ["a", 2, "b"]' in text
    again = parse_toml_model(text, "again.toml")
    assert generate(again).equations.K == generate(model).equations.K
    line = parse_toml_model(PENDULUM.format(direction='"line"', gravity="", preload='preload = "m*g"'), "p.toml")
    text = model_to_toml(line)
    assert 'direction = "line"' in text and "preload = " in text
    assert generate(parse_toml_model(text, "again.toml")).equations.K == generate(line).equations.K


def test_a_given_preload_on_an_irrational_length_is_refused():
    text = PENDULUM.format(direction="[1, 0, 1]", gravity="", preload='preload = "m*g"')
    with pytest.raises(ModelError, match="square root"):
        generate(parse_toml_model(text, "p.toml"))


@pytest.mark.parametrize(("direction", "preload", "key", "mentions"), [
    ("[0, 0, 0]", "", "direction", "zero vector"),
    ('["a", 0]', "", "direction", "list of 3 values"),
    ('"line"', "", "direction", "same point"),
    ('"rz"', 'preload = "m*g"', "preload", "a rotational element has none"),
    ('"line"', 'series = true\ndamping = 1', "direction", "series (Maxwell) element acts along an axis"),
])
def test_bad_line_elements_exit_2(capsys, tmp_path, direction, preload, key, mentions):
    text = PENDULUM.format(direction=direction, gravity="", preload=preload)
    if direction == '"line"' and "series" not in preload:
        text = text.replace('offset = [0, 0, "l"]', "offset = [0, 0, 0]")
    if direction == '"rz"':
        text = text.replace('dofs = ["x", "y", "z"]', 'dofs = ["x", "y", "z", "rz"]')
    path = tmp_path / "bad.toml"
    path.write_text(text)
    line = next(i for i, row in enumerate(text.splitlines(), start=1) if row.startswith(f"{key} ="))
    output = tmp_path / "out.txt"
    err = assert_input_error(capsys, "generate", str(path), "-o", str(output), mentions=mentions)
    assert f"bad.toml:{line}:" in err
    assert not output.exists()


SUBSTRUCTURE = """
[bodies.F]
mass = "M"
dofs = ["x", "y"]

[points.F_seat]
body = "F"

[substructures.axle]
parameters = ["t"]
connectors = ["seat"]

[substructures.axle.bodies.W]
mass = "m"
dofs = ["x", "y"]
position = ["d", 0, 0]

[substructures.axle.points]
box = { body = "W" }

[substructures.axle.elements]
skew = { from = "seat", to = "box", direction = [1, "t", 0], stiffness = "k" }
tie = { from = "box", to = "seat", direction = "line", stiffness = "kt" }

[instances.one]
substructure = "axle"
prefix = "A_"
station = "s"
parameters = { t = "tt" }
connect = { seat = "F_seat" }
"""


def test_line_elements_in_a_substructure():
    """The vector's formal parameter is the instance's; "line" to a connector is found
    from the expanded model (the tie from W at d + s to F at 0: along x)."""
    eom = generate(parse_toml_model(SUBSTRUCTURE, "sub.toml")).equations
    assert eom.dofs == ("F.x", "F.y", "A_W.x", "A_W.y")
    tt, kt = sp.symbols("tt kt")
    v = sp.Matrix([1, tt, -1, -tt])  # v . (u_seat - u_box) over the four DOFs
    along_x = sp.Matrix([1, 0, -1, 0])
    expected = k * v * v.T / (1 + tt**2) + kt * along_x * along_x.T
    assert (eom.K - expected).applyfunc(sp.simplify) == sp.zeros(4, 4)


def test_a_line_to_a_connector_at_the_same_point_is_refused():
    text = SUBSTRUCTURE.replace('station = "s"', "station = 0").replace('position = ["d", 0, 0]', "position = [0, 0, 0]")
    with pytest.raises(ModelError, match="zero vector"):
        generate(parse_toml_model(text, "sub.toml"))


def test_nonlinear_elements_on_a_line_see_the_true_deflection():
    """A bump stop and a friction element along [3, 0, 4]: the time domain's deflection
    is n . du = (3 x + 4 z)/5 (not the assembly's unnormalised v . du); the matrices get
    the friction element's stuck spring k n n^T."""
    text = PENDULUM.format(direction="[3, 0, 4]", gravity="", preload="friction = 100") + (
        '\n[elements.stop]\nfrom = "bob"\nto = "top"\ndirection = [3, 0, 4]\nstiffness = "k"\ngap = 0.01\n')
    eom = generate(parse_toml_model(text, "p.toml")).equations
    unit = {"B.x": sp.Rational(3, 5), "B.z": sp.Rational(4, 5)}
    assert eom.clearances[0].gradient == unit
    assert eom.element_terms[0].gradient == unit
    n = sp.Matrix([sp.Rational(3, 5), 0, sp.Rational(4, 5)])
    assert k * n * n.T == eom.K
