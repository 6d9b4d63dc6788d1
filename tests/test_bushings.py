"""Bushings (express.io.toml_bushings, issue 31 item 3) and rotational elements about a
vector: the generated K and C against the six-component bushing built independently,
``B^T blockdiag(R^T D_t R, R^T D_r R) B`` over the relative motion of the CPs, exactly;
the body-axes bushing equals its six axis elements; rigid motion gives no force; the
round trip; bad bushings refused with their line, exit status 2, nothing written."""

from __future__ import annotations

import pytest
import sympy as sp

from cli_support import assert_input_error
from express.assembly.generator import generate
from express.io import parse_toml_model
from express.io.toml_writer import model_to_toml
from test_line_elements import TWO_BODIES, _point_rows

kx, ky, kz, krx, kry, krz, cz, crz, a, b = sp.symbols("kx ky kz krx kry krz cz crz a b")

PARAMETERS = '''kx = "1e6 N/m"
ky = "2e6 N/m"
kz = "3e6 N/m"
krx = "1e4 N*m/rad"
kry = "2e4 N*m/rad"
krz = "3e4 N*m/rad"
cz = "5e3 N*s/m"
crz = "70 N*m*s/rad"
'''

#: A frame of rational unit vectors: x = (2, 3, 6)/7, y = (3, -6, 2)/7, z = x × y = (6, 2, -3)/7.
FRAME = "x = [2, 3, 6], y = [3, -6, 2]"
BUSHING = ('bushing = {{ stiffness = ["kx", "ky", "kz", "krx", "kry", "krz"], damping = [0, 0, "cz", 0, 0, "crz"]'
           '{frame} }}')


def _model(frame: str = FRAME):
    text = TWO_BODIES.replace("[parameters]\n", "[parameters]\n" + PARAMETERS)
    start = text.index("[elements.skew]")
    text = text[:start] + '[elements.bush]\nfrom = "SA"\nto = "TB"\n' + BUSHING.format(
        frame=f", {frame}" if frame else "") + "\n"
    return parse_toml_model(text, "bushing.toml")


def _expected(axes):
    """``(K, C)`` of the bushing built by hand over the 12 DOFs (A then B, x y z rx ry rz)."""
    s_offset, t_offset = (sp.Integer(2) / 5, a, -sp.Integer(1) / 5), (-sp.Integer(1) / 10, sp.Integer(1) / 2, b)
    translation = _point_rows((0, 0, 1), s_offset, 0) - _point_rows((1, 0, 0), t_offset, 1)
    rotation = sp.zeros(3, 12)
    for i in range(3):
        rotation[i, 3 + i], rotation[i, 9 + i] = 1, -1
    rows = sp.Matrix.vstack(*[sp.Matrix(v).T / sp.sqrt(sp.Matrix(v).dot(sp.Matrix(v))) for v in axes])  # R
    relative = sp.Matrix.vstack(rows * translation, rows * rotation)  # the bushing's own six deflections
    return (relative.T * sp.diag(kx, ky, kz, krx, kry, krz) * relative,
            relative.T * sp.diag(0, 0, cz, 0, 0, crz) * relative)


@pytest.mark.parametrize("frame, axes", [
    (FRAME, [(2, 3, 6), (3, -6, 2), (6, 2, -3)]),
    ("", [(1, 0, 0), (0, 1, 0), (0, 0, 1)]),
    ('x = [0, "a", 0], y = [0, 0, 1]', [(0, 1, 0), (0, 0, 1), (1, 0, 0)]),  # a = 0.3 > 0: x along +y
])
def test_a_bushing_is_its_six_component_stiffness_in_its_own_frame(frame, axes):
    model = _model(frame)
    assert [e.id for e in model.elements] == ["bush_x", "bush_y", "bush_z", "bush_rx", "bush_ry", "bush_rz"]
    eom = generate(model).equations
    stiffness, damping = _expected(axes)
    assert (eom.K - stiffness).applyfunc(sp.simplify) == sp.zeros(12, 12)
    assert (eom.C - damping).applyfunc(sp.simplify) == sp.zeros(12, 12)


def test_a_bushing_as_a_sub_table_is_the_inline_one():
    """The form docs/model-format.md shows, ``[elements.bush.bushing]``."""
    text = TWO_BODIES.replace("[parameters]\n", "[parameters]\n" + PARAMETERS)
    text = text[:text.index("[elements.skew]")] + (
        '[elements.bush]\nfrom = "SA"\nto = "TB"\n\n[elements.bush.bushing]\n'
        'stiffness = ["kx", "ky", "kz", "krx", "kry", "krz"]\ndamping = [0, 0, "cz", 0, 0, "crz"]\n'
        'x = [2, 3, 6]\ny = [3, -6, 2]\n')
    table = generate(parse_toml_model(text, "sub.toml")).equations
    inline = generate(_model()).equations
    assert table.K == inline.K and table.C == inline.C


def test_a_common_translation_deflects_no_bushing():
    """Both bodies moved alike along x, y or z: no force (a common rotation does deflect
    a bushing whose CPs are apart, as any element between separated points)."""
    eom = generate(_model()).equations
    for axis in range(3):
        q = sp.zeros(12, 1)
        q[axis], q[6 + axis] = 1, 1
        assert (eom.K * q).applyfunc(sp.simplify) == sp.zeros(12, 1)


def test_the_body_axes_bushing_is_its_six_axis_elements():
    bushing = generate(_model("")).equations
    text = TWO_BODIES.replace("[parameters]\n", "[parameters]\n" + PARAMETERS)
    text = text[:text.index("[elements.skew]")]
    for name, k, c in (("x", "kx", 0), ("y", "ky", 0), ("z", "kz", "cz"), ("rx", "krx", 0), ("ry", "kry", 0),
                       ("rz", "krz", "crz")):
        text += f'[elements.e_{name}]\nfrom = "SA"\nto = "TB"\ndirection = "{name}"\nstiffness = "{k}"\ndamping = "{c}"\n'
    axis_elements = generate(parse_toml_model(text, "six.toml")).equations
    assert bushing.K == axis_elements.K and bushing.C == axis_elements.C


def test_a_bushing_survives_writing_and_reading():
    model = _model()
    text = model_to_toml(model)
    assert "direction = { about = [42, 14, -21] }" in text and "direction = [2, 3, 6]" in text
    again = generate(parse_toml_model(text, "again.toml")).equations
    eom = generate(model).equations
    assert again.K == eom.K and again.C == eom.C


@pytest.mark.parametrize("frame, key, mentions", [
    ("x = [1, 1, 0], y = [0, 1, 0]", "bushing", "are not orthogonal"),
    ("x = [1, 0, 0]", "bushing", "needs both its x and y axes"),
    ("x = [0, 0, 0], y = [0, 1, 0]", "bushing", "x axis is the zero vector"),
    ("x = [1, 0], y = [0, 1, 0]", "bushing", "list of 3 values"),
    ('x = [1, 0, 0], y = [0, 1, 0], turn = 3', "bushing", 'unknown key "turn"'),
])
def test_bad_bushings_exit_2(capsys, tmp_path, frame, key, mentions):
    text = TWO_BODIES.replace("[parameters]\n", "[parameters]\n" + PARAMETERS)
    text = text[:text.index("[elements.skew]")] + '[elements.bush]\nfrom = "SA"\nto = "TB"\n' + BUSHING.format(
        frame=f", {frame}") + "\n"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    line = next(i for i, row in enumerate(text.splitlines(), start=1) if row.startswith(f"{key} ="))
    output = tmp_path / "out.txt"
    err = assert_input_error(capsys, "generate", str(path), "-o", str(output), mentions=mentions)
    assert f"bad.toml:{line}:" in err
    assert not output.exists()


@pytest.mark.parametrize("extra, mentions", [
    ('direction = "x"', 'an element with a bushing has no "direction"'),
    ('stiffness = "kx"', 'an element with a bushing has no "stiffness"'),
])
def test_a_bushing_beside_an_elements_own_values_is_refused(capsys, tmp_path, extra, mentions):
    text = TWO_BODIES.replace("[parameters]\n", "[parameters]\n" + PARAMETERS)
    text = text[:text.index("[elements.skew]")] + f'[elements.bush]\nfrom = "SA"\nto = "TB"\n{extra}\n' + \
        BUSHING.format(frame="") + "\n"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert_input_error(capsys, "generate", str(path), "-o", str(tmp_path / "o.txt"), mentions=mentions)


def test_a_rotational_element_about_a_vector_needs_the_rotations_as_dofs(capsys, tmp_path):
    text = TWO_BODIES.replace('dofs = ["x", "y", "z", "rx", "ry", "rz"]\nposition = [1, 0, 0]',
                              'dofs = ["x", "y", "z", "rz"]\nposition = [1, 0, 0]')
    text = text.replace('direction = {direction}', 'direction = { about = [0, 3, 4] }')
    path = tmp_path / "bad.toml"
    path.write_text(text)
    err = assert_input_error(capsys, "generate", str(path), "-o", str(tmp_path / "o.txt"),
                             mentions="rotational element about ry")
    assert "which has no rz" not in err and "no rx" not in err
